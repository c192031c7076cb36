// core/pgs.h — the bounded approximation of an island that cannot be solved exactly within its share of a step's
// budget: a fixed number of projected Gauss-Seidel sweeps in body space over the island's contact rows, warm-started
// from the previous step's impulses, written once for 2D and 3D (D = Dim2 or Dim3).
//
// Owns: PgsWarm (one contact's impulses carried from the last step), PgsResult and solvePgs(). The rows are those of
// the island's LCP (core/contact_resolver.h): per contact node one normal row whose target is the LCP's b_i
// (eq. (19): v_rel^+ + e v_rel^- - bias >= 0, complementary to the impulse) and D::kDim - 1 orthogonal tangent rows
// whose impulse is projected onto the Coulomb disc |f_t| <= mu f_n (in 2D exactly the LCP's pyramid; in 3D the
// round cone the pyramid approximates).
// Invariants: contacts are visited in the order given, every sweep the same way (friction rows, then the normal
// row, per contact), with no data-dependent branching beyond the projections, so the answer is a pure function of
// the inputs; the cost is exactly setup + sweeps x rows, whatever the data.
#pragma once

#include "contact_resolver.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace unison {

/// One contact's impulses from the previous step (world frame), the approximation's starting point.
template <class D>
struct PgsWarm {
    double normal = 0.0;                              ///< N s
    typename D::Vec tangent = D::zeroVec();           ///< N s
};

/// The approximation's answer.
template <class D>
struct PgsResult {
    std::vector<double> normal;                  ///< (contacts) normal impulses f_n (N s)
    std::vector<typename D::Vec> tangent;        ///< (contacts) friction impulses, world frame (N s)
    /// Largest complementarity violation after the last sweep: per contact max(|min(f_n, w_n)|, and where the
    /// friction impulse is inside the disc, min(mu f_n - |f_t|, |v_t|)); m/s or N s, as the LCP's residual.
    double residual = 0.0;
};

namespace pgs_detail {

/// One row: a direction at a contact, acting +dir on body a and -dir on body b.
template <class D>
struct Row {
    typename D::Vec dir = D::zeroVec();
    typename D::Ang angA = D::zeroAng(), angB = D::zeroAng();        // r_a x dir, r_b x dir
    typename D::Ang invIangA = D::zeroAng(), invIangB = D::zeroAng();  // I_a^-1 (r_a x dir), I_b^-1 (r_b x dir)
    double invK = 0.0;  // 1 / (effective mass's inverse), 0 when no body can move along the row
};

template <class D>
Row<D> makeRow(const std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c, const typename D::Vec& dir) {
    const ResolverBody<D>& A = bodies[std::size_t(c.a)];
    const ResolverBody<D>& B = bodies[std::size_t(c.b)];
    Row<D> r;
    r.dir = dir;
    r.angA = D::cross(D::sub(c.point, A.position), dir);
    r.angB = D::cross(D::sub(c.point, B.position), dir);
    r.invIangA = D::applyInvInertia(A.invInertia, r.angA);
    r.invIangB = D::applyInvInertia(B.invInertia, r.angB);
    const double k = A.invMass + B.invMass + D::angDot(r.angA, r.invIangA) + D::angDot(r.angB, r.invIangB);
    r.invK = k > 0.0 ? 1.0 / k : 0.0;
    return r;
}

/// Velocity of body a relative to body b along the row.
template <class D>
double rowVelocity(const std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c, const Row<D>& r) {
    const ResolverBody<D>& A = bodies[std::size_t(c.a)];
    const ResolverBody<D>& B = bodies[std::size_t(c.b)];
    return (D::dot(r.dir, A.velocity) + D::angDot(r.angA, A.angularVelocity)) -
           (D::dot(r.dir, B.velocity) + D::angDot(r.angB, B.angularVelocity));
}

/// Applies impulse p along the row (+ to a, - to b).
template <class D>
void applyRow(std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c, const Row<D>& r, double p) {
    ResolverBody<D>& A = bodies[std::size_t(c.a)];
    ResolverBody<D>& B = bodies[std::size_t(c.b)];
    A.velocity = D::add(A.velocity, D::scale(A.invMass * p, r.dir));
    A.angularVelocity = D::angAdd(A.angularVelocity, D::angScale(p, r.invIangA));
    B.velocity = D::sub(B.velocity, D::scale(B.invMass * p, r.dir));
    B.angularVelocity = D::angAdd(B.angularVelocity, D::angScale(-p, r.invIangB));
}

/// The D::kDim - 1 unit tangents of a normal: in 2D perp(n), in 3D the pyramid's first direction and n x it.
template <class D>
int tangentBasis(const typename D::Vec& n, typename D::Vec* out) {
    out[0] = D::tangentDirection(n, 0, D::frictionDirectionCount(4));
    if constexpr (D::kDim == 3) {
        out[1] = D::cross(n, out[0]);
        return 2;
    } else {
        return 1;
    }
}

}  // namespace pgs_detail

/// Tangent rows per contact of the approximation (D::kDim - 1).
template <class D>
constexpr int pgsTangentRows() {
    return D::kDim - 1;
}

/// Runs `sweeps` projected Gauss-Seidel sweeps on the contact rows of `nodes` (the island's LCP rows: bias and
/// restitution as the resolver reads them, e applied where the approach is faster than restitutionThreshold),
/// starting from `warm` (one entry per node, or empty for a cold start) and applies the impulses to `ioBodies`.
template <class D>
PgsResult<D> solvePgs(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& nodes,
                      const std::vector<PgsWarm<D>>& warm, int sweeps, double restitutionThreshold) {
    using pgs_detail::Row;
    using Vec = typename D::Vec;
    constexpr int T = pgsTangentRows<D>();
    const std::size_t nc = nodes.size();
    std::vector<Row<D>> rows(nc * std::size_t(T + 1));  // per contact: the normal row, then its tangent rows
    std::vector<double> target(nc), fn(nc, 0.0), ft(nc * std::size_t(T), 0.0);
    for (std::size_t i = 0; i < nc; ++i) {
        const ContactNode<D>& c = nodes[i];
        Row<D>* r = &rows[i * std::size_t(T + 1)];
        r[0] = pgs_detail::makeRow(ioBodies, c, c.normal);
        Vec t[2];
        pgs_detail::tangentBasis<D>(c.normal, t);
        for (int m = 0; m < T; ++m) r[1 + m] = pgs_detail::makeRow(ioBodies, c, t[m]);
        // eq. (19): w = v_rel^+ + e v_rel^- - bias, with v_rel^- the velocity before any impulse of this step.
        const double v0 = pgs_detail::rowVelocity(ioBodies, c, r[0]);
        target[i] = (v0 < -restitutionThreshold ? c.restitution * v0 : 0.0) - c.bias;
    }
    // Warm start: last step's impulses, the friction part projected onto this step's tangents and disc.
    for (std::size_t i = 0; i < nc && !warm.empty(); ++i) {
        const ContactNode<D>& c = nodes[i];
        const Row<D>* r = &rows[i * std::size_t(T + 1)];
        fn[i] = std::max(0.0, warm[i].normal);
        pgs_detail::applyRow(ioBodies, c, r[0], fn[i]);
        double len2 = 0.0;
        for (int m = 0; m < T; ++m) {
            ft[i * T + std::size_t(m)] = D::dot(warm[i].tangent, r[1 + m].dir);
            len2 += ft[i * T + std::size_t(m)] * ft[i * T + std::size_t(m)];
        }
        const double limit = c.friction * fn[i];
        const double scale = len2 > limit * limit ? limit / std::sqrt(len2) : 1.0;
        for (int m = 0; m < T; ++m) {
            ft[i * T + std::size_t(m)] *= scale;
            pgs_detail::applyRow(ioBodies, c, r[1 + m], ft[i * T + std::size_t(m)]);
        }
    }
    for (int s = 0; s < sweeps; ++s) {
        for (std::size_t i = 0; i < nc; ++i) {
            const ContactNode<D>& c = nodes[i];
            const Row<D>* r = &rows[i * std::size_t(T + 1)];
            double* f = &ft[i * std::size_t(T)];
            // Friction first (against the normal impulse of the last sweep), projected onto the disc.
            double next[2] = {0.0, 0.0}, len2 = 0.0;
            for (int m = 0; m < T; ++m) {
                next[m] = f[m] - pgs_detail::rowVelocity(ioBodies, c, r[1 + m]) * r[1 + m].invK;
                len2 += next[m] * next[m];
            }
            const double limit = c.friction * fn[i];
            const double scale = len2 > limit * limit ? (len2 > 0.0 ? limit / std::sqrt(len2) : 0.0) : 1.0;
            for (int m = 0; m < T; ++m) {
                const double v = next[m] * scale;
                pgs_detail::applyRow(ioBodies, c, r[1 + m], v - f[m]);
                f[m] = v;
            }
            const double vn = pgs_detail::rowVelocity(ioBodies, c, r[0]);
            const double n = std::max(0.0, fn[i] - (vn + target[i]) * r[0].invK);
            pgs_detail::applyRow(ioBodies, c, r[0], n - fn[i]);
            fn[i] = n;
        }
    }
    PgsResult<D> out;
    out.normal = fn;
    out.tangent.assign(nc, D::zeroVec());
    for (std::size_t i = 0; i < nc; ++i) {
        const ContactNode<D>& c = nodes[i];
        const Row<D>* r = &rows[i * std::size_t(T + 1)];
        const double w = pgs_detail::rowVelocity(ioBodies, c, r[0]) + target[i];
        double res = std::fabs(std::min(fn[i], w));
        double len2 = 0.0, slip2 = 0.0;
        for (int m = 0; m < T; ++m) {
            const double f = ft[i * T + std::size_t(m)];
            out.tangent[i] = D::add(out.tangent[i], D::scale(f, r[1 + m].dir));
            len2 += f * f;
            const double v = pgs_detail::rowVelocity(ioBodies, c, r[1 + m]);
            slip2 += v * v;
        }
        const double inside = c.friction * fn[i] - std::sqrt(len2);
        if (inside > 0.0) res = std::max(res, std::min(inside, std::sqrt(slip2)));
        out.residual = std::max(out.residual, res);
    }
    return out;
}

}  // namespace unison
