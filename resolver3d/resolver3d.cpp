// resolver3d/resolver3d.cpp — the 3D instantiation of the paper's resolver and the 3D friction directions.
#include "contact_resolver_impl.h"
#include "det_math.h"
#include "dim3.h"

#include <algorithm>
#include <cmath>

namespace unison {

// A deterministic tangent basis (t1, t2) of n, then k/2 directions evenly spread over a half turn and their
// negatives: index m < k/2 is cos(theta) t1 + sin(theta) t2 with theta = pi m / (k/2); index m + k/2 is its negative.
Dim3::Vec Dim3::tangentDirection(const Vec& n, int index, int k) {
    Vec3 t1;
    if (std::fabs(n.x()) >= 0.57735026918962576) {
        t1 = Vec3(n.y(), -n.x(), 0.0);
    } else {
        t1 = Vec3(0.0, n.z(), -n.y());
    }
    t1 = scale(1.0 / std::sqrt(dot(t1, t1)), t1);
    const Vec3 t2 = cross(n, t1);
    const int half = k / 2;
    const int m = index % half;
    Vec3 dir;
    if (m == 0) {
        dir = t1;
    } else if (2 * m == half) {
        dir = t2;
    } else {
        double s = 0.0;
        double c = 0.0;
        dmath::sincos(dmath::kPi * double(m) / double(half), &s, &c);
        dir = add(scale(c, t1), scale(s, t2));
    }
    return index < half ? dir : scale(-1.0, dir);
}

// I^-1 = L L^T for the symmetric positive semi-definite world-frame inverse inertia (+ - * / sqrt only). A pivot
// that is not positive (a rotation locked about some axis, or rounding at the level of the other entries) gives a
// zero column: for a positive semi-definite matrix the rest of that column is zero too.
Dim3::InvInertia Dim3::couplingFactor(const InvInertia& a) {
    Mat3 l = Mat3::Zero();
    const double tiny = 1e-14 * std::max(a(0, 0), std::max(a(1, 1), a(2, 2)));
    for (int c = 0; c < 3; ++c) {
        double d = a(c, c);
        for (int k = 0; k < c; ++k) d -= l(c, k) * l(c, k);
        if (!(d > tiny)) continue;
        const double root = std::sqrt(d);
        l(c, c) = root;
        for (int r = c + 1; r < 3; ++r) {
            double v = a(r, c);
            for (int k = 0; k < c; ++k) v -= l(r, k) * l(c, k);
            l(r, c) = v / root;
        }
    }
    return l;
}

UNISON_INSTANTIATE_RESOLVER(Dim3)

}  // namespace unison
