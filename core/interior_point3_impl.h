// core/interior_point3_impl.h — the 3D active-set path's interior-point restart (core/active_set3_impl.h): the
// convex relaxation of a contact LCP whose friction sets are boxes |g_r| <= mu p_n in the path's coordinates (four
// constraints per contact), by Mehrotra's predictor-corrector method in the bodies' normalised degrees of freedom, as
// core/interior_point_impl.h does in 2D. Included by core/active_set3_impl.h only.
#pragma once

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "body_space_solve.h"
#include "symmetric_pattern_lu.h"

namespace unison {
namespace detail {

// One contact's three rows in the normalised degrees of freedom: 0 the normal, 1 (t1 + t2) / 2, 2 (t1 - t2) / 2.
// Per side its body's first degree of freedom (-1: immovable) and 6 components.
struct BoxContactRows {
    int d[2];
    double j[3][2][6];
};

// J~^T h for one contact (h per row) added to `moment`.
inline void addBoxRows(const BoxContactRows& q, const double h[3], double* moment) {
    for (int r = 0; r < 3; ++r) {
        const double v = h[r];
        if (v == 0.0) continue;
        for (int s = 0; s < 2; ++s) {
            if (q.d[s] < 0) continue;
            double* m = moment + q.d[s];
            for (int a = 0; a < 6; ++a) m[a] += v * q.j[r][s][a];
        }
    }
}

inline double boxRowDot(const BoxContactRows& q, int r, const double* v) {
    double sum = 0.0;
    for (int s = 0; s < 2; ++s) {
        if (q.d[s] < 0) continue;
        const double* x = v + q.d[s];
        for (int a = 0; a < 6; ++a) sum += q.j[r][s][a] * x[a];
    }
    return sum;
}

// The interior-point answer of the convex relaxation min 1/2 p^T A p + b^T p over |g_r| <= mu p_n (p_n >= 0 where a
// contact has no friction), Mehrotra's predictor-corrector as core/interior_point_impl.h in 2D; p = (p_n, g1, g2) per
// contact. Rounded onto its active constraints unless an iterate answers the LCP within tolAbs. `velocities` is
// called once per iteration, first thing, and may move b (the caller's de Saxce shift; `lcpResidual` then undoes it).
template <class Velocities, class Residual>
bool boxInteriorPoint(const std::vector<BoxContactRows>& rows, const std::vector<double>& mu,
                      const std::vector<std::uint8_t>& frictional, const std::vector<double>& diag, int ndof,
                      double bMax, const Velocities& velocities, const Residual& lcpResidual, double tolAbs,
                      std::uint64_t rowWork, SymmetricPatternCache* cache, std::uint64_t maxWork, std::uint64_t& work,
                      std::vector<double>& xOut) {
    const int nc = int(rows.size());
    int m = 0;
    for (int c = 0; c < nc; ++c) m += frictional[std::size_t(c)] ? 4 : 1;
    const double v0 = std::max(bMax, 1e-6);
    const std::size_t n3 = std::size_t(3 * nc), n4 = std::size_t(4 * nc);
    std::vector<double> p(n3, 0.0), uu(n3), rd(n3), g(n3), dp(n3), hinv(std::size_t(6 * nc), 0.0);
    std::vector<double> s(n4, 0.0), y(n4, 0.0), rp(n4, 0.0), rc(n4, 0.0), ds(n4, 0.0), dy(n4, 0.0);
    std::vector<double> dsAff(n4, 0.0), dyAff(n4, 0.0);
    auto count = [&](int c) { return frictional[std::size_t(c)] ? 4 : 1; };
    for (int c = 0; c < nc; ++c) {
        for (int i = 0, cnt = count(c); i < cnt; ++i) {
            const std::size_t jj = std::size_t(4 * c + i);
            s[jj] = v0 / diag[std::size_t(3 * c)];
            y[jj] = v0;
        }
    }
    // Row i of C q for contact c: p_n without friction; mu p_n - g1, mu p_n + g1, mu p_n - g2, mu p_n + g2.
    auto cp = [&](const std::vector<double>& q, int c, int i) {
        const double pn = q[std::size_t(3 * c)];
        if (!frictional[std::size_t(c)]) return pn;
        const double gr = q[std::size_t(3 * c + 1 + i / 2)];
        return mu[std::size_t(c)] * pn + ((i & 1) ? gr : -gr);
    };
    // C^T w for contact c (w per constraint).
    auto ctw = [&](int c, const double* w, double out[3]) {
        if (!frictional[std::size_t(c)]) {
            out[0] = w[0];
            out[1] = out[2] = 0.0;
            return;
        }
        out[0] = mu[std::size_t(c)] * (w[0] + w[1] + w[2] + w[3]);
        out[1] = w[1] - w[0];
        out[2] = w[3] - w[2];
    };
    auto applyHinv = [&](int c, const double in[3], double out[3]) {
        const double* H = &hinv[std::size_t(6 * c)];  // 00 01 02 11 12 22
        out[0] = H[0] * in[0] + H[1] * in[1] + H[2] * in[2];
        out[1] = H[1] * in[0] + H[3] * in[1] + H[4] * in[2];
        out[2] = H[2] * in[0] + H[4] * in[1] + H[5] * in[2];
    };
    // The body-space matrix I + J~^T H^-1 J~: a fixed pattern (each contact couples its bodies' degrees of freedom),
    // assembled and analysed on the first iteration; on every later one each contact's values are added, in the same
    // order, only where its L D L^T factorisation reads them (readPlace: one of each symmetric pair, per contact value
    // in the order computed).
    std::vector<Eigen::Triplet<double>> kt;
    std::vector<int> kpos, readPlace;
    Eigen::SparseMatrix<double> Kb;
    ColumnAssembly assembly;
    SymmetricPatternLu factor;
    bool analysed = false;
    std::vector<double> moment(std::size_t(std::max(ndof, 1)));
    Eigen::VectorXd rv(ndof), dv(ndof);
    auto direction = [&]() -> bool {
        std::fill(moment.begin(), moment.end(), 0.0);
        for (int c = 0; c < nc; ++c) {
            double w[4] = {0.0, 0.0, 0.0, 0.0}, cw[3], hg[3];
            for (int i = 0, cnt = count(c); i < cnt; ++i) {
                const std::size_t jj = std::size_t(4 * c + i);
                w[i] = (rc[jj] + y[jj] * rp[jj]) / s[jj];
            }
            ctw(c, w, cw);
            for (int r = 0; r < 3; ++r) g[std::size_t(3 * c + r)] = -rd[std::size_t(3 * c + r)] - cw[r];
            applyHinv(c, &g[std::size_t(3 * c)], hg);
            addBoxRows(rows[std::size_t(c)], hg, moment.data());
        }
        for (int i = 0; i < ndof; ++i) rv[i] = moment[std::size_t(i)];
        if (ndof > 0) dv = factor.solve(rv);
        work += 4 * std::uint64_t(factor.factorNonZeros()) + rowWork;
        for (int c = 0; c < nc; ++c) {
            double rest[3];
            for (int r = 0; r < 3; ++r)
                rest[r] = g[std::size_t(3 * c + r)] - (ndof > 0 ? boxRowDot(rows[std::size_t(c)], r, dv.data()) : 0.0);
            applyHinv(c, rest, &dp[std::size_t(3 * c)]);
            for (int i = 0, cnt = count(c); i < cnt; ++i) {
                const std::size_t jj = std::size_t(4 * c + i);
                ds[jj] = cp(dp, c, i) + rp[jj];
                dy[jj] = -(rc[jj] + y[jj] * ds[jj]) / s[jj];
            }
        }
        for (double v : dp)
            if (!std::isfinite(v)) return false;
        return true;
    };
    auto maxStep = [&](const std::vector<double>& v, const std::vector<double>& dvv) {
        double a = 1.0;
        for (int c = 0; c < nc; ++c) {
            for (int i = 0, cnt = count(c); i < cnt; ++i) {
                const std::size_t jj = std::size_t(4 * c + i);
                if (dvv[jj] < 0.0) a = std::min(a, -v[jj] / dvv[jj]);
            }
        }
        return a;
    };
    // Bit i: constraint i is active (its slack small against its multiplier).
    auto activeOf = [&](int c) -> std::uint8_t {
        const double gn = diag[std::size_t(3 * c)];
        std::uint8_t bits = 0;
        for (int i = 0, cnt = count(c); i < cnt; ++i) {
            const std::size_t jj = std::size_t(4 * c + i);
            if (s[jj] * gn <= y[jj]) bits = std::uint8_t(bits | (1u << i));
        }
        return bits;
    };
    constexpr int kInteriorIterations = 40;
    constexpr double kStableGap = 1e-8;
    std::vector<std::uint8_t> cls(static_cast<std::size_t>(nc), 0), prevCls(static_cast<std::size_t>(nc), 255);
    const bool frictionless = m == nc;
    double mu0 = 0.0, lastMub = std::numeric_limits<double>::infinity();
    for (int it = 0; it < kInteriorIterations; ++it) {
        if (maxWork > 0 && work >= maxWork) return false;
        velocities(p, uu);
        work += rowWork;
        double gap = 0.0, rdMax = 0.0, rpMax = 0.0;
        for (int c = 0; c < nc; ++c) {
            const double* yc = &y[std::size_t(4 * c)];
            double cy[3];
            ctw(c, yc, cy);
            for (int r = 0; r < 3; ++r) {
                const std::size_t jj = std::size_t(3 * c + r);
                rd[jj] = frictional[std::size_t(c)] || r == 0 ? uu[jj] - cy[r] : 0.0;  // no friction: g stays 0
                rdMax = std::max(rdMax, std::fabs(rd[jj]));
            }
            for (int i = 0, cnt = count(c); i < cnt; ++i) {
                const std::size_t jj = std::size_t(4 * c + i);
                rp[jj] = cp(p, c, i) - s[jj];
                rpMax = std::max(rpMax, std::fabs(rp[jj]) * diag[std::size_t(3 * c)]);
                gap += s[jj] * y[jj];
            }
        }
        const double mub = gap / double(m);
        if (it == 0) mu0 = mub;
        if (mub <= kStableGap * mu0) {
            const double raw = lcpResidual(p, uu);
            work += rowWork;
            if (raw <= tolAbs) {
                xOut = p;
                return true;
            }
            const bool onTheWay = frictionless && mub <= 0.5 * lastMub;  // as in 2D (interior_point_impl.h)
            lastMub = mub;
            if (!onTheWay) {
                for (int c = 0; c < nc; ++c) cls[std::size_t(c)] = activeOf(c);
                if (cls == prevCls) break;
                prevCls = cls;
                if (mub <= 1e-12 * mu0 && rdMax <= 1e-10 * v0 && rpMax <= 1e-10 * v0) break;
            }
        }
        // H^-1 per contact from e = s / y (capped: a contact inside its box becomes a stiff constraint). With
        // ea = e0 + e1, eb = e2 + e3: the Schur complement of the p_n entry is S = mu^2 (4 / ea + 4 / eb), the
        // coupling a_r = mu (e_(2r-2) - e_(2r-1)) / e_r's pair sum, and H^-1 = [1/S, -a^T/S; -a/S, E + a a^T / S]
        // with E = diag(e0 e1 / ea, e2 e3 / eb).
        for (int c = 0; c < nc; ++c) {
            const double gn = diag[std::size_t(3 * c)];
            double e[4] = {0.0, 0.0, 0.0, 0.0};
            for (int i = 0, cnt = count(c); i < cnt; ++i) {
                const std::size_t jj = std::size_t(4 * c + i);
                e[i] = std::min(s[jj] / y[jj], 1e12 / gn);
            }
            double* H = &hinv[std::size_t(6 * c)];
            if (frictional[std::size_t(c)]) {
                const double mc = mu[std::size_t(c)];
                const double ea = e[0] + e[1], eb = e[2] + e[3];
                const double S = mc * mc * (4.0 / ea + 4.0 / eb);
                const double a1 = mc * (e[0] - e[1]) / ea, a2 = mc * (e[2] - e[3]) / eb;
                H[0] = 1.0 / S;
                H[1] = -a1 / S;
                H[2] = -a2 / S;
                H[3] = e[0] * e[1] / ea + a1 * a1 / S;
                H[4] = a1 * a2 / S;
                H[5] = e[2] * e[3] / eb + a2 * a2 / S;
            } else {
                H[0] = e[0];
                H[1] = H[2] = H[3] = H[4] = H[5] = 0.0;
            }
        }
        if (!analysed) kt.clear();
        double* values = analysed ? Kb.valuePtr() : nullptr;
        if (analysed) std::fill(values, values + Kb.nonZeros(), 0.0);
        const int* readAt = readPlace.data();
        // Per contact J~^T H^-1 J~ on its sides' degrees of freedom: each value computed once, for entry (i, j) with
        // side sa <= side sb (a <= b within one side). The first iteration puts it at (i, j) and (j, i), so K's values
        // are symmetric to the bit, as its L D L^T factorisation takes them; the later ones add it where the
        // factorisation reads it (the same sums in the same order there).
        auto put = [&](int r, int col, double v) {
            if (analysed) {
                values[*readAt++] += v;
                return;
            }
            kt.emplace_back(r, col, v);
            if (r != col) kt.emplace_back(col, r, v);
        };
        if (!analysed)
            for (int i = 0; i < ndof; ++i) kt.emplace_back(i, i, 1.0);
        else
            for (int i = 0; i < ndof; ++i) values[kpos[std::size_t(i)]] += 1.0;
        for (int c = 0; c < nc; ++c) {
            const BoxContactRows& q = rows[std::size_t(c)];
            const double* H = &hinv[std::size_t(6 * c)];
            const double Hm[3][3] = {{H[0], H[1], H[2]}, {H[1], H[3], H[4]}, {H[2], H[4], H[5]}};
            double hj[2][3][6];  // H^-1 J~ per side, row and component
            for (int sb = 0; sb < 2; ++sb) {
                if (q.d[sb] < 0) continue;
                for (int r = 0; r < 3; ++r)
                    for (int b = 0; b < 6; ++b)
                        hj[sb][r][b] = Hm[r][0] * q.j[0][sb][b] + Hm[r][1] * q.j[1][sb][b] + Hm[r][2] * q.j[2][sb][b];
            }
            for (int sa = 0; sa < 2; ++sa) {
                if (q.d[sa] < 0) continue;
                for (int sb = sa; sb < 2; ++sb) {
                    if (q.d[sb] < 0) continue;
                    for (int a = 0; a < 6; ++a)
                        for (int b = sa == sb ? a : 0; b < 6; ++b) {
                            const double v = q.j[0][sa][a] * hj[sb][0][b] + q.j[1][sa][a] * hj[sb][1][b] +
                                             q.j[2][sa][a] * hj[sb][2][b];
                            put(q.d[sa] + a, q.d[sb] + b, v);
                        }
                }
            }
        }
        if (ndof > 0) {
            if (!analysed) {
                analysed = true;
                assembleColumns(ndof, kt, Kb, assembly);
                factor.analyzePattern(Kb, cache);
                kpos.resize(kt.size());
                for (std::size_t t = 0; t < kt.size(); ++t) {
                    const int col = kt[t].col();
                    const int* rws = Kb.innerIndexPtr();
                    const int* at = std::lower_bound(rws + Kb.outerIndexPtr()[col], rws + Kb.outerIndexPtr()[col + 1],
                                                     kt[t].row());
                    kpos[t] = int(at - rws);
                }
                // The contact values in kt after the mass diagonal: one entry on the diagonal, else a pair (i, j),
                // (j, i) of which the factorisation reads one.
                readPlace.clear();
                for (std::size_t t = std::size_t(ndof); t < kt.size(); ++t) {
                    const bool pair = kt[t].row() != kt[t].col();
                    const bool second = pair && !factor.readsSymmetric(kt[t].row(), kt[t].col());
                    readPlace.push_back(kpos[second ? t + 1 : t]);
                    if (pair) ++t;
                }
            }
            if (!factor.factorize(Kb, true)) return false;
            work += std::uint64_t(Kb.nonZeros()) + 8 * std::uint64_t(factor.factorNonZeros()) +
                    2 * std::uint64_t(kt.size());
        }
        // Predictor (affine scaling).
        for (std::size_t jj = 0; jj < rc.size(); ++jj) rc[jj] = s[jj] * y[jj];
        if (!direction()) return false;
        const double aAff = std::min(maxStep(s, ds), maxStep(y, dy));
        double gapAff = 0.0;
        for (std::size_t jj = 0; jj < s.size(); ++jj) gapAff += (s[jj] + aAff * ds[jj]) * (y[jj] + aAff * dy[jj]);
        const double ratio = gapAff / double(m) / mub;
        const double sigma = ratio * ratio * ratio;
        dsAff = ds;
        dyAff = dy;
        // Corrector.
        for (int c = 0; c < nc; ++c) {
            for (int i = 0, cnt = count(c); i < cnt; ++i) {
                const std::size_t jj = std::size_t(4 * c + i);
                rc[jj] = s[jj] * y[jj] + dsAff[jj] * dyAff[jj] - sigma * mub;
            }
        }
        if (!direction()) return false;
        const double alpha = std::min(1.0, 0.99 * std::min(maxStep(s, ds), maxStep(y, dy)));
        for (std::size_t jj = 0; jj < p.size(); ++jj) p[jj] += alpha * dp[jj];
        for (std::size_t jj = 0; jj < s.size(); ++jj) {
            s[jj] += alpha * ds[jj];
            y[jj] += alpha * dy[jj];
        }
    }
    // The answer with the active constraints taken as equalities.
    for (int c = 0; c < nc; ++c) {
        double pn = std::max(p[std::size_t(3 * c)], 0.0);
        double gr[2] = {p[std::size_t(3 * c + 1)], p[std::size_t(3 * c + 2)]};
        const std::uint8_t act = activeOf(c);
        if (!frictional[std::size_t(c)]) {
            if (act & 1) pn = 0.0;
            gr[0] = gr[1] = 0.0;
        } else if ((act & 3) == 3 || (act & 12) == 12) {
            pn = gr[0] = gr[1] = 0.0;
        } else {
            const double bound = mu[std::size_t(c)] * pn;
            for (int r = 0; r < 2; ++r) {
                if (act & (1u << (2 * r))) gr[r] = bound;
                if (act & (2u << (2 * r))) gr[r] = -bound;
            }
        }
        xOut[std::size_t(3 * c)] = pn;
        xOut[std::size_t(3 * c + 1)] = gr[0];
        xOut[std::size_t(3 * c + 2)] = gr[1];
    }
    return true;
}

}  // namespace detail
}  // namespace unison
