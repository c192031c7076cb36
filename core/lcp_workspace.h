// core/lcp_workspace.h — private to core/lcp.cpp: the per-solve state of LemkeSolver (the compact basis block,
// its explicit inverse, the sparsity pattern of A, basic values and their perturbation coefficients) and the
// operations on it. Not part of the public API; include it nowhere else.
#pragma once

#include "lcp.h"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace unison {

namespace lcp_detail {

constexpr double kTiny = 1e-300;

/// A candidate to leave the basis in a ratio test.
struct Candidate {
    bool isColumn;  // true: a basic column variable (z_j or z0) at block position `pos`; false: basic w_i, i = pos
    int pos;
    double ratio;
    double ratio2;  // the same ratio for the epsilon coefficient of the perturbed values (tie-breaker)
    double delta;  // its rate of change as the entering variable grows (< 0 in a min test, > 0 in the start test)
    int var;       // index for the lowest-index rule: j for z_j, n for z0, i for w_i
};

}  // namespace lcp_detail
using lcp_detail::Candidate;
using lcp_detail::kTiny;

namespace lcp_detail {

// A_{alpha,alpha} of a guessed basis, factorised once for a solve and one refinement: a dense LU with partial
// pivoting for small blocks (Eigen's sparse LU costs more than the whole solve there: a one-contact island has a
// 2 x 2 block), Eigen's sparse LU otherwise.
class BlockFactor {
public:
    static constexpr int kDenseMax = 48;

    /// Factorises A(guess, guess) of the compressed rows (rowStart, rowCol, rowVal); pos[j] is j's place in guess.
    bool factor(const std::vector<int>& rowStart, const std::vector<int>& rowCol, const std::vector<double>& rowVal,
                const std::vector<int>& guess, const std::vector<int>& pos) {
        k = int(guess.size());
        dense = k <= kDenseMax;
        if (dense) {
            a.assign(std::size_t(k) * std::size_t(k), 0.0);
            perm.resize(std::size_t(k));
            double scale = 0.0;
            for (int q = 0; q < k; ++q) {
                const int i = guess[std::size_t(q)];
                for (int t = rowStart[std::size_t(i)]; t < rowStart[std::size_t(i) + 1]; ++t) {
                    const int c = pos[std::size_t(rowCol[std::size_t(t)])];
                    if (c < 0) continue;
                    at(q, c) = rowVal[std::size_t(t)];
                    scale = std::max(scale, std::fabs(rowVal[std::size_t(t)]));
                }
            }
            for (int c = 0; c < k; ++c) {
                int best = c;
                for (int r = c + 1; r < k; ++r) {
                    if (std::fabs(at(r, c)) > std::fabs(at(best, c))) best = r;
                }
                perm[std::size_t(c)] = best;
                if (!(std::fabs(at(best, c)) > 1e-14 * scale)) return false;
                if (best != c) {
                    for (int j = 0; j < k; ++j) std::swap(at(best, j), at(c, j));
                }
                for (int r = c + 1; r < k; ++r) {
                    const double f = at(r, c) / at(c, c);
                    at(r, c) = f;
                    if (f == 0.0) continue;
                    for (int j = c + 1; j < k; ++j) at(r, j) -= f * at(c, j);
                }
            }
            return true;
        }
        entries.clear();
        for (int q = 0; q < k; ++q) {
            const int i = guess[std::size_t(q)];
            for (int t = rowStart[std::size_t(i)]; t < rowStart[std::size_t(i) + 1]; ++t) {
                const int c = pos[std::size_t(rowCol[std::size_t(t)])];
                if (c >= 0) entries.emplace_back(q, c, rowVal[std::size_t(t)]);
            }
        }
        Eigen::SparseMatrix<double> M(k, k);
        M.setFromTriplets(entries.begin(), entries.end());
        M.makeCompressed();
        nonZeros = std::uint64_t(M.nonZeros());
        // A resting island checks the same pattern step after step: keep the fill-reducing ordering and symbolic
        // analysis while the pattern is unchanged (the numbers come out the same as a fresh compute()).
        const int* outer = M.outerIndexPtr();
        const int* inner = M.innerIndexPtr();
        const bool samePattern = analyzedSize == k && analyzedOuter.size() == std::size_t(k) + 1 &&
                                 std::equal(outer, outer + k + 1, analyzedOuter.begin()) &&
                                 analyzedInner.size() == std::size_t(M.nonZeros()) &&
                                 std::equal(inner, inner + M.nonZeros(), analyzedInner.begin());
        if (!samePattern) {
            sparse.analyzePattern(M);
            analyzedSize = k;
            analyzedOuter.assign(outer, outer + k + 1);
            analyzedInner.assign(inner, inner + M.nonZeros());
        }
        sparse.factorize(M);
        if (sparse.info() != Eigen::Success) analyzedSize = -1;  // start afresh next time
        return sparse.info() == Eigen::Success;
    }

    /// x := A^-1 x.
    void solve(std::vector<double>& x) const {
        if (!dense) {
            Eigen::Map<Eigen::VectorXd> v(x.data(), k);
            const Eigen::VectorXd y = sparse.solve(v);
            v = y;
            return;
        }
        for (int c = 0; c < k; ++c) std::swap(x[std::size_t(c)], x[std::size_t(perm[std::size_t(c)])]);
        for (int r = 1; r < k; ++r) {
            double s = x[std::size_t(r)];
            for (int j = 0; j < r; ++j) s -= at(r, j) * x[std::size_t(j)];
            x[std::size_t(r)] = s;
        }
        for (int r = k - 1; r >= 0; --r) {
            double s = x[std::size_t(r)];
            for (int j = r + 1; j < k; ++j) s -= at(r, j) * x[std::size_t(j)];
            x[std::size_t(r)] = s / at(r, r);
        }
    }

    std::uint64_t work() const { return dense ? std::uint64_t(k) * std::uint64_t(k) : nonZeros; }

private:
    double& at(int r, int c) { return a[std::size_t(r) * std::size_t(k) + std::size_t(c)]; }
    double at(int r, int c) const { return a[std::size_t(r) * std::size_t(k) + std::size_t(c)]; }

    int k = 0;
    bool dense = true;
    std::vector<double> a;
    std::vector<int> perm;
    std::vector<Eigen::Triplet<double>> entries;
    std::uint64_t nonZeros = 0;
    Eigen::SparseLU<Eigen::SparseMatrix<double>> sparse;
    int analyzedSize = -1;
    std::vector<int> analyzedOuter, analyzedInner;
};

}  // namespace lcp_detail
using lcp_detail::BlockFactor;

/// All per-solve state. Lives on the stack of solve(); the big buffers are borrowed from the solver object.
struct LemkeSolver::Workspace {
    int n = 0;
    int cap = 0;
    const double* b = nullptr;
    std::vector<double> d;  // covering vector (n)
    // Sparsity of A: column-major (for A z and directions) and row-major (for rows entering the block).
    std::vector<int> colStart, colRow, rowStart, rowCol;
    std::vector<double> colVal, rowVal;
    bool columnsReady = false;      // colStart/colRow/colVal match the rows (see ensureColumns)
    BlockFactor blockFactor;        // the warm-start check's factorisation (keeps its symbolic analysis)
    std::vector<double> bStore;     // b of a problem taken over by takeSparse
    std::vector<double> binvStore;  // storage of Binv, kept between solves (grows, never shrinks)
    double* Binv = nullptr;  // (cap x cap), Binv[q * cap + p]: block column-variable q by block row p
    int m = 0;
    std::vector<int> rowIdx, posRow;  // block row p <-> index i (posRow[i] = -1: w_i basic)
    std::vector<int> colVar, posCol;  // block column q <-> variable (0..n-1: z_j, n: z0); posCol has n + 1 entries
    std::vector<double> zval;         // (cap) value of the column variable at block position q
    std::vector<double> wval;         // (n) value of w_i while it is basic
    // Degeneracy: b is treated as b + eps p for a fixed generic p > 0 and an infinitesimal eps; zval2/wval2 carry
    // the eps coefficient of every basic value, updated by the same pivots. Ratio ties (contact LCPs are full of
    // them: every resting contact has b_i = 0) are broken by these coefficients first.
    std::vector<double> p;            // (n) perturbation direction
    std::vector<double> bPerturbed;   // (n) b + delta max|b| p, the right-hand side pivoted on
    std::vector<double> zval2;        // (cap)
    std::vector<double> wval2;        // (n)
    std::vector<double> dy, dw, vrow, tmp;
    std::vector<Candidate> cands, tied;
    double aMaxA = 0.0;           // max |A_ij|
    double aMax = 0.0, bMax = 0.0;  // aMax also covers the covering vector d

    double* row(int q) { return Binv + std::size_t(q) * std::size_t(cap); }

    /// Takes b for a solve: sets aMax from A's and bMax = max |b_i|. Returns the first non-finite entry, or -1.
    int loadB(const double* rhs) {
        b = rhs;
        aMax = aMaxA;
        bMax = 0.0;
        for (int i = 0; i < n; ++i) {
            if (!std::isfinite(rhs[i])) return i;
            bMax = std::max(bMax, std::fabs(rhs[i]));
        }
        return -1;
    }

    /// Makes room for a block of `size` (the row stride grows geometrically up to n + 1; live rows are moved).
    /// Only the block that is actually used is ever allocated: a warm start that needs no pivot allocates none.
    void reserveBlock(int size) {
        if (size <= cap && Binv != nullptr) return;
        const int newCap = std::min(n + 1, std::max(size, 2 * cap));
        const std::size_t need = std::size_t(newCap) * std::size_t(newCap);
        if (binvStore.size() < need) {
            std::vector<double> grown(need);
            for (int q = 0; q < m; ++q) std::copy_n(row(q), m, grown.data() + std::size_t(q) * std::size_t(newCap));
            binvStore.swap(grown);
        } else {
            // Same storage, wider stride: move rows from the last to the first so nothing is overwritten.
            for (int q = m - 1; q >= 0; --q) {
                std::copy_backward(binvStore.data() + std::size_t(q) * std::size_t(cap),
                                   binvStore.data() + std::size_t(q) * std::size_t(cap) + std::size_t(m),
                                   binvStore.data() + std::size_t(q) * std::size_t(newCap) + std::size_t(m));
            }
        }
        Binv = binvStore.data();
        cap = newCap;
    }

    /// One pass over a dense row-major A: its nonzeros by rows, the largest |A_ij|, and the first non-finite
    /// entry (returned as its flat index, or -1).
    long long loadDense(const double* A) {
        rowStart.assign(std::size_t(n) + 1, 0);
        rowCol.clear();
        rowVal.clear();
        aMaxA = 0.0;
        for (int i = 0; i < n; ++i) {
            const double* Ai = A + std::size_t(i) * std::size_t(n);
            for (int j = 0; j < n; ++j) {
                const double v = Ai[j];
                if (v == 0.0) continue;
                if (!std::isfinite(v)) return (long long)i * n + j;
                aMaxA = std::max(aMaxA, std::fabs(v));
                rowCol.push_back(j);
                rowVal.push_back(v);
            }
            rowStart[std::size_t(i) + 1] = int(rowCol.size());
        }
        columnsReady = false;
        return -1;
    }

    /// Checks a compressed-row A (and computes aMaxA); returns an empty string or what is wrong with it. One
    /// branch-light pass over the entries; the message for a bad entry comes from a second, slow pass.
    std::string checkSparse(const SparseLcp& lcp) {
        if (lcp.rowStart.size() != std::size_t(n) + 1 || lcp.rowStart[0] != 0 ||
            lcp.cols.size() != lcp.vals.size() || std::size_t(lcp.rowStart[std::size_t(n)]) != lcp.cols.size())
            return "sparse LCP: rowStart must have n + 1 entries from 0 to the number of entries";
        if (lcp.maxAbs >= 0.0 && lcp.maxAbs <= std::numeric_limits<double>::max()) {
            aMaxA = lcp.maxAbs;  // vouched for by its assembler (SparseLcp::maxAbs)
            return {};
        }
        aMaxA = 0.0;
        bool bad = false;
        const int* cols = lcp.cols.data();
        const double* vals = lcp.vals.data();
        for (int i = 0; i < n; ++i) {
            const int first = lcp.rowStart[std::size_t(i)], last = lcp.rowStart[std::size_t(i) + 1];
            if (last < first) return "sparse LCP: rowStart must not decrease";
            int previous = -1;
            for (int k = first; k < last; ++k) {
                const int j = cols[k];
                bad |= j <= previous || j >= n;
                previous = j;
                const double a = std::fabs(vals[k]);
                bad |= !(a <= std::numeric_limits<double>::max());  // NaN or infinity
                aMaxA = a > aMaxA ? a : aMaxA;
            }
        }
        if (!bad) return {};
        for (int i = 0; i < n; ++i) {
            for (int k = lcp.rowStart[std::size_t(i)]; k < lcp.rowStart[std::size_t(i) + 1]; ++k) {
                const int j = cols[k];
                if (j < 0 || j >= n) return "sparse LCP: column index out of range in row " + std::to_string(i);
                if (k > lcp.rowStart[std::size_t(i)] && j <= cols[k - 1])
                    return "sparse LCP: columns of row " + std::to_string(i) + " must be strictly increasing";
                if (!std::isfinite(vals[k]))
                    return "A has a non-finite entry at (" + std::to_string(i) + ", " + std::to_string(j) + ")";
            }
        }
        return "sparse LCP: malformed";
    }

    /// Takes a compressed-row A over (no copy); `lcp` is left empty.
    std::string takeSparse(SparseLcp& lcp) {
        std::string why = checkSparse(lcp);
        if (!why.empty()) return why;
        rowStart.swap(lcp.rowStart);
        rowCol.swap(lcp.cols);
        rowVal.swap(lcp.vals);
        columnsReady = false;
        return {};
    }

    /// The column-major copy is built only once a solve needs it (a warm start that checks out uses rows only).
    void ensureColumns() {
        if (!columnsReady) buildColumns();
        columnsReady = true;
    }

    /// The column-major copy of the row pattern (rows ascending within each column).
    void buildColumns() {
        colStart.assign(std::size_t(n) + 1, 0);
        for (int j : rowCol) ++colStart[std::size_t(j) + 1];
        for (int j = 0; j < n; ++j) colStart[std::size_t(j) + 1] += colStart[std::size_t(j)];
        colRow.resize(rowCol.size());
        colVal.resize(rowCol.size());
        std::vector<int> fill(colStart.begin(), colStart.end() - 1);
        for (int i = 0; i < n; ++i) {
            for (int k = rowStart[std::size_t(i)]; k < rowStart[std::size_t(i) + 1]; ++k) {
                const int j = rowCol[std::size_t(k)];
                colRow[std::size_t(fill[std::size_t(j)])] = i;
                colVal[std::size_t(fill[std::size_t(j)])] = rowVal[std::size_t(k)];
                ++fill[std::size_t(j)];
            }
        }
    }

    /// out[i] += s * (column `var` of [A | d])[i] for every row i.
    void addColumn(int var, double s, double* out) const {
        if (var < n) {
            for (int k = colStart[std::size_t(var)]; k < colStart[std::size_t(var) + 1]; ++k)
                out[colRow[std::size_t(k)]] += colVal[std::size_t(k)] * s;
        } else {
            for (int i = 0; i < n; ++i) out[i] += d[std::size_t(i)] * s;
        }
    }

    /// vrow[p] = sum_q [A | d](i, colVar[q]) * Binv[q][p]: row i of [A | d] restricted to the block columns, times Binv.
    void rowTimesBinv(int i, double* out) {
        std::fill(out, out + m, 0.0);
        for (int k = rowStart[std::size_t(i)]; k < rowStart[std::size_t(i) + 1]; ++k) {
            const int q = posCol[std::size_t(rowCol[std::size_t(k)])];
            if (q < 0) continue;
            const double c = rowVal[std::size_t(k)];
            const double* __restrict r = row(q);
            for (int p = 0; p < m; ++p) out[p] += c * r[p];
        }
        const int q0 = posCol[std::size_t(n)];
        if (q0 >= 0 && d[std::size_t(i)] != 0.0) {
            const double c = d[std::size_t(i)];
            const double* __restrict r = row(q0);
            for (int p = 0; p < m; ++p) out[p] += c * r[p];
        }
    }

    /// dw[i] = change of basic w_i per unit of the entering variable, given dy. enteringVar >= 0 adds its column.
    void computeDw(int enteringVar) {
        std::fill(dw.begin(), dw.end(), 0.0);
        for (int q = 0; q < m; ++q) {
            if (dy[std::size_t(q)] != 0.0) addColumn(colVar[std::size_t(q)], dy[std::size_t(q)], dw.data());
        }
        if (enteringVar >= 0) addColumn(enteringVar, 1.0, dw.data());
    }

    /// Inverts the block M[p][q] = [A | d](rowIdx[p], colVar[q]) into Binv: a sparse LU of the block (the block of a
    /// contact LCP is as sparse as A), then one solve per unit vector. False when the block is singular or so badly
    /// conditioned that rank-one updates from it would be meaningless.
    bool refactor() {
        reserveBlock(m);
        if (m == 0) return true;
        std::vector<Eigen::Triplet<double>> entries;
        double scale = 0.0;
        const int q0 = posCol[std::size_t(n)];
        for (int p = 0; p < m; ++p) {
            const int i = rowIdx[std::size_t(p)];
            for (int k = rowStart[std::size_t(i)]; k < rowStart[std::size_t(i) + 1]; ++k) {
                const int q = posCol[std::size_t(rowCol[std::size_t(k)])];
                if (q < 0) continue;
                entries.emplace_back(p, q, rowVal[std::size_t(k)]);
                scale = std::max(scale, std::fabs(rowVal[std::size_t(k)]));
            }
            if (q0 >= 0 && d[std::size_t(i)] != 0.0) {
                entries.emplace_back(p, q0, d[std::size_t(i)]);
                scale = std::max(scale, std::fabs(d[std::size_t(i)]));
            }
        }
        Eigen::SparseMatrix<double> M(m, m);
        M.setFromTriplets(entries.begin(), entries.end());
        Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
        lu.compute(M);
        if (lu.info() != Eigen::Success) return false;
        // Column p of M^-1 is row p of nothing in particular: Binv[q][p] = (M^-1)(q, p).
        Eigen::VectorXd e = Eigen::VectorXd::Zero(m), x(m);
        double xMax = 0.0;
        for (int p = 0; p < m; ++p) {
            e[p] = 1.0;
            x = lu.solve(e);
            e[p] = 0.0;
            for (int q = 0; q < m; ++q) {
                if (!std::isfinite(x[q])) return false;
                row(q)[p] = x[q];
                xMax = std::max(xMax, std::fabs(x[q]));
            }
        }
        // |M^-1| |M| ~ condition number: beyond 1e14 the pivots that follow would be rounding noise.
        return xMax * scale <= 1e14;
    }

    /// Recomputes every basic value from scratch (the entering variable is at zero between pivots).
    void recomputeValues() {
        recomputeValues(b, zval, wval);
        recomputeValues(p.data(), zval2, wval2);
    }
    void recomputeValues(const double* rhs, std::vector<double>& zv, std::vector<double>& wv) {
        for (int q = 0; q < m; ++q) {
            const double* r = row(q);
            double s = 0.0;
            for (int k = 0; k < m; ++k) s += r[k] * rhs[rowIdx[std::size_t(k)]];
            zv[std::size_t(q)] = -s;
        }
        std::vector<double> w(rhs, rhs + n);
        for (int q = 0; q < m; ++q) addColumn(colVar[std::size_t(q)], zv[std::size_t(q)], w.data());
        for (int i = 0; i < n; ++i) wv[std::size_t(i)] = posRow[std::size_t(i)] < 0 ? w[std::size_t(i)] : 0.0;
    }

    /// d(value)/d(b_k) of a candidate: the lexicographic row of B^-1 [b | I].
    double sensitivity(const Candidate& c, int k, const std::vector<double>& candRow) {
        const int p = posRow[std::size_t(k)];
        if (c.isColumn) return p >= 0 ? -row(c.pos)[p] : 0.0;
        return (k == c.pos ? 1.0 : 0.0) - (p >= 0 ? candRow[std::size_t(p)] : 0.0);
    }

    /// Breaks a tie among candidates lexicographically (min test: smallest; start test: largest), then by index.
    int breakTie(std::vector<Candidate>& tied, bool takeMax) {
        std::vector<std::vector<double>> rows(tied.size());
        for (std::size_t t = 0; t < tied.size(); ++t) {
            if (!tied[t].isColumn) {
                rows[t].resize(std::size_t(m));
                rowTimesBinv(tied[t].pos, rows[t].data());
            }
        }
        std::vector<std::size_t> alive(tied.size());
        for (std::size_t t = 0; t < tied.size(); ++t) alive[t] = t;
        std::vector<double> val(tied.size());
        for (int k = 0; k < n && alive.size() > 1; ++k) {
            double best = 0.0, mag = 0.0;
            bool first = true;
            for (std::size_t t : alive) {
                // Ratio of the perturbed value: value(eps) / -delta (min test) or -value(eps) / delta (start test).
                val[t] = -sensitivity(tied[t], k, rows[t]) / tied[t].delta;
                mag = std::max(mag, std::fabs(val[t]));
                if (first || (takeMax ? val[t] > best : val[t] < best)) best = val[t];
                first = false;
            }
            const double tol = 1e-12 * mag;
            std::vector<std::size_t> keep;
            for (std::size_t t : alive) {
                if (std::fabs(val[t] - best) <= tol) keep.push_back(t);
            }
            alive.swap(keep);
        }
        std::size_t pick = alive[0];
        for (std::size_t t : alive) {
            if (tied[t].var < tied[pick].var) pick = t;
        }
        return int(pick);
    }
};


}  // namespace unison
