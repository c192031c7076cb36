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

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

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

// J M^-1 J^T of `rows`, eq. (20), one row at a time. Per body, the rows touching it in row order (with the
// row's slot, 0 for A and 1 for B) and I_k^-1 r*_ki of each; row i's entries are then the merge of the row lists of
// its two bodies. An entry shared by both bodies (two rows on the same pair) is summed in body index order, so every
// A_ij is the same sum, in the same order, whether it is built densely (addTo) or in compressed rows (appendRow).
// Appends compressed-row entries into storage reserved beforehand to an upper bound (never reallocated; reserving
// rather than resizing spares zero-filling the bound, which is often much more than is written).
struct RowWriter {
    explicit RowWriter(SparseLcp& lcp, std::size_t bound) : lcp(lcp) {
        lcp.cols.clear();
        lcp.vals.clear();
        lcp.cols.reserve(bound);
        lcp.vals.reserve(bound);
    }
    void push(int j, double v) {
        lcp.cols.push_back(j);
        lcp.vals.push_back(v);
    }
    int row(int i) const { return lcp.rowStart[std::size_t(i)]; }
    void endRow(int i) { lcp.rowStart[std::size_t(i) + 1] = int(lcp.cols.size()); }
    SparseLcp& lcp;
};

template <class D>
class Coupling {
public:
    Coupling(const std::vector<ResolverBody<D>>& bodies, const std::vector<JacobianRow<D>>& rows)
        : mBodies(bodies), mStart(bodies.size() + 1, 0) {
        for (const auto& r : rows) {
            ++mStart[std::size_t(r.body[0]) + 1];
            ++mStart[std::size_t(r.body[1]) + 1];
        }
        for (std::size_t k = 0; k < bodies.size(); ++k) mStart[k + 1] += mStart[k];
        std::vector<int> fill(mStart.begin(), mStart.end() - 1);
        std::vector<typename D::InvInertia> factors;
        factors.reserve(bodies.size());
        for (const ResolverBody<D>& b : bodies) factors.push_back(D::couplingFactor(b.invInertia));
        mEntries.resize(std::size_t(mStart.back()));
        mRowEntry.resize(2 * rows.size());
        mBodyOf.resize(2 * rows.size());
        for (int i = 0; i < int(rows.size()); ++i) {
            const JacobianRow<D>& r = rows[std::size_t(i)];
            for (int s = 0; s < 2; ++s) {
                const int k = r.body[s];
                const std::size_t e = std::size_t(fill[std::size_t(k)]++);
                // lambda_k = r*_ki^T I_k^-1, applied to the other row's angular part in term(), split into two
                // halves (D::couplingHalves: in 3D both are L^T r*, which makes A exactly symmetric).
                Entry& en = mEntries[e];
                en.row = i;
                en.lin = r.lin[s];
                D::couplingHalves(factors[std::size_t(k)], r.ang[s], en.ang, en.invIr);
                mRowEntry[2 * std::size_t(i) + std::size_t(s)] = int(e);
                mBodyOf[2 * std::size_t(i) + std::size_t(s)] = k;
            }
        }
    }

    /// Restricts the columns of appendRow<true> to the rows j with keep[j] != 0: each body's list of rows is
    /// filtered once here, rather than every row that meets the body skipping the same entries.
    void keepColumns(const char* keep) {
        mKeptStart.assign(mStart.size(), 0);
        mKept.clear();
        for (std::size_t k = 0; k + 1 < mStart.size(); ++k) {
            for (int e = mStart[k]; e < mStart[k + 1]; ++e) {
                if (keep[mEntries[std::size_t(e)].row]) mKept.push_back(mEntries[std::size_t(e)]);
            }
            mKeptStart[k + 1] = int(mKept.size());
        }
    }

    /// An upper bound on the entries of all rows (every row meets each row of its two bodies at most once); with
    /// Restricted, of the columns kept by keepColumns.
    template <bool Restricted = false>
    std::size_t entryBound() const {
        const std::vector<int>& start = Restricted ? mKeptStart : mStart;
        std::size_t total = 0;
        for (std::size_t i = 0; 2 * i < mBodyOf.size(); ++i) {
            for (int s = 0; s < 2; ++s) {
                const int k = mBodyOf[2 * i + std::size_t(s)];
                if (movable(k)) total += std::size_t(start[std::size_t(k) + 1] - start[std::size_t(k)]);
            }
        }
        return total;
    }

    /// Appends row i's nonzero entries (columns ascending) to `out`; raises maxAbs to their largest |value| and
    /// clears `finite` on a NaN or infinity. Restricted: only the columns kept by keepColumns (same values).
    template <bool Restricted = false>
    void appendRow(int i, RowWriter& out, double& maxAbs, bool& finite) const {
        const int a = mBodyOf[2 * std::size_t(i)], b = mBodyOf[2 * std::size_t(i) + 1];
        const Entry& ia = mEntries[std::size_t(mRowEntry[2 * std::size_t(i)])];
        const Entry& ib = mEntries[std::size_t(mRowEntry[2 * std::size_t(i) + 1])];
        const double ma = mBodies[std::size_t(a)].invMass, mb = mBodies[std::size_t(b)].invMass;
        const std::vector<Entry>& list = Restricted ? mKept : mEntries;
        const std::vector<int>& start = Restricted ? mKeptStart : mStart;
        const Entry* pa = movable(a) ? list.data() + start[std::size_t(a)] : nullptr;
        const Entry* ea = movable(a) ? list.data() + start[std::size_t(a) + 1] : nullptr;
        const Entry* pb = movable(b) ? list.data() + start[std::size_t(b)] : nullptr;
        const Entry* eb = movable(b) ? list.data() + start[std::size_t(b) + 1] : nullptr;
        constexpr int kEnd = std::numeric_limits<int>::max();
        while (pa != ea || pb != eb) {
            const int ja = pa != ea ? pa->row : kEnd;
            const int jb = pb != eb ? pb->row : kEnd;
            double v;
            int j;
            if (ja < jb) {
                j = ja;
                v = term(ma, ia, *pa++);
            } else if (jb < ja) {
                j = jb;
                v = term(mb, ib, *pb++);
            } else {
                j = ja;
                const double ta = term(ma, ia, *pa++), tb = term(mb, ib, *pb++);
                v = a < b ? ta + tb : tb + ta;
            }
            if (v != 0.0) {
                out.push(j, v);
                const double m = std::fabs(v);
                finite = finite && m <= std::numeric_limits<double>::max();
                maxAbs = m > maxAbs ? m : maxAbs;
            }
        }
    }

    /// out[i] = (J M^-1 J^T z)_i for every row i, through per-body sums M_k^-1 J_k^T z (O(entries), not
    /// O(entries^2) as the rows themselves): the matrix-free product of LemkeSolver::checkGuess. Equal to the rows'
    /// products up to rounding (the sums run in another order).
    void multiply(const double* z, double* out) const {
        const std::size_t nb = mBodies.size();
        std::vector<typename D::Vec> lin(nb, D::zeroVec());
        std::vector<typename D::Ang> ang(nb, D::zeroAng());
        for (std::size_t k = 0; k < nb; ++k) {
            if (!movable(int(k))) continue;
            for (int e = mStart[k]; e < mStart[k + 1]; ++e) {
                const Entry& en = mEntries[std::size_t(e)];
                const double zj = z[en.row];
                if (zj == 0.0) continue;
                lin[k] = D::add(lin[k], D::scale(zj, en.lin));
                ang[k] = D::angAdd(ang[k], D::angScale(zj, en.ang));
            }
        }
        for (std::size_t i = 0; 2 * i < mBodyOf.size(); ++i) {
            double v = 0.0;
            for (int s = 0; s < 2; ++s) {
                const int k = mBodyOf[2 * i + std::size_t(s)];
                if (!movable(k)) continue;
                const Entry& en = mEntries[std::size_t(mRowEntry[2 * i + std::size_t(s)])];
                v += mBodies[std::size_t(k)].invMass * D::dot(en.lin, lin[std::size_t(k)]) +
                     D::angDot(en.invIr, ang[std::size_t(k)]);
            }
            out[i] = v;
        }
    }

    /// A_ii, the same sum appendRow forms for column i of row i.
    double diagonal(int i) const {
        const int a = mBodyOf[2 * std::size_t(i)], b = mBodyOf[2 * std::size_t(i) + 1];
        const Entry& ia = mEntries[std::size_t(mRowEntry[2 * std::size_t(i)])];
        const Entry& ib = mEntries[std::size_t(mRowEntry[2 * std::size_t(i) + 1])];
        const bool ma = movable(a), mb = movable(b);
        const double ta = ma ? term(mBodies[std::size_t(a)].invMass, ia, ia) : 0.0;
        const double tb = mb ? term(mBodies[std::size_t(b)].invMass, ib, ib) : 0.0;
        if (ma && mb) return a < b ? ta + tb : tb + ta;
        return ma ? ta : tb;
    }

    /// Adds every term to `lcp` (dense assembly), bodies in index order.
    void addTo(LcpTriplets& lcp) const {
        for (std::size_t k = 0; k < mBodies.size(); ++k) {
            if (!movable(int(k))) continue;
            for (int p = mStart[k]; p < mStart[k + 1]; ++p) {
                const Entry& ei = mEntries[std::size_t(p)];
                for (int q = mStart[k]; q < mStart[k + 1]; ++q)
                    lcp.add(ei.row, mEntries[std::size_t(q)].row, term(mBodies[k].invMass, ei, mEntries[std::size_t(q)]));
            }
        }
    }

private:
    // One row as seen by one of its bodies: its direction and the two halves of its angular part, whose product
    // angDot(invIr_i, ang_j) is r*_i . I^-1 r*_j (D::couplingHalves: in 2D r* l and I^-1 r* l; in 3D L^T r* l both).
    struct Entry {
        Entry() {}  // user-provided: resizing the entry list must not zero-fill what the constructor overwrites
        int row = 0;
        typename D::Vec lin;
        typename D::Ang ang;
        typename D::Ang invIr;
    };

    // Infinite mass contributes nothing (the paper's dummy body).
    bool movable(int k) const { return !isImmovable(mBodies[std::size_t(k)]); }

    // The contribution to A_ij of one body (inverse mass invMass) touched by both rows: ei is row i's entry in the
    // body's list, ej row j's.
    static double term(double invMass, const Entry& ei, const Entry& ej) {
        return invMass * D::dot(ei.lin, ej.lin) + D::angDot(ei.invIr, ej.ang);
    }

    const std::vector<ResolverBody<D>>& mBodies;
    std::vector<int> mStart, mRowEntry, mBodyOf;
    std::vector<Entry> mEntries;
    std::vector<int> mKeptStart;  // keepColumns: per body, its entries whose rows are kept
    std::vector<Entry> mKept;
};

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
// True when the impulses of `r` are to be applied (see ResolverOptions::acceptResidual).
inline bool takeSolveReport(LcpResult& r, Resolution& out, const ResolverOptions& options) {
    out.status = r.status;
    out.pivots = r.pivots;
    out.work = r.work;
    out.residual = r.residual;
    out.scaledResidual = r.scaledResidual;
    out.approximate = r.status == LcpStatus::numerical_failure && r.scaledResidual <= options.acceptResidual;
    out.warmStarted = r.warmStarted;
    out.basis = std::move(r.basis);
    out.message = std::move(r.message);
    return r.status == LcpStatus::solved || out.approximate;
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
std::vector<JacobianRow<D>> normalRows(const std::vector<ResolverBody<D>>& bodies,
                                       const std::vector<ContactNode<D>>& contacts, std::size_t capacity = 0) {
    std::vector<JacobianRow<D>> rows;
    rows.reserve(std::max(capacity, contacts.size()));
    for (const auto& c : contacts) rows.push_back(makeRow(bodies, c, c.normal));
    return rows;
}

template <class D>
std::vector<double> normalRhsAll(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                                 const ResolverOptions& options) {
    std::vector<double> b(contacts.size());
    for (std::size_t i = 0; i < contacts.size(); ++i) b[i] = normalRhs(bodies, contacts[i], options.restitutionThreshold);  // eq. (19)
    return b;
}

}  // namespace detail

template <class D>
Lcp assembleCollisionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                         const ResolverOptions& options) {
    const auto rows = detail::normalRows(bodies, contacts);
    LcpTriplets lcp(int(contacts.size()));
    detail::Coupling<D>(bodies, rows).addTo(lcp);  // eq. (20)
    lcp.b = detail::normalRhsAll(bodies, contacts, options);
    return lcp.toDense();
}

template <class D>
SparseLcp assembleCollisionLcpSparse(const std::vector<ResolverBody<D>>& bodies,
                                     const std::vector<ContactNode<D>>& contacts, const ResolverOptions& options) {
    const auto rows = detail::normalRows(bodies, contacts);
    const detail::Coupling<D> coupling(bodies, rows);
    SparseLcp lcp;
    lcp.n = int(contacts.size());
    lcp.rowStart.assign(std::size_t(lcp.n) + 1, 0);
    detail::RowWriter out(lcp, coupling.entryBound());
    double maxAbs = 0.0;
    bool finite = true;
    for (int i = 0; i < lcp.n; ++i) {
        coupling.appendRow(i, out, maxAbs, finite);
        out.endRow(i);
    }
    lcp.b = detail::normalRhsAll(bodies, contacts, options);
    lcp.maxAbs = finite ? maxAbs : -1.0;  // rows built here: the solver need not check them again
    lcp.symmetricHint = D::kExactCoupling;
    return lcp;
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

// The rows and right-hand side of the friction LCP; A's coupling block comes from Coupling over `rows`.
template <class D>
struct FrictionSystem {
    FrictionLayout layout;
    std::vector<JacobianRow<D>> rows;  // normal rows first, then the tangent rows of contact 0, 1, ...: J = [N ; D]
    std::vector<double> b;
    std::vector<double> mu;            // per contact
    std::vector<typename D::Vec> dirs; // the tangent directions, contact c's at c * k (for composing the impulses)
};

// With evenDirectionsOnly (for a reader of the +t rows of a 2D pyramid only), the rows of the odd directions (-t)
// are left empty with b = 0; every other row is as without it.
template <class D>
FrictionSystem<D> buildFrictionSystem(const std::vector<ResolverBody<D>>& bodies,
                                      const std::vector<ContactNode<D>>& contacts, const ResolverOptions& options,
                                      bool evenDirectionsOnly = false) {
    FrictionSystem<D> sys;
    FrictionLayout& layout = sys.layout;
    layout.contacts = int(contacts.size());
    layout.directions = D::frictionDirectionCount(options.frictionDirections);
    const int nc = layout.contacts;
    const int k = layout.directions;
    sys.rows = normalRows(bodies, contacts, std::size_t(nc) * std::size_t(k + 1));  // room for the tangent rows
    sys.b.assign(std::size_t(layout.size()), 0.0);
    sys.mu.resize(std::size_t(nc));
    sys.dirs.reserve(std::size_t(nc) * std::size_t(k));
    for (int c = 0; c < nc; ++c) {
        const ContactNode<D>& node = contacts[std::size_t(c)];
        sys.b[std::size_t(c)] = normalRhs(bodies, node, options.restitutionThreshold);
        sys.mu[std::size_t(c)] = node.friction;
        for (int m = 0; m < k; ++m) {
            const typename D::Vec dir = D::tangentDirection(node.normal, m, k);  // as frictionDirections(node, k)
            sys.dirs.push_back(dir);
            if (evenDirectionsOnly && m % 2 == 1) {  // an empty row in its place, b = 0
                sys.rows.emplace_back();
                continue;
            }
            sys.rows.push_back(makeRow(bodies, node, dir));
            const double vt = relativeVelocityAlong(bodies, node, dir);
            sys.b[std::size_t(layout.tangentOffset() + c * k + m)] = std::fabs(vt) <= options.tangentDeadZone ? 0.0 : vt;
        }
    }
    return sys;
}

// The earlier tangent row of the same contact whose direction is exactly -1 times row i's (every component of the
// row negated, compared bit for bit), or -1.
template <class D>
int negatedEarlierRow(const std::vector<JacobianRow<D>>& rows, int i, const FrictionLayout& layout) {
    const int k = layout.directions;
    const int m = (i - layout.tangentOffset()) % k;
    const JacobianRow<D>& r = rows[std::size_t(i)];
    for (int p = i - m; p < i; ++p) {
        const JacobianRow<D>& q = rows[std::size_t(p)];
        bool negated = true;
        for (int s = 0; s < 2 && negated; ++s) {
            const typename D::Vec lin = D::scale(-1.0, q.lin[s]);
            const typename D::Ang ang = D::angScale(-1.0, q.ang[s]);
            negated = std::memcmp(&lin, &r.lin[s], sizeof lin) == 0 && std::memcmp(&ang, &r.ang[s], sizeof ang) == 0;
        }
        if (negated) return p;
    }
    return -1;
}

}  // namespace detail

template <class D>
Lcp assembleFrictionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                        const ResolverOptions& options, FrictionLayout* outLayout) {
    const detail::FrictionSystem<D> sys = detail::buildFrictionSystem(bodies, contacts, options);
    const FrictionLayout& layout = sys.layout;
    LcpTriplets lcp(layout.size());
    detail::Coupling<D>(bodies, sys.rows).addTo(lcp);
    for (int c = 0; c < layout.contacts; ++c) {
        const int lambda = layout.slackOffset() + c;
        for (int m = 0; m < layout.directions; ++m) {
            const int t = layout.tangentOffset() + c * layout.directions + m;
            lcp.add(t, lambda, 1.0);   // E: w_t = D^T v^+ + lambda e >= 0
            lcp.add(lambda, t, -1.0);  // -E^T
        }
        lcp.add(lambda, c, sys.mu[std::size_t(c)]);  // w_lambda = mu f_n - sum beta >= 0 (Coulomb pyramid)
    }
    lcp.b = sys.b;
    if (outLayout) *outLayout = layout;
    return lcp.toDense();
}

namespace detail {

// The rows of the friction LCP in compressed form: coupling rows (each tangent row ending with its slack column, the
// largest index), then the slack rows [mu at the normal, -1 at each tangent]. Restricted: only the columns j with
// keep[j] != 0 (see LemkeSolver::checkGuess; `coupling.keepColumns(keep)` must have been called). Either way
// maxAbs is the largest of the diagonal entries, the friction coefficients and 1: computable from the diagonal
// alone, so the part and the whole carry the same voucher, and equal to max |A_ij| up to rounding (the coupling
// block is a Gram matrix: |A_ij| <= sqrt(A_ii A_jj)).
template <class D, bool Restricted>
SparseLcp writeFrictionRows(const FrictionSystem<D>& sys, const Coupling<D>& coupling, const char* keep,
                            const char* keepRows = nullptr) {
    const FrictionLayout& layout = sys.layout;
    const int nc = layout.contacts, k = layout.directions, nr = int(sys.rows.size());
    SparseLcp lcp;
    lcp.n = layout.size();
    lcp.rowStart.assign(std::size_t(lcp.n) + 1, 0);
    double maxAbs = 1.0;  // the +-1 entries of E
    bool finite = true;
    const std::size_t bound = coupling.template entryBound<Restricted>() + std::size_t(nc) * std::size_t(2 * k + 1);
    RowWriter out(lcp, bound);
    auto kept = [&](int j) { return !Restricted || keep[j] != 0; };
    auto rowKept = [&](int i) { return !keepRows || keepRows[i] != 0; };
    for (int i = 0; i < nr; ++i) {
        if (!rowKept(i)) {
            // Not written (checkGuess with a product needs only the guessed rows); the scale still counts it. No
            // search for a negated partner row: its diagonal would be this one's, bit for bit.
            const double d = std::fabs(coupling.diagonal(i));
            finite = finite && d <= std::numeric_limits<double>::max();
            maxAbs = d > maxAbs ? d : maxAbs;
            out.endRow(i);
            continue;
        }
        const int slack = i >= layout.tangentOffset() ? layout.slackOffset() + (i - layout.tangentOffset()) / k : -1;
        const int partner = slack >= 0 ? negatedEarlierRow(sys.rows, i, layout) : -1;
        if (partner >= 0 && rowKept(partner)) {
            // Row i is exactly -1 times an earlier tangent row of its contact (+t / -t pairs): every coupling term
            // is that row's term negated, bit for bit (negation is exact, and so are the products and sums of
            // negated values), so copy them rather than recompute. The partner's slack column is not copied.
            for (int e = out.row(partner); e < out.row(partner + 1); ++e) {
                if (lcp.cols[std::size_t(e)] != slack) out.push(lcp.cols[std::size_t(e)], -lcp.vals[std::size_t(e)]);
            }
        } else {
            double pushedMax = 0.0;  // finiteness of the entries is what counts here; the scale is the diagonal's
            coupling.template appendRow<Restricted>(i, out, pushedMax, finite);
            const double d = std::fabs(coupling.diagonal(i));
            finite = finite && d <= std::numeric_limits<double>::max();
            maxAbs = d > maxAbs ? d : maxAbs;
        }
        if (slack >= 0 && kept(slack)) out.push(slack, 1.0);
        out.endRow(i);
    }
    for (int c = 0; c < nc; ++c) {
        const bool written = rowKept(nr + c);
        if (sys.mu[std::size_t(c)] != 0.0) {
            if (written && kept(c)) out.push(c, sys.mu[std::size_t(c)]);
            maxAbs = std::max(maxAbs, sys.mu[std::size_t(c)]);  // mu is finite and >= 0 (validate)
        }
        for (int m = 0; m < k; ++m) {
            if (written && kept(layout.tangentOffset() + c * k + m)) out.push(layout.tangentOffset() + c * k + m, -1.0);
        }
        out.endRow(nr + c);
    }
    lcp.maxAbs = finite ? maxAbs : -1.0;  // rows built here: the solver need not check them again
    lcp.symmetricHint = D::kExactCoupling;
    return lcp;
}

}  // namespace detail

template <class D>
SparseLcp assembleFrictionLcpSparse(const std::vector<ResolverBody<D>>& bodies,
                                    const std::vector<ContactNode<D>>& contacts, const ResolverOptions& options,
                                    FrictionLayout* outLayout) {
    // The same entries as assembleFrictionLcp, written row by row.
    detail::FrictionSystem<D> sys = detail::buildFrictionSystem(bodies, contacts, options);
    SparseLcp lcp = detail::writeFrictionRows<D, false>(sys, detail::Coupling<D>(bodies, sys.rows), nullptr);
    lcp.b = std::move(sys.b);
    if (outLayout) *outLayout = sys.layout;
    return lcp;
}

namespace detail {

/// eq. (15) for one contact's impulse P: v += P / M, omega += I^-1 (r x P) on A; B receives -P (Newton's third law).
template <class D>
void applyImpulse(std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c, const typename D::Vec& P) {
    ResolverBody<D>& A = bodies[std::size_t(c.a)];
    ResolverBody<D>& B = bodies[std::size_t(c.b)];
    A.velocity = D::add(A.velocity, D::scale(A.invMass, P));
    A.angularVelocity = D::angAdd(A.angularVelocity, D::applyInvInertia(A.invInertia, D::cross(D::sub(c.point, A.position), P)));
    B.velocity = D::sub(B.velocity, D::scale(B.invMass, P));
    B.angularVelocity = D::angAdd(B.angularVelocity,
                                  D::applyInvInertia(B.invInertia, D::cross(D::sub(c.point, B.position), D::scale(-1.0, P))));
}

}  // namespace detail

template <class D>
void applyImpulses(std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                   const std::vector<double>& impulses, const std::vector<typename D::Vec>* tangent) {
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        const ContactNode<D>& c = contacts[i];
        typename D::Vec P = D::scale(impulses[i], c.normal);  // Psi = f n, eq. (5)
        if (tangent) P = D::add(P, (*tangent)[i]);
        detail::applyImpulse(bodies, c, P);
    }
}

template <class D>
Resolution resolveCollisions(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                             const ResolverOptions& options, LemkeSolver& solver) {
    Resolution out;
    out.message = validate(ioBodies, contacts);
    if (!out.message.empty()) return out;
    SparseLcp lcp = assembleCollisionLcpSparse(ioBodies, contacts, options);
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
        LcpResult r = solver.solve(std::move(lcp), options.lcp);
        if (!detail::takeSolveReport(r, out, options)) return out;
        out.impulses = std::move(r.z);
    } else {
        out.status = LcpStatus::solved;
    }
    applyImpulses(ioBodies, contacts, out.impulses);
    return out;
}

}  // namespace unison

#include "single_contact_impl.h"

namespace unison {

template <class D>
Resolution resolveWithFriction(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                               const ResolverOptions& options, LemkeSolver& solver) {
    Resolution out;
    out.message = validate(ioBodies, contacts);
    if (!out.message.empty()) return out;
    if constexpr (D::kDim == 2) {
        if (contacts.size() == 1 && detail::singleContactFriction(ioBodies, contacts[0], options, out)) return out;
    }
    detail::FrictionSystem<D> sys = detail::buildFrictionSystem(ioBodies, contacts, options);
    const FrictionLayout layout = sys.layout;
    detail::Coupling<D> coupling(ioBodies, sys.rows);
    const std::vector<typename D::Vec> dirs = std::move(sys.dirs);
    LcpResult r;
    const std::vector<int>* guess = options.lcp.warmBasis;
    if (guess && !guess->empty()) {
        // A resting island's guess is usually right, and checking it needs only A's columns in the guess (a small
        // part of A: most unknowns of a pile are zero). The full A is built only when the guess fails; the answer
        // is the same bits either way (LemkeSolver::checkGuess).
        std::vector<char> keep(std::size_t(layout.size()), 0);
        bool inRange = true;
        for (int j : *guess) {
            inRange = inRange && j >= 0 && j < layout.size();
            if (inRange) keep[std::size_t(j)] = 1;
        }
        if (inRange) coupling.keepColumns(keep.data());
        if (inRange && D::kMatrixFreeCheck) {
            // Only the guess's block of A, and w on every row as J (M^-1 (J^T z)) (Coupling::multiply): the other
            // rows of A's guessed columns are never formed.
            SparseLcp block = detail::writeFrictionRows<D, true>(sys, coupling, keep.data(), keep.data());
            block.b = sys.b;
            const int nr = int(sys.rows.size()), nc = layout.contacts, k = layout.directions;
            const LemkeSolver::Product product = [&](const double* z, double* w) {
                coupling.multiply(z, w);
                for (int i = 0; i < nr; ++i) {
                    double s = w[i] + sys.b[std::size_t(i)];
                    if (i >= layout.tangentOffset()) s += z[layout.slackOffset() + (i - layout.tangentOffset()) / k];
                    w[i] = s;
                }
                for (int c = 0; c < nc; ++c) {  // w_lambda = mu f_n - sum beta (+ b, which is 0)
                    double s = sys.b[std::size_t(nr + c)] + sys.mu[std::size_t(c)] * z[c];
                    for (int m = 0; m < k; ++m) s -= z[layout.tangentOffset() + c * k + m];
                    w[nr + c] = s;
                }
            };
            r = solver.checkGuess(std::move(block), options.lcp, product);
        } else if (inRange) {
            SparseLcp part = detail::writeFrictionRows<D, true>(sys, coupling, keep.data());
            part.b = sys.b;
            r = solver.checkGuess(std::move(part), options.lcp);
        }
    }
    if (r.status != LcpStatus::solved) {
        SparseLcp lcp = detail::writeFrictionRows<D, false>(sys, coupling, nullptr);
        lcp.b = std::move(sys.b);
        r = solver.solve(std::move(lcp), options.lcp);
    }
    if (!detail::takeSolveReport(r, out, options)) return out;
    const int nc = layout.contacts;
    const int k = layout.directions;
    out.impulses.assign(r.z.begin(), r.z.begin() + nc);
    std::vector<typename D::Vec> tangent(std::size_t(nc), D::zeroVec());
    for (int c = 0; c < nc; ++c) {
        for (int m = 0; m < k; ++m) {
            const double beta = r.z[std::size_t(layout.tangentOffset() + c * k + m)];
            const typename D::Vec& dir = dirs[std::size_t(c * k + m)];
            tangent[std::size_t(c)] = D::add(tangent[std::size_t(c)], D::scale(beta, dir));
        }
    }
    for (const auto& t : tangent) {
        for (int d = 0; d < D::kDim; ++d) out.tangentImpulses.push_back(t[d]);
    }
    applyImpulses(ioBodies, contacts, out.impulses, &tangent);
    return out;
}

}  // namespace unison

#include "active_set_impl.h"

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
                                               const ResolverOptions&, LemkeSolver&);                             \
    template Resolution resolveActiveSet<D>(std::vector<ResolverBody<D>>&, const std::vector<ContactNode<D>>&,    \
                                            const std::vector<double>&, const ResolverOptions&,                   \
                                            const ActiveSetOptions&);
