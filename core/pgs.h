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

/// A body's velocities during the sweeps, packed (the island's ResolverBody array holds more than a sweep reads).
template <class D>
struct Motion {
    typename D::Vec v;
    typename D::Ang w;
};

/// One contact's rows, prepared once: row 0 the normal, rows 1..T the tangents. A row acts +dir on body a and -dir
/// on body b; invIangA/invIangB are the angular velocity change per unit impulse. (2D: 168 bytes, read every
/// sweep, so nothing is stored that a multiplication can give.)
template <class D, int T>
struct Contact {  // every field is written by solvePgs' set-up before it is read (no initialisers: reused buffers)
    int a, b;
    double mu;      // Coulomb coefficient
    double target;  // normal row: w = v_rel + target (eq. (19): e v_rel^- - bias)
    double invMassA, invMassB;
    typename D::Vec dir[T + 1];
    typename D::Ang angA[T + 1], angB[T + 1], invIangA[T + 1], invIangB[T + 1];
    double invK[T + 1];   // 1 / the row's effective inverse mass (0 when neither body can move along it)
    double k0[T + 1];     // k0[m]: change of the normal row's velocity per unit impulse on tangent row m
    double f[T + 1];      // accumulated impulses
};

/// Velocity of body a relative to body b along row r of contact c.
template <class D, int T>
double rowVelocity(const Contact<D, T>& c, int r, const Motion<D>& A, const Motion<D>& B) {
    return D::dot(c.dir[r], D::sub(A.v, B.v)) + (D::angDot(c.angA[r], A.w) - D::angDot(c.angB[r], B.w));
}

/// Applies impulse p along row r (+ to a, - to b).
template <class D, int T>
void applyRow(const Contact<D, T>& c, int r, double p, Motion<D>& A, Motion<D>& B) {
    A.v = D::add(A.v, D::scale(p * c.invMassA, c.dir[r]));
    A.w = D::angAdd(A.w, D::angScale(p, c.invIangA[r]));
    B.v = D::sub(B.v, D::scale(p * c.invMassB, c.dir[r]));
    B.w = D::angAdd(B.w, D::angScale(-p, c.invIangB[r]));
}

/// Scales the tangent impulses f[1..T] of c onto the disc |f_t| <= limit.
template <class D, int T>
void project(double* f, double limit) {
    if constexpr (T == 1) {
        f[1] = std::min(limit, std::max(-limit, f[1]));
    } else {
        double len2 = 0.0;
        for (int m = 1; m <= T; ++m) len2 += f[m] * f[m];
        if (len2 > limit * limit) {
            const double scale = limit / std::sqrt(len2);
            for (int m = 1; m <= T; ++m) f[m] *= scale;
        }
    }
}

/// The D::kDim - 1 unit tangents of a normal: in 2D perp(n), in 3D the pyramid's first direction and n x it.
template <class D>
void tangentBasis(const typename D::Vec& n, typename D::Vec* out) {
    out[0] = D::tangentDirection(n, 0, D::frictionDirectionCount(4));
    if constexpr (D::kDim == 3) out[1] = D::cross(n, out[0]);
}

}  // namespace pgs_detail

/// Tangent rows per contact of the approximation (D::kDim - 1).
template <class D>
constexpr int pgsTangentRows() {
    return D::kDim - 1;
}

/// Buffers of solvePgs kept between calls (one per thread): they only grow, so a step that runs the approximation
/// every step does not allocate or clear them.
template <class D>
struct PgsScratch {
    std::vector<pgs_detail::Motion<D>> motion;
    std::vector<pgs_detail::Contact<D, pgsTangentRows<D>()>> rows;
};

/// Runs `sweeps` projected Gauss-Seidel sweeps on the contact rows of `nodes` (the island's LCP rows: bias and
/// restitution as the resolver reads them, e applied where the approach is faster than restitutionThreshold),
/// starting from `warm` (one entry per node, or empty for a cold start) and applies the impulses to `ioBodies`.
/// `scratch` holds the working arrays (any content; reused).
template <class D>
PgsResult<D> solvePgs(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& nodes,
                      const std::vector<PgsWarm<D>>& warm, int sweeps, double restitutionThreshold,
                      PgsScratch<D>& scratch) {
    constexpr int T = pgsTangentRows<D>();
    using Contact = pgs_detail::Contact<D, T>;
    using Motion = pgs_detail::Motion<D>;
    const std::size_t nc = nodes.size();
    if (scratch.motion.size() < ioBodies.size()) scratch.motion.resize(ioBodies.size());
    if (scratch.rows.size() < nc) scratch.rows.resize(nc);
    Motion* motion = scratch.motion.data();
    Contact* rows = scratch.rows.data();
    for (std::size_t k = 0; k < ioBodies.size(); ++k) motion[k] = {ioBodies[k].velocity, ioBodies[k].angularVelocity};
    for (std::size_t i = 0; i < nc; ++i) {
        const ContactNode<D>& node = nodes[i];
        const ResolverBody<D>& A = ioBodies[std::size_t(node.a)];
        const ResolverBody<D>& B = ioBodies[std::size_t(node.b)];
        Contact& c = rows[i];
        c.a = node.a;
        c.b = node.b;
        c.mu = node.friction;
        c.invMassA = A.invMass;
        c.invMassB = B.invMass;
        typename D::Vec t[2];
        pgs_detail::tangentBasis<D>(node.normal, t);
        const typename D::Vec rA = D::sub(node.point, A.position), rB = D::sub(node.point, B.position);
        for (int r = 0; r <= T; ++r) {
            const typename D::Vec dir = r == 0 ? node.normal : t[r - 1];
            c.dir[r] = dir;
            c.angA[r] = D::cross(rA, dir);
            c.angB[r] = D::cross(rB, dir);
            c.invIangA[r] = D::applyInvInertia(A.invInertia, c.angA[r]);
            c.invIangB[r] = D::applyInvInertia(B.invInertia, c.angB[r]);
            const double k = A.invMass + B.invMass + D::angDot(c.angA[r], c.invIangA[r]) + D::angDot(c.angB[r], c.invIangB[r]);
            c.invK[r] = k > 0.0 ? 1.0 / k : 0.0;
            c.f[r] = 0.0;
        }
        for (int m = 1; m <= T; ++m)
            c.k0[m] = (A.invMass + B.invMass) * D::dot(c.dir[0], c.dir[m]) + D::angDot(c.angA[0], c.invIangA[m]) +
                      D::angDot(c.angB[0], c.invIangB[m]);
        // eq. (19): w = v_rel^+ + e v_rel^- - bias, with v_rel^- the velocity before any impulse of this step.
        const double v0 = pgs_detail::rowVelocity(c, 0, motion[std::size_t(c.a)], motion[std::size_t(c.b)]);
        c.target = (v0 < -restitutionThreshold ? node.restitution * v0 : 0.0) - node.bias;
    }
    // Warm start: last step's impulses, the friction part projected onto this step's tangents and disc.
    for (std::size_t i = 0; i < nc && !warm.empty(); ++i) {
        Contact& c = rows[i];
        c.f[0] = std::max(0.0, warm[i].normal);
        for (int m = 1; m <= T; ++m) c.f[m] = D::dot(warm[i].tangent, c.dir[m]);
        pgs_detail::project<D, T>(c.f, c.mu * c.f[0]);
        for (int r = 0; r <= T; ++r) pgs_detail::applyRow(c, r, c.f[r], motion[std::size_t(c.a)], motion[std::size_t(c.b)]);
    }
    for (int s = 0; s < sweeps; ++s) {
        for (std::size_t i = 0; i < nc; ++i) {
            Contact& c = rows[i];
            Motion& A = motion[std::size_t(c.a)];
            Motion& B = motion[std::size_t(c.b)];
            // The contact's relative motion once: the friction rows (against the normal impulse of the last sweep,
            // projected onto the disc), then the normal row with its velocity moved by what friction changed, then
            // both bodies once with the sum.
            const typename D::Vec dv = D::sub(A.v, B.v);
            double next[T + 1], delta[T + 1];
            for (int m = 1; m <= T; ++m) {
                const double v = D::dot(c.dir[m], dv) + (D::angDot(c.angA[m], A.w) - D::angDot(c.angB[m], B.w));
                next[m] = c.f[m] - v * c.invK[m];
            }
            pgs_detail::project<D, T>(next, c.mu * c.f[0]);
            double vn = D::dot(c.dir[0], dv) + (D::angDot(c.angA[0], A.w) - D::angDot(c.angB[0], B.w));
            for (int m = 1; m <= T; ++m) {
                delta[m] = next[m] - c.f[m];
                c.f[m] = next[m];
                vn += c.k0[m] * delta[m];
            }
            const double n = std::max(0.0, c.f[0] - (vn + c.target) * c.invK[0]);
            delta[0] = n - c.f[0];
            c.f[0] = n;
            typename D::Vec p = D::scale(delta[0], c.dir[0]);
            typename D::Ang wa = D::angScale(delta[0], c.invIangA[0]), wb = D::angScale(delta[0], c.invIangB[0]);
            for (int m = 1; m <= T; ++m) {
                p = D::add(p, D::scale(delta[m], c.dir[m]));
                wa = D::angAdd(wa, D::angScale(delta[m], c.invIangA[m]));
                wb = D::angAdd(wb, D::angScale(delta[m], c.invIangB[m]));
            }
            A.v = D::add(A.v, D::scale(c.invMassA, p));
            A.w = D::angAdd(A.w, wa);
            B.v = D::sub(B.v, D::scale(c.invMassB, p));
            B.w = D::angAdd(B.w, D::angScale(-1.0, wb));
        }
    }
    PgsResult<D> out;
    out.normal.resize(nc);
    out.tangent.assign(nc, D::zeroVec());
    for (std::size_t i = 0; i < nc; ++i) {
        const Contact& c = rows[i];
        const Motion& A = motion[std::size_t(c.a)];
        const Motion& B = motion[std::size_t(c.b)];
        out.normal[i] = c.f[0];
        double res = std::fabs(std::min(c.f[0], pgs_detail::rowVelocity(c, 0, A, B) + c.target));
        double len2 = 0.0, slip2 = 0.0;
        for (int m = 1; m <= T; ++m) {
            out.tangent[i] = D::add(out.tangent[i], D::scale(c.f[m], c.dir[m]));
            len2 += c.f[m] * c.f[m];
            const double v = pgs_detail::rowVelocity(c, m, A, B);
            slip2 += v * v;
        }
        const double inside = c.mu * c.f[0] - std::sqrt(len2);
        if (inside > 0.0) res = std::max(res, std::min(inside, std::sqrt(slip2)));
        out.residual = std::max(out.residual, res);
    }
    for (std::size_t k = 0; k < ioBodies.size(); ++k) {
        ioBodies[k].velocity = motion[k].v;
        ioBodies[k].angularVelocity = motion[k].w;
    }
    return out;
}

/// solvePgs with buffers of its own.
template <class D>
PgsResult<D> solvePgs(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& nodes,
                      const std::vector<PgsWarm<D>>& warm, int sweeps, double restitutionThreshold) {
    PgsScratch<D> scratch;
    return solvePgs(ioBodies, nodes, warm, sweeps, restitutionThreshold, scratch);
}

}  // namespace unison
