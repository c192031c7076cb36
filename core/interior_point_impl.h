// core/interior_point_impl.h — template body of the active-set path's interior-point restart (core/active_set_impl.h,
// ActiveSetOptions::interiorPoint). Included by core/active_set_impl.h only.
//
// The convex relaxation of the island's problem,
// min 1/2 p^T A p + b^T p over the cones |p_t| <= mu p_n (A = J M^-1 J^T), by Mehrotra's predictor-corrector
// method. Per contact the constraints are C p >= 0 with C = [mu, -1; mu, 1] (one row, p_n >= 0, where mu or
// the tangent row's diagonal is 0). Its Newton system (A + C^T S^-1 Y C) dp = g is solved in body space: with
// H^-1 the inverse of each contact's 2 x 2 block C^T S^-1 Y C, (M + J^T H^-1 J) dv = J^T H^-1 g and
// dp = H^-1 (g - J dv), a symmetric positive definite system of the bodies' degrees of freedom whose pattern
// (the bodies' contact graph) does not change between iterations. The relaxation differs from the
// Stewart–Trinkle problem only where contacts slide (it lets them separate at mu |u_t|), so its answer, with
// the constraints whose slack is small against their multiplier taken as active, is a start the active-set
// iteration finishes from (docs/solver.md, "Landing piles"). Once the gap is small, a face step (below) solves the
// LCP's equations on the face of the iterate's active constraints with the same system's pattern, and usually ends
// the iteration with an answer that passes the island LCP's certificate. Where contacts slide and the first answer
// does not certify, further rounds solve the relaxation again with de Saxce's shift (below).
#pragma once

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "body_space_solve.h"
#include "interior_point_start.h"
#include "symmetric_pattern_lu.h"

namespace unison {
namespace detail {

/// The interior-point answer of the island's convex relaxation, rounded onto its active constraints, in xOut (p_n,
/// p_t of contact c at 2c, 2c + 1). rowAt(c, r) is contact c's normal (r = 0) or +t (r = 1) Jacobian row, velocities(x,
/// u) sets u = b + J M^-1 J^T x, lcpResidual(x, u) is the island LCP's complementarity residual of (x, u) and tolAbs
/// the residual that certifies an answer, diag the diagonal of J M^-1 J^T per unknown, dof each body's first degree
/// of freedom (-1: immovable), bMax the largest |b|. Adds its work units to `work` and stops (false) once `maxWork`
/// (0: none) is reached, or when a factorisation fails. `scratch` (nullptr: none) keeps the system between calls.
/// An iterate that answers the LCP within tolAbs is returned as it stands, without the rounding. `warmStart`
/// (nullptr: a cold start) is the impulses to start from, in xOut's layout (core/interior_point_start.h).
template <class D, class RowAt, class Velocities, class Residual>
bool interiorPointStart(const std::vector<ResolverBody<D>>& bodies, const std::vector<double>& friction,
                        const std::vector<double>& diag, const std::vector<int>& dof, int ndof, double bMax,
                        const RowAt& rowAt, const Velocities& velocities, const Residual& lcpResidual,
                        double tolAbs, std::uint64_t rowWork,
                        SymmetricPatternCache* cache, InteriorPointScratch* scratch, std::uint64_t maxWork,
                        std::uint64_t& work, std::vector<double>& xOut,
                        const std::vector<double>* warmStart = nullptr) {
    const int nc = int(friction.size());
    const int nb = int(bodies.size());
    std::vector<std::uint8_t> locked(std::size_t(ndof), std::uint8_t(0));
    std::vector<std::uint8_t> two(static_cast<std::size_t>(nc));
    int m = 0;
    for (int c = 0; c < nc; ++c) {
        two[std::size_t(c)] = friction[std::size_t(c)] > 0.0 && diag[std::size_t(2 * c + 1)] > 0.0 ? 1 : 0;
        m += two[std::size_t(c)] ? 2 : 1;
    }
    const bool frictionless = m == nc;  // no contact has a friction row
    // Per contact, mu |u_t| of the last round's answer, added to its normal velocity in the rounds after the first
    // (below); 0 in the first.
    std::vector<double> shift(std::size_t(nc), 0.0);
    const double v0 = std::max(bMax, 1e-6);
    std::vector<double> p(std::size_t(2 * nc), 0.0), s(std::size_t(2 * nc), 0.0), y(std::size_t(2 * nc), 0.0);
    std::vector<double> uu(std::size_t(2 * nc)), rd(std::size_t(2 * nc)), rp(std::size_t(2 * nc), 0.0);
    std::vector<double> e(std::size_t(2 * nc), 0.0), hinv(std::size_t(3 * nc), 0.0);
    std::vector<double> dp(std::size_t(2 * nc)), ds(std::size_t(2 * nc), 0.0), dy(std::size_t(2 * nc), 0.0);
    std::vector<double> dsAff(std::size_t(2 * nc), 0.0), dyAff(std::size_t(2 * nc), 0.0);
    std::vector<double> rc(std::size_t(2 * nc), 0.0), g(std::size_t(2 * nc));
    // The start: cold, or from the warm start's impulses (core/interior_point_start.h).
    const double mu0Cold = interiorPointStartingPoint(friction, two, diag, v0, m, warmStart, velocities, p, s, y, uu);
    if (warmStart) work += rowWork;
    auto cp = [&](const std::vector<double>& q, int c, int i) {  // row i of C q for contact c
        const double pn = q[std::size_t(2 * c)], pt = q[std::size_t(2 * c + 1)];
        if (!two[std::size_t(c)]) return pn;
        return friction[std::size_t(c)] * pn + (i == 0 ? -pt : pt);
    };
    // The body-space matrix M + J^T H^-1 J: its pattern is fixed (every contact couples its bodies' degrees
    // of freedom), only the values change. After the first iteration only the entries its L D L^T factorisation of
    // symmetric values reads (those on and above the diagonal in its elimination order) are written; the others stay 0.
    InteriorPointScratch localScratch;
    InteriorPointScratch& sc = scratch ? *scratch : localScratch;
    // The contact entries the factorisation reads, contact by contact: their place in Kb's values and their sides and
    // components ((sa * 3 + a) << 4 | (sb * 3 + bb)), and where each contact's begin; the place of each diagonal.
    std::vector<int>& readPos = sc.readPos;
    std::vector<int>& readStart = sc.readStart;
    std::vector<std::uint8_t>& readCode = sc.readCode;
    std::vector<int>& diagPos = sc.diagPos;
    Eigen::SparseMatrix<double>& Kb = sc.Kb;
    SymmetricPatternLu& kbFactor = sc.factor;
    bool analysed = false;
    std::vector<double> moment(std::size_t(ndof > 0 ? ndof : 1));
    // Per contact, what the loops below read of its rows: each side's first degree of freedom (-1: immovable), the
    // normal and +t rows' components on it, and a bit per component that does not move (side * 3 + component).
    struct ContactRows {
        int d[2];
        double n[2][3], t[2][3];
        unsigned lockedMask;
    };
    std::vector<ContactRows> contactRows(static_cast<std::size_t>(nc));
    auto addRows = [&](int c, double hn, double ht) {  // moment += J_n^T hn + J_t^T ht
        const ContactRows& q = contactRows[std::size_t(c)];
        for (int r = 0; r < 2; ++r) {
            const double v = r == 0 ? hn : ht;
            if (v == 0.0) continue;
            const double(*j)[3] = r == 0 ? q.n : q.t;
            for (int sd = 0; sd < 2; ++sd) {
                const int d = q.d[sd];
                if (d < 0) continue;
                double* mo = &moment[std::size_t(d)];
                const unsigned lockedHere = (q.lockedMask >> (3 * sd)) & 7u;
                if (lockedHere == 0) {
                    mo[0] += v * j[sd][0];
                    mo[1] += v * j[sd][1];
                    mo[2] += v * j[sd][2];
                    continue;
                }
                for (int a = 0; a < 3; ++a)
                    if (!((lockedHere >> a) & 1u)) mo[a] += v * j[sd][a];
            }
        }
    };
    auto rowDot = [&](int c, int r, const Eigen::VectorXd& v) {  // J_r v
        const ContactRows& q = contactRows[std::size_t(c)];
        const double(*j)[3] = r == 0 ? q.n : q.t;
        double sum = 0.0;
        for (int sd = 0; sd < 2; ++sd) {
            const int d = q.d[sd];
            if (d < 0) continue;
            sum += j[sd][0] * v[d] + j[sd][1] * v[d + 1] + j[sd][2] * v[d + 2];
        }
        return sum;
    };
    auto applyHinv = [&](int c, double gn, double gt, double& hn, double& ht) {
        const double* H = &hinv[std::size_t(3 * c)];
        hn = H[0] * gn + H[1] * gt;
        ht = H[1] * gn + H[2] * gt;
    };
    for (int k = 0; k < nb; ++k) {
        const int d = dof[std::size_t(k)];
        if (d < 0) continue;
        const ResolverBody<D>& B = bodies[std::size_t(k)];
        const double inv[3] = {B.invMass, B.invMass, B.invInertia};
        for (int a = 0; a < 3; ++a) locked[std::size_t(d + a)] = inv[a] > 0.0 ? 0 : 1;
    }
    for (int c = 0; c < nc; ++c) {
        ContactRows& q = contactRows[std::size_t(c)];
        const detail::JacobianRow<D>& rn = rowAt(c, 0);
        const detail::JacobianRow<D>& rt = rowAt(c, 1);
        q.lockedMask = 0;
        for (int sd = 0; sd < 2; ++sd) {
            q.d[sd] = dof[std::size_t(rn.body[sd])];
            const double nv[3] = {rn.lin[sd].x, rn.lin[sd].y, rn.ang[sd]};
            const double tv[3] = {rt.lin[sd].x, rt.lin[sd].y, rt.ang[sd]};
            for (int a = 0; a < 3; ++a) {
                q.n[sd][a] = nv[a];
                q.t[sd][a] = tv[a];
                if (q.d[sd] >= 0 && locked[std::size_t(q.d[sd] + a)]) q.lockedMask |= 1u << (3 * sd + a);
            }
        }
    }
    // Direction for a complementarity target rc (rd, rp, s, y, hinv and the factors current).
    auto direction = [&]() -> bool {
        std::fill(moment.begin(), moment.end(), 0.0);
        for (int c = 0; c < nc; ++c) {
            double wn = 0.0, wt = 0.0;  // C^T (rc + y rp) / s
            if (two[std::size_t(c)]) {
                const double w0 = (rc[std::size_t(2 * c)] + y[std::size_t(2 * c)] * rp[std::size_t(2 * c)]) /
                                  s[std::size_t(2 * c)];
                const double w1 = (rc[std::size_t(2 * c + 1)] +
                                   y[std::size_t(2 * c + 1)] * rp[std::size_t(2 * c + 1)]) /
                                  s[std::size_t(2 * c + 1)];
                wn = friction[std::size_t(c)] * (w0 + w1);
                wt = w1 - w0;
            } else {
                wn = (rc[std::size_t(2 * c)] + y[std::size_t(2 * c)] * rp[std::size_t(2 * c)]) /
                     s[std::size_t(2 * c)];
            }
            g[std::size_t(2 * c)] = -rd[std::size_t(2 * c)] - wn;
            g[std::size_t(2 * c + 1)] = -rd[std::size_t(2 * c + 1)] - wt;
            double hn = 0.0, ht = 0.0;
            applyHinv(c, g[std::size_t(2 * c)], g[std::size_t(2 * c + 1)], hn, ht);
            addRows(c, hn, ht);
        }
        Eigen::VectorXd rv(ndof);
        for (int i = 0; i < ndof; ++i) rv[i] = moment[std::size_t(i)];
        const Eigen::VectorXd dv = ndof > 0 ? kbFactor.solve(rv) : rv;
        work += 4 * std::uint64_t(kbFactor.factorNonZeros()) + rowWork;
        for (int c = 0; c < nc; ++c) {
            const double gn = g[std::size_t(2 * c)] - rowDot(c, 0, dv);
            const double gt = g[std::size_t(2 * c + 1)] - rowDot(c, 1, dv);
            applyHinv(c, gn, gt, dp[std::size_t(2 * c)], dp[std::size_t(2 * c + 1)]);
            const int cnt = two[std::size_t(c)] ? 2 : 1;
            for (int i = 0; i < cnt; ++i) {
                const std::size_t j = std::size_t(2 * c + i);
                ds[j] = cp(dp, c, i) + rp[j];
                dy[j] = -(rc[j] + y[j] * ds[j]) / s[j];
            }
        }
        for (double v : dp) if (!std::isfinite(v)) return false;
        return true;
    };
    auto maxStep = [&](const std::vector<double>& v, const std::vector<double>& dv) {
        double a = 1.0;
        for (int c = 0; c < nc; ++c) {
            const int cnt = two[std::size_t(c)] ? 2 : 1;
            for (int i = 0; i < cnt; ++i) {
                const std::size_t j = std::size_t(2 * c + i);
                if (dv[j] < 0.0) a = std::min(a, -v[j] / dv[j]);
            }
        }
        return a;
    };
    // The values of the analysed system for the current hinv: the entries the factorisation reads, contact by
    // contact (readStart), with the products of H and the rows shared by a contact's entries computed once.
    auto fillRead = [&](double* values) {
        for (int c = 0; c < nc; ++c) {
            const int first = readStart[std::size_t(c)], last = readStart[std::size_t(c) + 1];
            if (first == last) continue;
            const ContactRows& q = contactRows[std::size_t(c)];
            const double* H = &hinv[std::size_t(3 * c)];
            double na[6], ta[6], hn[6], ht[6];  // by side * 3 + component
            for (int sd = 0; sd < 2; ++sd) {
                for (int a = 0; a < 3; ++a) {
                    const double nv = q.n[sd][a], tv = q.t[sd][a];
                    na[3 * sd + a] = nv;
                    ta[3 * sd + a] = tv;
                    hn[3 * sd + a] = H[0] * nv + H[1] * tv;
                    ht[3 * sd + a] = H[1] * nv + H[2] * tv;
                }
            }
            for (int r = first; r < last; ++r) {
                const unsigned code = readCode[std::size_t(r)];
                const unsigned ia = code >> 4, ib = code & 15u;
                values[readPos[std::size_t(r)]] += na[ia] * hn[ib] + ta[ia] * ht[ib];
            }
        }
    };
    // The first of the sorted rows [first, last) that is not below `row` (a column of Kb holds a few bodies' components).
    auto rowAtOrAfter = [](const int* first, const int* last, int row) {
        while (first != last && *first < row) ++first;
        return first;
    };
    // The mass diagonal of Kb's values (the rest 0).
    auto fillMass = [&](double* values) {
        std::fill(values, values + Kb.nonZeros(), 0.0);
        for (int k = 0; k < nb; ++k) {
            const int d = dof[std::size_t(k)];
            if (d < 0) continue;
            const ResolverBody<D>& B = bodies[std::size_t(k)];
            const double inv[3] = {B.invMass, B.invMass, B.invInertia};
            for (int a = 0; a < 3; ++a) values[diagPos[std::size_t(d + a)]] += inv[a] > 0.0 ? 1.0 / inv[a] : 1.0;
        }
    };
    // Kb = M + J^T E J for per-contact 2 x 2 blocks E (row-major, stride 4) that need not be symmetric: every entry
    // of the pattern, for an LU factorisation.
    auto fillFull = [&](const std::vector<double>& E4) {
        double* values = Kb.valuePtr();
        fillMass(values);
        const int* rows = Kb.innerIndexPtr();
        const int* cols = Kb.outerIndexPtr();
        for (int c = 0; c < nc; ++c) {
            const double* E = &E4[std::size_t(4 * c)];
            if (E[0] == 0.0 && E[1] == 0.0 && E[2] == 0.0 && E[3] == 0.0) continue;
            const ContactRows& q = contactRows[std::size_t(c)];
            for (int sb = 0; sb < 2; ++sb) {
                const int db = q.d[sb];
                if (db < 0) continue;
                for (int bb = 0; bb < 3; ++bb) {
                    if (locked[std::size_t(db + bb)]) continue;
                    const double en = E[0] * q.n[sb][bb] + E[1] * q.t[sb][bb];
                    const double et = E[2] * q.n[sb][bb] + E[3] * q.t[sb][bb];
                    const int col = db + bb;
                    for (int sa = 0; sa < 2; ++sa) {
                        const int da = q.d[sa];
                        if (da < 0) continue;
                        // The column holds the moving components of each body its own shares a contact with, in
                        // order: those of da's body follow one another.
                        const int* at = rowAtOrAfter(rows + cols[col], rows + cols[col + 1], da);
                        for (int a = 0; a < 3; ++a) {
                            if (locked[std::size_t(da + a)]) continue;
                            values[at - rows] += q.n[sa][a] * en + q.t[sa][a] * et;
                            ++at;
                        }
                    }
                }
            }
        }
    };
    // Kb's values for the current hinv: the mass diagonal, then each contact's entries where the factorisation reads
    // them, in contact order (the sums and their order of an assembly of all the entries; the rest stay 0).
    auto fillSystem = [&]() {
        double* values = Kb.valuePtr();
        fillMass(values);
        fillRead(values);
    };
    // Kb's pattern, its analysis and the lists above, from the bodies' contact graph: column d + a of a body whose
    // first degree of freedom is d holds, for the body and each body it shares a contact with (ascending), the rows of
    // their components that move; a component that does not move has its diagonal only. The pattern of all the
    // contacts' 3 x 3 blocks J^T H^-1 J and the mass diagonal. A call whose contacts couple the same degrees of
    // freedom as the last call's (a pile's next landing step with the same contacts) keeps all of it.
    auto buildSystem = [&]() {
        std::vector<int>& key = sc.planKey;
        std::vector<int> now;
        now.reserve(std::size_t(3 * nc) + 1);
        now.push_back(ndof);
        for (int c = 0; c < nc; ++c) {
            const ContactRows& q = contactRows[std::size_t(c)];
            now.push_back(q.d[0]);
            now.push_back(q.d[1]);
            now.push_back(int(q.lockedMask));
        }
        if (now == key && Kb.rows() == ndof) {
            ++sc.refills;
            kbFactor.keepAnalysis(cache);
            return;
        }
        key.swap(now);
        const int slots = ndof / 3;
        std::vector<int>& nbrStart = sc.nbrStart;
        std::vector<int>& nbr = sc.nbr;
        nbrStart.assign(std::size_t(slots) + 1, 0);
        for (int c = 0; c < nc; ++c) {
            const ContactRows& q = contactRows[std::size_t(c)];
            if (q.d[0] >= 0 && q.d[1] >= 0 && q.d[0] != q.d[1]) {
                ++nbrStart[std::size_t(q.d[0] / 3) + 1];
                ++nbrStart[std::size_t(q.d[1] / 3) + 1];
            }
        }
        for (int k = 0; k < slots; ++k) nbrStart[std::size_t(k) + 1] += nbrStart[std::size_t(k)] + 1;  // + itself
        nbr.assign(std::size_t(nbrStart[std::size_t(slots)]), 0);
        std::vector<int> fillAt(nbrStart.begin(), nbrStart.end() - 1);
        for (int k = 0; k < slots; ++k) nbr[std::size_t(fillAt[std::size_t(k)]++)] = 3 * k;
        for (int c = 0; c < nc; ++c) {
            const ContactRows& q = contactRows[std::size_t(c)];
            if (q.d[0] >= 0 && q.d[1] >= 0 && q.d[0] != q.d[1]) {
                nbr[std::size_t(fillAt[std::size_t(q.d[0] / 3)]++)] = q.d[1];
                nbr[std::size_t(fillAt[std::size_t(q.d[1] / 3)]++)] = q.d[0];
            }
        }
        std::vector<int>& outer = sc.outer;
        std::vector<int>& inner = sc.inner;
        outer.assign(std::size_t(ndof) + 1, 0);
        inner.clear();
        for (int k = 0; k < slots; ++k) {
            int* first = nbr.data() + nbrStart[std::size_t(k)];
            int* last = nbr.data() + nbrStart[std::size_t(k) + 1];
            std::sort(first, last);
            last = std::unique(first, last);
            for (int a = 0; a < 3; ++a) {
                const int col = 3 * k + a;
                if (locked[std::size_t(col)]) {
                    inner.push_back(col);
                } else {
                    for (const int* e = first; e != last; ++e)
                        for (int b = 0; b < 3; ++b)
                            if (!locked[std::size_t(*e + b)]) inner.push_back(*e + b);
                }
                outer[std::size_t(col) + 1] = int(inner.size());
            }
        }
        Kb.resize(ndof, ndof);
        Kb.resizeNonZeros(Eigen::Index(inner.size()));
        std::copy(outer.begin(), outer.end(), Kb.outerIndexPtr());
        std::copy(inner.begin(), inner.end(), Kb.innerIndexPtr());
        // A new contact graph (a landing: the pattern of the next call is usually this one, which the refill above
        // keeps, or a newer one; measured: 1 of 60+ analyses of the 20- to 40-row pyramids and the 2000-circle pile
        // found in the cache) is analysed without being kept there.
        kbFactor.analyzePatternOnce(Kb, cache);
        auto place = [&](int row, int col) {
            const int* rows = Kb.innerIndexPtr();
            return int(rowAtOrAfter(rows + Kb.outerIndexPtr()[col], rows + Kb.outerIndexPtr()[col + 1], row) -
                       rows);
        };
        diagPos.resize(std::size_t(ndof));
        for (int i = 0; i < ndof; ++i) diagPos[std::size_t(i)] = place(i, i);
        // Written without branching on which entries the factorisation reads (about half, in no pattern): every
        // entry goes to the next place, which then moves on only when it is read. The lists only grow (readStart
        // gives their used part).
        if (readPos.size() < std::size_t(36 * nc)) readPos.resize(std::size_t(36 * nc));
        if (readCode.size() < std::size_t(36 * nc)) readCode.resize(std::size_t(36 * nc));
        readStart.assign(std::size_t(nc) + 1, 0);
        std::size_t entries = std::size_t(ndof);
        std::size_t reads = 0;
        const int* kbOuter = Kb.outerIndexPtr();
        const int* order = kbFactor.symmetricOrder();  // nullptr: every entry is read
        for (int c = 0; c < nc; ++c) {
            const ContactRows& q = contactRows[std::size_t(c)];
            const std::size_t first = reads;
            for (int sa = 0; sa < 2; ++sa) {
                const int da = q.d[sa];
                if (da < 0) continue;
                for (int sb = 0; sb < 2; ++sb) {
                    const int db = q.d[sb];
                    if (db < 0) continue;
                    // Every moving column of db's body holds the same rows (see above): da's moving components, in
                    // order, from the same offset; found once in the first such column.
                    int offset = 0;
                    for (int bb = 0; bb < 3; ++bb) {
                        if (locked[std::size_t(db + bb)]) continue;
                        offset = place(da, db + bb) - kbOuter[db + bb];
                        break;
                    }
                    int rank = 0;  // a's place among da's moving components
                    for (int a = 0; a < 3; ++a) {
                        if (locked[std::size_t(da + a)]) continue;
                        const int at = offset + rank++;
                        const int ia = da + a;
                        for (int bb = 0; bb < 3; ++bb) {
                            if (locked[std::size_t(db + bb)]) continue;
                            ++entries;
                            const bool read = !order || order[ia] <= order[db + bb];
                            readPos[reads] = kbOuter[db + bb] + at;
                            readCode[reads] = std::uint8_t((sa * 3 + a) << 4 | (sb * 3 + bb));
                            reads += read ? 1 : 0;
                        }
                    }
                }
            }
            readStart[std::size_t(c) + 1] = int(reads - first);
        }
        for (int c = 0; c < nc; ++c) readStart[std::size_t(c) + 1] += readStart[std::size_t(c)];
        sc.entryCount = entries;
    };
    double mu0 = 0.0;
    constexpr int kInteriorIterations = 40;
    constexpr double kStableGap = 1e-8;
    // The face step (below): tried once the gap is this far below its start, with this proximal term relative
    // to each contact's diagonal, at most this many solves with its factors, and given up after the first solve
    // when that is above kFaceHope tolerances; at most kFaceTries faces per solve.
    constexpr double kFaceGap = 1e-3, kFaceEps = 1e-6, kFaceHope = 1e4;
    constexpr int kFaceSolves = 3, kFaceTries = 3;
    // Bit 0: the first constraint is active (its slack small against its multiplier), bit 1: the second.
    auto activeOf = [&](int c) -> std::uint8_t {
        const double gn = diag[std::size_t(2 * c)];
        const bool a0 = s[std::size_t(2 * c)] * gn <= y[std::size_t(2 * c)];
        const bool a1 = two[std::size_t(c)] && s[std::size_t(2 * c + 1)] * gn <= y[std::size_t(2 * c + 1)];
        return std::uint8_t((a0 ? 1 : 0) | (a1 ? 2 : 0));
    };
    // The face step: the answer on the face of the iterate's active constraints, from one factorisation of the
    // same body-space system. Separated contacts keep p = 0, the others are free within their active constraints
    // (a slipping contact on its edge of the cone), and a proximal term eps G |p - p^|^2 selects among the face's
    // answers (a pile's rows are redundant, so there are many), p^ the iterate projected onto the face. Each solve
    // is a proximal step from the last answer pf, computed from its velocities u (matrix-free, so the step's own
    // rounding does not accumulate): per contact dp = -E (u + J dv) with E = B R / (eps G), B a basis of its free
    // directions and R the velocity rows they answer (B^T with B orthonormal, except on the LCP's rim equation
    // below), and (M + J^T E J) dv = -J^T E u. The system is M + J^T H^-1 J with E in place of H^-1, so the
    // iteration's analysis serves it. The iterate has the answer's face well before it certifies:
    // degenerate contacts (no load, no approach) keep impulse and velocity both near the gap's square root, so the
    // gap would have to fall several more orders (measured on a landing 20-row pyramid: 157 iterations and 38 face
    // steps where the iteration alone took 282); the face step ends the iteration there.
    std::vector<double> faceH(std::size_t(3 * nc), 0.0), faceE(std::size_t(4 * nc), 0.0);
    std::vector<double> pf(std::size_t(2 * nc), 0.0), uf(std::size_t(2 * nc), 0.0);
    auto faceStep = [&]() -> bool {
        if (!analysed || ndof == 0) return false;
        // A contact on one edge of its cone, p = (1, sgn mu) q, solves the LCP's rim equation u_n = 0 (dq = -(u_n +
        // J_n dv) / (eps G_nn)) once some contact on a rim slips by more than the tolerance; until then the
        // relaxation's u_n + sgn mu u_t = 0, E = w (1, sgn mu)^T (1, sgn mu) / (1 + mu^2) with p^ the iterate's
        // projection onto the edge (the same answers there, and a symmetric system).
        bool slips = false;
        for (int c = 0; c < nc && !slips; ++c) {
            const std::uint8_t act = activeOf(c);
            slips = two[std::size_t(c)] && (act == 1 || act == 2) && std::fabs(uu[std::size_t(2 * c + 1)]) > tolAbs;
        }
        for (int c = 0; c < nc; ++c) {
            const std::uint8_t act = activeOf(c);
            const double pn = p[std::size_t(2 * c)], pt = p[std::size_t(2 * c + 1)];
            const double w = 1.0 / (kFaceEps * diag[std::size_t(2 * c)]);
            double* E = &faceE[std::size_t(4 * c)];
            double* ph = &pf[std::size_t(2 * c)];  // the iterate projected onto the face
            E[0] = E[1] = E[2] = E[3] = 0.0;
            ph[0] = ph[1] = 0.0;
            if (!two[std::size_t(c)]) {
                if (!(act & 1)) {
                    E[0] = w;
                    ph[0] = pn;
                }
            } else if (act == 0) {
                E[0] = E[3] = w;
                ph[0] = pn;
                ph[1] = pt;
            } else if (act != 3) {
                const double mu = friction[std::size_t(c)];
                const double sgn = act == 1 ? 1.0 : -1.0;
                if (slips) {
                    E[0] = w;
                    E[2] = w * sgn * mu;
                    ph[0] = pn;
                    ph[1] = sgn * mu * pn;
                } else {
                    const double k = 1.0 / (1.0 + mu * mu);
                    E[0] = w * k;
                    E[1] = E[2] = w * k * sgn * mu;
                    E[3] = w * k * mu * mu;
                    const double along = (pn + sgn * mu * pt) * k;
                    ph[0] = along;
                    ph[1] = sgn * mu * along;
                }
            }
            double* H = &faceH[std::size_t(3 * c)];  // the symmetric form's H^-1 entries (used without slips)
            H[0] = E[0];
            H[1] = E[1];
            H[2] = E[3];
        }
        if (!slips) {
            hinv.swap(faceH);
            fillSystem();
            hinv.swap(faceH);
            if (!kbFactor.factorize(Kb, true)) return false;
        } else {
            fillFull(faceE);  // not symmetric
            if (!kbFactor.factorize(Kb, false)) return false;
        }
        work += std::uint64_t(Kb.nonZeros()) + 8 * std::uint64_t(kbFactor.factorNonZeros()) +
                2 * std::uint64_t(sc.entryCount);
        Eigen::VectorXd rv(ndof);
        std::vector<double> firstAnswer;
        velocities(pf, uf);
        work += rowWork;
        for (int solve = 0; solve < kFaceSolves; ++solve) {
            std::fill(moment.begin(), moment.end(), 0.0);
            for (int c = 0; c < nc; ++c) {
                const double* E = &faceE[std::size_t(4 * c)];
                if (E[0] == 0.0 && E[3] == 0.0) continue;
                const double un = uf[std::size_t(2 * c)], ut = uf[std::size_t(2 * c + 1)];
                addRows(c, -(E[0] * un + E[1] * ut), -(E[2] * un + E[3] * ut));
            }
            for (int i = 0; i < ndof; ++i) rv[i] = moment[std::size_t(i)];
            const Eigen::VectorXd dv = kbFactor.solve(rv);
            work += 4 * std::uint64_t(kbFactor.factorNonZeros()) + 2 * rowWork;
            for (int c = 0; c < nc; ++c) {
                const double* E = &faceE[std::size_t(4 * c)];
                if (E[0] == 0.0 && E[3] == 0.0) continue;
                const double jn = uf[std::size_t(2 * c)] + rowDot(c, 0, dv);
                const double jt = uf[std::size_t(2 * c + 1)] + rowDot(c, 1, dv);
                pf[std::size_t(2 * c)] -= E[0] * jn + E[1] * jt;
                pf[std::size_t(2 * c + 1)] -= E[2] * jn + E[3] * jt;
            }
            for (double v : pf) if (!std::isfinite(v)) return false;
            velocities(pf, uf);
            const double r = lcpResidual(pf, uf);
            // The first step's answer, when it certifies, gets one more step (its velocities are at the
            // tolerance, the next one's usually 100x below it), and stays the answer if that one does not certify.
            if (r <= tolAbs && solve > 0) return true;
            if (r <= tolAbs) {
                firstAnswer = pf;
                continue;
            }
            if (!firstAnswer.empty()) {
                pf = firstAnswer;
                return true;
            }
            // A face whose first step is this far off is not the answer's (measured: 12-370 tolerances where
            // the next step certifies, above 1e6 where none does).
            if (r > kFaceHope * tolAbs) return false;
        }
        return false;
    };
    std::vector<std::uint8_t> cls(static_cast<std::size_t>(nc), 0), prevCls(static_cast<std::size_t>(nc), 255);
    int faceWait = 0, faceSkip = 0, faceTries = 0;
    double lastMub = std::numeric_limits<double>::infinity();
    std::vector<double> uTrue(std::size_t(2 * nc));
    // The answer of the iteration, rounded onto its active constraints (a sliding contact on its edge of the cone).
    auto rounded = [&](std::vector<double>& out) {
        for (int c = 0; c < nc; ++c) {
            double pn = p[std::size_t(2 * c)], pt = p[std::size_t(2 * c + 1)];
            const std::uint8_t act = activeOf(c);
            const bool a0 = (act & 1) != 0, a1 = (act & 2) != 0;
            const double mu = friction[std::size_t(c)];
            if (!two[std::size_t(c)]) {
                if (a0) pn = 0.0;
                pt = 0.0;
            } else if (a0 && a1) {
                pn = pt = 0.0;
            } else if (a0) {
                pt = mu * std::max(pn, 0.0);
            } else if (a1) {
                pt = -mu * std::max(pn, 0.0);
            }
            out[std::size_t(2 * c)] = pn;
            out[std::size_t(2 * c + 1)] = pt;
        }
    };
    // Rounds: the relaxation's answer lets a sliding contact separate at mu |u_t| where the island's LCP keeps it
    // touching (u_n = 0). When the first round's answer does not certify and some pushing contact slides by more
    // than the tolerance, the next rounds solve the relaxation again from the start with mu |u_t| of the last
    // round's answer added to each contact's normal velocity (de Saxce's fixed point: a relaxation whose answer
    // keeps that slip is the LCP's). The face step then gets the LCP's faces. On a landing pile of circles the LCP's
    // residual of the rounds' answers falls by about half a round; the best rounded answer (smallest LCP residual
    // of its iterate) goes to the active-set iteration.
    constexpr int kRounds = 4;
    bool haveBest = false;  // xOut holds a rounded answer of an earlier round
    double bestRaw = std::numeric_limits<double>::infinity();
    for (int round = 0; round < kRounds; ++round) {
        if (round > 0) {
            interiorPointStartingPoint(friction, two, diag, v0, m, nullptr, velocities, p, s, y, uu);  // cold
            faceWait = faceSkip = faceTries = 0;
            lastMub = std::numeric_limits<double>::infinity();
            std::fill(prevCls.begin(), prevCls.end(), std::uint8_t(255));
        }
        bool broke = false;  // the iteration stopped early (the failures below): the round gives no answer
        for (int it = 0; it < kInteriorIterations; ++it) {
            if (maxWork > 0 && work >= maxWork) return haveBest;
            velocities(p, uu);
            work += rowWork;
            if (round > 0) {
                uTrue = uu;
                for (int c = 0; c < nc; ++c) uu[std::size_t(2 * c)] += shift[std::size_t(c)];
            }
            double gap = 0.0, rdMax = 0.0, rpMax = 0.0;
            for (int c = 0; c < nc; ++c) {
                const double ys0 = y[std::size_t(2 * c)], ys1 = y[std::size_t(2 * c + 1)];
                if (two[std::size_t(c)]) {
                    rd[std::size_t(2 * c)] = uu[std::size_t(2 * c)] - friction[std::size_t(c)] * (ys0 + ys1);
                    rd[std::size_t(2 * c + 1)] = uu[std::size_t(2 * c + 1)] + ys0 - ys1;
                } else {
                    rd[std::size_t(2 * c)] = uu[std::size_t(2 * c)] - ys0;
                    rd[std::size_t(2 * c + 1)] = 0.0;  // p_t stays 0 (H^-1 has no tangent part)
                }
                rdMax = std::max({rdMax, std::fabs(rd[std::size_t(2 * c)]), std::fabs(rd[std::size_t(2 * c + 1)])});
                const int cnt = two[std::size_t(c)] ? 2 : 1;
                for (int i = 0; i < cnt; ++i) {
                    const std::size_t j = std::size_t(2 * c + i);
                    rp[j] = cp(p, c, i) - s[j];
                    rpMax = std::max(rpMax, std::fabs(rp[j]) * diag[std::size_t(2 * c)]);
                    gap += s[j] * y[j];
                }
            }
            const double mub = gap / double(m);
            if (it == 0) mu0 = warmStart && round == 0 ? mu0Cold : mub;
            // The face step, once the gap is small; after each attempt that does not certify, the next waits twice
            // as many iterations as the last wait plus one (1, 3 apart). On the landing 20-row pyramid no solve
            // needed a fourth; a cap of two costs it 6 % more instructions. The Box2D-manifold pyramid's frictionless
            // LCP, whose float-rounded rows are nearly dependent, certifies at no face: its three cost 10 % (22
            // iterations).
            if (it > 0 && mub <= kFaceGap * mu0 && faceTries < kFaceTries) {
                if (faceWait == 0) {
                    ++faceTries;
                    if (faceStep()) {
                        xOut = pf;
                        return true;
                    }
                    faceWait = faceSkip;
                    faceSkip = 2 * faceSkip + 1;
                } else {
                    --faceWait;
                }
            }
            if (mub <= kStableGap * mu0) {
                // Once the gap is small, an iterate that answers the LCP ends the iteration as it stands.
                const double raw = lcpResidual(p, round > 0 ? uTrue : uu);
                work += rowWork;
                if (raw <= tolAbs) {
                    xOut = p;
                    return true;
                }
                // Without friction the relaxation is the LCP itself, and its iterate certifies once every
                // contact's impulse or velocity is within the tolerance: a few iterations after the gap is at the
                // data's precision (a contact without load or approach keeps both at about the square root of the
                // gap). The rounding below can class a slowly separating contact as pushing before then, and the
                // face it gives does not hold; so such an island goes on while its gap still falls at least twofold
                // an iteration.
                const bool onTheWay = frictionless && mub <= 0.5 * lastMub;
                lastMub = mub;
                if (!onTheWay) {
                    // Stop when the active constraints are those of the last iteration (the active-set iteration
                    // finishes from there), or once converged to the data's precision.
                    for (int c = 0; c < nc; ++c) cls[std::size_t(c)] = activeOf(c);
                    if (cls == prevCls) break;
                    prevCls = cls;
                    if (mub <= 1e-12 * mu0 && rdMax <= 1e-10 * v0 && rpMax <= 1e-10 * v0) break;
                }
            }
            // H^-1 per contact from e = s / y (capped: a contact inside its cone becomes a stiff constraint).
            for (int c = 0; c < nc; ++c) {
                const double gn = diag[std::size_t(2 * c)];
                const int cnt = two[std::size_t(c)] ? 2 : 1;
                for (int i = 0; i < cnt; ++i) {
                    const std::size_t j = std::size_t(2 * c + i);
                    e[j] = std::min(s[j] / y[j], 1e12 / gn);
                }
                double* H = &hinv[std::size_t(3 * c)];
                if (two[std::size_t(c)]) {
                    const double mu = friction[std::size_t(c)];
                    const double e0 = e[std::size_t(2 * c)], e1 = e[std::size_t(2 * c + 1)];
                    H[0] = (e0 + e1) / (4.0 * mu * mu);
                    H[1] = (e1 - e0) / (4.0 * mu);
                    H[2] = (e0 + e1) / 4.0;
                } else {
                    H[0] = e[std::size_t(2 * c)];
                    H[1] = H[2] = 0.0;
                }
            }
            if (ndof > 0) {
                if (!analysed) buildSystem();
                analysed = true;
                fillSystem();
                if (!kbFactor.factorize(Kb, true)) {
                    broke = true;
                    break;
                }
                work += std::uint64_t(Kb.nonZeros()) + 8 * std::uint64_t(kbFactor.factorNonZeros()) +
                        2 * std::uint64_t(sc.entryCount);  // every entry counts in the work, read or not
            }
            // Predictor (affine scaling).
            for (std::size_t j = 0; j < rc.size(); ++j) rc[j] = s[j] * y[j];
            if (!direction()) {
                broke = true;
                break;
            }
            const double ap = maxStep(s, ds), ad = maxStep(y, dy);
            const double aAff = std::min(ap, ad);
            double gapAff = 0.0;
            for (std::size_t j = 0; j < s.size(); ++j) gapAff += (s[j] + aAff * ds[j]) * (y[j] + aAff * dy[j]);
            const double ratio = gapAff / double(m) / mub;
            const double sigma = ratio * ratio * ratio;
            dsAff = ds;
            dyAff = dy;
            // Corrector.
            for (int c = 0; c < nc; ++c) {
                const int cnt = two[std::size_t(c)] ? 2 : 1;
                for (int i = 0; i < cnt; ++i) {
                    const std::size_t j = std::size_t(2 * c + i);
                    rc[j] = s[j] * y[j] + dsAff[j] * dyAff[j] - sigma * mub;
                }
            }
            if (!direction()) {
                broke = true;
                break;
            }
            const double alpha = std::min(1.0, 0.99 * std::min(maxStep(s, ds), maxStep(y, dy)));
            for (std::size_t j = 0; j < p.size(); ++j) {
                p[j] += alpha * dp[j];
                s[j] += alpha * ds[j];
                y[j] += alpha * dy[j];
            }
        }
        if (broke) return haveBest;
        // Another round when a pushing contact slides by more than the tolerance (read off the last iteration's
        // velocities: the iteration stops with them current). Without one the round's answer is the last.
        bool slides = false;
        if (!frictionless && round + 1 < kRounds)
            for (int c = 0; c < nc && !slides; ++c) {
                const std::uint8_t act = activeOf(c);  // one edge of the cone active: the contact slides
                slides = two[std::size_t(c)] && (act == 1 || act == 2) &&
                         friction[std::size_t(c)] * std::fabs(uu[std::size_t(2 * c + 1)]) > tolAbs;
            }
        if (!slides && !haveBest) {
            rounded(xOut);
            return true;
        }
        velocities(p, uTrue);
        work += rowWork;
        const double raw = lcpResidual(p, uTrue);
        if (raw <= tolAbs) {
            xOut = p;
            return true;
        }
        if (raw < bestRaw) {
            bestRaw = raw;
            rounded(xOut);
            haveBest = true;
        }
        if (!slides) break;
        for (int c = 0; c < nc; ++c)
            shift[std::size_t(c)] = two[std::size_t(c)] ? friction[std::size_t(c)] * std::fabs(uTrue[std::size_t(2 * c + 1)]) : 0.0;
    }
    return haveBest;
}

}  // namespace detail
}  // namespace unison
