// core/contact_resolver_impl.h — template bodies of core/contact_resolver.h. Included only by the files that
// instantiate the resolver for a dimension (resolver2d/resolver2d.cpp, resolver3d/resolver3d.cpp).
//
// The one idea here: every LCP row (a normal row of the paper, or a friction tangent row) is a direction l at a
// point, acting with +l on body A and -l on body B. Eq. (20) is then the same sum for every pair of rows:
//     A_ij = sum over bodies k touched by both rows of  s_ik s_jk ( l_i.l_j / M_k + (r_ki x l_i) . I_k^-1 (r_kj x l_j) )
// with s = +1 for body A and -1 for body B. For two rows on the same pair (A, B) this is exactly the paper's
// n_i . ((n_j/M_A + lambda_A r*_Aj n_j) - (-n_j/M_B + lambda_B r*_Bj (-n_j))); where the bodies of row j differ
// from those of row i, only the shared body contributes ("the usual care" of DESIGN.md).
#pragma once

#include "contact_resolver.h"

#include <cmath>
#include <string>

namespace unison {
namespace detail {

template <class D>
struct JacobianRow {
    int body[2] = {-1, -1};       // A, B
    typename D::Vec lin[2];        // +l, -l
    typename D::Ang ang[2];        // r_A x l, r_B x (-l)
};

template <class D>
JacobianRow<D> makeRow(const std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c,
                       const typename D::Vec& dir) {
    JacobianRow<D> row;
    row.body[0] = c.a;
    row.body[1] = c.b;
    const typename D::Vec rA = D::sub(c.point, bodies[std::size_t(c.a)].position);
    const typename D::Vec rB = D::sub(c.point, bodies[std::size_t(c.b)].position);
    const typename D::Vec neg = D::scale(-1.0, dir);
    row.lin[0] = dir;
    row.lin[1] = neg;
    row.ang[0] = D::cross(rA, dir);  // r*_A n, eq. (17)
    row.ang[1] = D::cross(rB, neg);  // r*_B (-n)
    return row;
}

template <class D>
bool isImmovable(const ResolverBody<D>& body) {
    return body.invMass == 0.0 && D::invInertiaZero(body.invInertia);
}

// Adds J M^-1 J^T of `rows` into the top-left block of `lcp` (rows.size() x rows.size()), eq. (20).
// Bodies are visited in index order and, per body, rows in index order, so every A_ij is summed in a fixed order.
template <class D>
void addCoupling(const std::vector<ResolverBody<D>>& bodies, const std::vector<JacobianRow<D>>& rows, LcpTriplets& lcp) {
    // Rows touching each body: (row, slot) pairs, built in row order.
    std::vector<int> start(bodies.size() + 1, 0);
    for (const auto& r : rows) {
        ++start[std::size_t(r.body[0]) + 1];
        ++start[std::size_t(r.body[1]) + 1];
    }
    for (std::size_t k = 0; k < bodies.size(); ++k) start[k + 1] += start[k];
    std::vector<int> fill(start.begin(), start.end() - 1);
    std::vector<int> entryRow(std::size_t(start.back()));
    std::vector<int> entrySlot(std::size_t(start.back()));
    for (int i = 0; i < int(rows.size()); ++i) {
        for (int s = 0; s < 2; ++s) {
            const int k = rows[std::size_t(i)].body[s];
            entryRow[std::size_t(fill[std::size_t(k)])] = i;
            entrySlot[std::size_t(fill[std::size_t(k)])] = s;
            ++fill[std::size_t(k)];
        }
    }
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        const ResolverBody<D>& body = bodies[k];
        if (isImmovable(body)) continue;  // infinite mass: contributes nothing (the paper's dummy body)
        for (int p = start[k]; p < start[k + 1]; ++p) {
            const JacobianRow<D>& ri = rows[std::size_t(entryRow[std::size_t(p)])];
            const int si = entrySlot[std::size_t(p)];
            // lambda_k = r*_ki^T I_k^-1, applied to the other row's angular part below.
            const typename D::Ang invIri = D::applyInvInertia(body.invInertia, ri.ang[si]);
            for (int q = start[k]; q < start[k + 1]; ++q) {
                const JacobianRow<D>& rj = rows[std::size_t(entryRow[std::size_t(q)])];
                const int sj = entrySlot[std::size_t(q)];
                const double term = body.invMass * D::dot(ri.lin[si], rj.lin[sj]) + D::angDot(invIri, rj.ang[sj]);
                lcp.add(entryRow[std::size_t(p)], entryRow[std::size_t(q)], term);
            }
        }
    }
}

// Velocity of the contact point along `dir`, body A minus body B, eq. (2) and (4).
template <class D>
double relativeVelocityAlong(const std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c,
                             const typename D::Vec& dir) {
    const ResolverBody<D>& A = bodies[std::size_t(c.a)];
    const ResolverBody<D>& B = bodies[std::size_t(c.b)];
    const typename D::Vec pA = D::add(A.velocity, D::angularVelocityAt(A.angularVelocity, D::sub(c.point, A.position)));
    const typename D::Vec pB = D::add(B.velocity, D::angularVelocityAt(B.angularVelocity, D::sub(c.point, B.position)));
    return D::dot(dir, D::sub(pA, pB));
}

// b_i per eq. (19): (1 + e) v_rel^- for contacts approaching faster than the threshold, v_rel^- otherwise
// (e = 0 for slow, resting and separating contacts), minus the node's separation bias.
template <class D>
double normalRhs(const std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c, double threshold) {
    const double vrel = relativeVelocityAlong(bodies, c, c.normal);
    const double e = vrel < -threshold ? c.restitution : 0.0;
    return (1.0 + e) * vrel - c.bias;
}

// Status, counts, basis and message of a Lemke solve, moved into the resolver's report.
inline void takeSolveReport(LcpResult& r, Resolution& out) {
    out.status = r.status;
    out.pivots = r.pivots;
    out.work = r.work;
    out.residual = r.residual;
    out.basis = std::move(r.basis);
    out.message = std::move(r.message);
}

template <class D>
std::string fail(const char* what, int index, const char* why) {
    return std::string(what) + " " + std::to_string(index) + ": " + why;
}

}  // namespace detail

template <class D>
double relativeNormalVelocity(const std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c) {
    return detail::relativeVelocityAlong(bodies, c, c.normal);
}

template <class D>
std::string validate(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts) {
    for (int i = 0; i < int(bodies.size()); ++i) {
        const ResolverBody<D>& b = bodies[std::size_t(i)];
        if (!std::isfinite(b.invMass) || b.invMass < 0.0)
            return detail::fail<D>("body", i, "inverse mass must be finite and >= 0 (mass > 0, or static)");
        if (!D::invInertiaValid(b.invInertia))
            return detail::fail<D>("body", i, "inverse inertia must be finite with a non-negative diagonal");
        if (!D::finite(b.position) || !D::finite(b.velocity) || !D::angFinite(b.angularVelocity))
            return detail::fail<D>("body", i, "position and velocities must be finite");
    }
    for (int i = 0; i < int(contacts.size()); ++i) {
        const ContactNode<D>& c = contacts[std::size_t(i)];
        if (c.a < 0 || c.b < 0 || c.a >= int(bodies.size()) || c.b >= int(bodies.size()))
            return detail::fail<D>("contact", i, "body index out of range");
        if (c.a == c.b) return detail::fail<D>("contact", i, "bodies a and b must differ");
        if (!D::finite(c.point) || !D::finite(c.normal)) return detail::fail<D>("contact", i, "point and normal must be finite");
        const double len2 = D::dot(c.normal, c.normal);
        if (!(std::fabs(len2 - 1.0) <= 1e-6)) return detail::fail<D>("contact", i, "normal must have unit length");
        if (!(c.restitution >= 0.0 && c.restitution <= 1.0))
            return detail::fail<D>("contact", i, "restitution must be in [0, 1]");
        if (!(c.friction >= 0.0) || !std::isfinite(c.friction))
            return detail::fail<D>("contact", i, "friction must be finite and >= 0");
        if (!std::isfinite(c.bias)) return detail::fail<D>("contact", i, "bias must be finite");
    }
    return {};
}

namespace detail {

template <class D>
LcpTriplets buildCollisionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                              const ResolverOptions& options) {
    const int n = int(contacts.size());
    LcpTriplets lcp(n);
    std::vector<JacobianRow<D>> rows;
    rows.reserve(std::size_t(n));
    for (const auto& c : contacts) rows.push_back(makeRow(bodies, c, c.normal));
    addCoupling(bodies, rows, lcp);  // eq. (20)
    for (int i = 0; i < n; ++i)
        lcp.b[std::size_t(i)] = normalRhs(bodies, contacts[std::size_t(i)], options.restitutionThreshold);  // eq. (19)
    return lcp;
}

}  // namespace detail

template <class D>
Lcp assembleCollisionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                         const ResolverOptions& options) {
    return detail::buildCollisionLcp(bodies, contacts, options).toDense();
}

template <class D>
SparseLcp assembleCollisionLcpSparse(const std::vector<ResolverBody<D>>& bodies,
                                     const std::vector<ContactNode<D>>& contacts, const ResolverOptions& options) {
    return detail::buildCollisionLcp(bodies, contacts, options).toSparse();
}

template <class D>
std::vector<typename D::Vec> frictionDirections(const ContactNode<D>& c, int k) {
    const int count = D::frictionDirectionCount(k);
    std::vector<typename D::Vec> dirs;
    dirs.reserve(std::size_t(count));
    for (int m = 0; m < count; ++m) dirs.push_back(D::tangentDirection(c.normal, m, count));
    return dirs;
}

namespace detail {

template <class D>
LcpTriplets buildFrictionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                             const ResolverOptions& options, FrictionLayout* outLayout) {
    FrictionLayout layout;
    layout.contacts = int(contacts.size());
    layout.directions = D::frictionDirectionCount(options.frictionDirections);
    const int nc = layout.contacts;
    const int k = layout.directions;
    LcpTriplets lcp(layout.size());
    // Normal rows first, then the tangent rows of contact 0, contact 1, ...: J = [N ; D].
    std::vector<JacobianRow<D>> rows;
    rows.reserve(std::size_t(nc * (k + 1)));
    for (const auto& c : contacts) rows.push_back(makeRow(bodies, c, c.normal));
    for (const auto& c : contacts) {
        for (const auto& t : frictionDirections(c, k)) rows.push_back(makeRow(bodies, c, t));
    }
    addCoupling(bodies, rows, lcp);
    for (int c = 0; c < nc; ++c) {
        const ContactNode<D>& node = contacts[std::size_t(c)];
        lcp.b[std::size_t(c)] = normalRhs(bodies, node, options.restitutionThreshold);
        const auto dirs = frictionDirections(node, k);
        const int lambda = layout.slackOffset() + c;
        for (int m = 0; m < k; ++m) {
            const int t = layout.tangentOffset() + c * k + m;
            const double vt = relativeVelocityAlong(bodies, node, dirs[std::size_t(m)]);
            lcp.b[std::size_t(t)] = std::fabs(vt) <= options.tangentDeadZone ? 0.0 : vt;
            lcp.add(t, lambda, 1.0);   // E: w_t = D^T v^+ + lambda e >= 0
            lcp.add(lambda, t, -1.0);  // -E^T
        }
        lcp.add(lambda, c, node.friction);  // w_lambda = mu f_n - sum beta >= 0 (Coulomb pyramid)
    }
    if (outLayout) *outLayout = layout;
    return lcp;
}

}  // namespace detail

template <class D>
Lcp assembleFrictionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                        const ResolverOptions& options, FrictionLayout* outLayout) {
    return detail::buildFrictionLcp(bodies, contacts, options, outLayout).toDense();
}

template <class D>
SparseLcp assembleFrictionLcpSparse(const std::vector<ResolverBody<D>>& bodies,
                                    const std::vector<ContactNode<D>>& contacts, const ResolverOptions& options,
                                    FrictionLayout* outLayout) {
    return detail::buildFrictionLcp(bodies, contacts, options, outLayout).toSparse();
}

template <class D>
void applyImpulses(std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                   const std::vector<double>& impulses, const std::vector<typename D::Vec>* tangent) {
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        const ContactNode<D>& c = contacts[i];
        typename D::Vec P = D::scale(impulses[i], c.normal);  // Psi = f n, eq. (5)
        if (tangent) P = D::add(P, (*tangent)[i]);
        ResolverBody<D>& A = bodies[std::size_t(c.a)];
        ResolverBody<D>& B = bodies[std::size_t(c.b)];
        // eq. (15): v += Psi / M, omega += I^-1 (r x Psi); B receives -Psi (Newton's third law).
        A.velocity = D::add(A.velocity, D::scale(A.invMass, P));
        A.angularVelocity = D::angAdd(A.angularVelocity, D::applyInvInertia(A.invInertia, D::cross(D::sub(c.point, A.position), P)));
        B.velocity = D::sub(B.velocity, D::scale(B.invMass, P));
        B.angularVelocity = D::angAdd(B.angularVelocity,
                                      D::applyInvInertia(B.invInertia, D::cross(D::sub(c.point, B.position), D::scale(-1.0, P))));
    }
}

template <class D>
Resolution resolveCollisions(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                             const ResolverOptions& options, LemkeSolver& solver) {
    Resolution out;
    out.message = validate(ioBodies, contacts);
    if (!out.message.empty()) return out;
    const SparseLcp lcp = assembleCollisionLcpSparse(ioBodies, contacts, options);
    if (lcp.n == 1) {
        // One point: one linear equation in one unknown (end of the paper's section 5), f = max(0, -b / A).
        out.fastPath = true;
        const double a = lcp.vals.empty() ? 0.0 : lcp.vals[0];
        const double b = lcp.b[0];
        if (b >= 0.0) {
            out.impulses = {0.0};
        } else if (a > 0.0) {
            out.impulses = {-b / a};
            out.basis = {0};
        } else {
            out.status = LcpStatus::infeasible;
            out.message = "single contact between two immovable bodies is approaching";
            return out;
        }
        out.status = LcpStatus::solved;
    } else if (lcp.n > 1) {
        LcpResult r = solver.solve(lcp, options.lcp);
        detail::takeSolveReport(r, out);
        if (r.status != LcpStatus::solved) return out;
        out.impulses = std::move(r.z);
    } else {
        out.status = LcpStatus::solved;
    }
    applyImpulses(ioBodies, contacts, out.impulses);
    return out;
}

template <class D>
Resolution resolveWithFriction(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                               const ResolverOptions& options, LemkeSolver& solver) {
    Resolution out;
    out.message = validate(ioBodies, contacts);
    if (!out.message.empty()) return out;
    FrictionLayout layout;
    const SparseLcp lcp = assembleFrictionLcpSparse(ioBodies, contacts, options, &layout);
    LcpResult r = solver.solve(lcp, options.lcp);
    detail::takeSolveReport(r, out);
    if (r.status != LcpStatus::solved) return out;
    const int nc = layout.contacts;
    const int k = layout.directions;
    out.impulses.assign(r.z.begin(), r.z.begin() + nc);
    std::vector<typename D::Vec> tangent(std::size_t(nc), D::zeroVec());
    for (int c = 0; c < nc; ++c) {
        const auto dirs = frictionDirections(contacts[std::size_t(c)], k);
        for (int m = 0; m < k; ++m) {
            const double beta = r.z[std::size_t(layout.tangentOffset() + c * k + m)];
            tangent[std::size_t(c)] = D::add(tangent[std::size_t(c)], D::scale(beta, dirs[std::size_t(m)]));
        }
    }
    for (const auto& t : tangent) {
        for (int d = 0; d < D::kDim; ++d) out.tangentImpulses.push_back(t[d]);
    }
    applyImpulses(ioBodies, contacts, out.impulses, &tangent);
    return out;
}

}  // namespace unison

/// Explicit instantiation of the whole resolver for one dimension trait (used once per dimension).
#define UNISON_INSTANTIATE_RESOLVER(D)                                                                              \
    template double relativeNormalVelocity<D>(const std::vector<ResolverBody<D>>&, const ContactNode<D>&);        \
    template std::string validate<D>(const std::vector<ResolverBody<D>>&, const std::vector<ContactNode<D>>&);    \
    template Lcp assembleCollisionLcp<D>(const std::vector<ResolverBody<D>>&, const std::vector<ContactNode<D>>&, \
                                         const ResolverOptions&);                                                 \
    template Lcp assembleFrictionLcp<D>(const std::vector<ResolverBody<D>>&, const std::vector<ContactNode<D>>&,  \
                                        const ResolverOptions&, FrictionLayout*);                                 \
    template SparseLcp assembleCollisionLcpSparse<D>(const std::vector<ResolverBody<D>>&,                         \
                                                     const std::vector<ContactNode<D>>&, const ResolverOptions&); \
    template SparseLcp assembleFrictionLcpSparse<D>(const std::vector<ResolverBody<D>>&,                          \
                                                    const std::vector<ContactNode<D>>&, const ResolverOptions&,   \
                                                    FrictionLayout*);                                             \
    template std::vector<D::Vec> frictionDirections<D>(const ContactNode<D>&, int);                               \
    template void applyImpulses<D>(std::vector<ResolverBody<D>>&, const std::vector<ContactNode<D>>&,             \
                                   const std::vector<double>&, const std::vector<D::Vec>*);                       \
    template Resolution resolveCollisions<D>(std::vector<ResolverBody<D>>&, const std::vector<ContactNode<D>>&,   \
                                             const ResolverOptions&, LemkeSolver&);                               \
    template Resolution resolveWithFriction<D>(std::vector<ResolverBody<D>>&, const std::vector<ContactNode<D>>&, \
                                               const ResolverOptions&, LemkeSolver&);
