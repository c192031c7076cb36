// resolver2d/resolver2d.cpp — the 2D instantiation of the paper's resolver (core/contact_resolver_impl.h).
#include "contact_resolver_impl.h"
#include "dim2.h"

namespace unison {
UNISON_INSTANTIATE_RESOLVER(Dim2)
}  // namespace unison
