// resolver3d/resolver3d.h — the paper's resolver for bodies in space: Dim3 (Eigen) plus the core templates.
// Bodies carry a world-frame 3x3 inverse inertia tensor and an angular velocity vector.
#pragma once

#include "contact_resolver.h"
#include "dim3.h"

namespace unison {
using Body3 = ResolverBody<Dim3>;
using Contact3 = ContactNode<Dim3>;
}  // namespace unison
