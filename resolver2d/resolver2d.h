// resolver2d/resolver2d.h — the paper's resolver for planar bodies: Dim2 plus the core templates.
// Bodies carry a scalar inverse inertia and a scalar angular velocity (about z).
#pragma once

#include "contact_resolver.h"
#include "dim2.h"

namespace unison {
using Body2 = ResolverBody<Dim2>;
using Contact2 = ContactNode<Dim2>;
}  // namespace unison
