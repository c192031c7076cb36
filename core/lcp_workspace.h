// core/lcp_workspace.h — private to core/lcp.cpp: the per-solve state of LemkeSolver (the compact basis block as
// a factorised B0 plus a Schur border, the sparsity pattern of A, basic values and their perturbation
// coefficients) and the operations on it. Not part of the public API; include it nowhere else.
#pragma once

#include "block_factor.h"
#include <unison/lcp.h>

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace unison {

namespace lcp_detail {

constexpr double kTiny = 1e-300;

/// The messages of a pivot_limit that the caller's caps caused (the robust path does not run after those).
constexpr const char* kPivotCapMessage = "pivot cap reached";
constexpr const char* kWorkBudgetMessage = "work budget exhausted";

// The rank-one correction every pivot applies to the border's explicit inverse Sinv: row q of inv -= c_q v (c_q
// negated when `negate`), for every row q < m except `skip`. On x86-64 GCC it is also built for AVX2, picked at
// load time. Each element is one rounded product and one rounded difference in either clone (no FMA: the build
// contracts nothing), so both give the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
static void subtractOuter(double* __restrict inv, std::size_t stride, int m, const double* __restrict c, bool negate,
                          const double* __restrict v, int skip) {
    for (int q = 0; q < m; ++q) {
        if (q == skip) continue;
        const double cq = negate ? -c[q] : c[q];
        double* __restrict r = inv + std::size_t(q) * stride;
        for (int p = 0; p < m; ++p) r[p] -= cq * v[p];
    }
}

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
using lcp_detail::subtractOuter;


/// All per-solve state. Lives on the stack of solve(); the big buffers are borrowed from the solver object.
struct LemkeSolver::Workspace {
    int n = 0;
    const double* b = nullptr;
    std::vector<double> d;  // covering vector (n)
    // Sparsity of A: column-major (for A z and directions) and row-major (for rows entering the block).
    std::vector<int> colStart, colRow, rowStart, rowCol;
    std::vector<double> colVal, rowVal;
    bool columnsReady = false;      // colStart/colRow/colVal match the rows (see ensureColumns)
    bool symmetricHint = false;     // SparseLcp::symmetricHint of the problem taken over (takeSparse)
    // A guess that checkGuess refused, with the b and tolerance it was checked against and the corrected guess its
    // block principal round produced. The warm start of the next solve on the same guess and b begins at that
    // correction instead of repeating the check (trySparseWarmStart); any solve consumes it.
    struct Refusal {
        bool valid = false;
        std::vector<int> guess, corrected;
        std::vector<double> b;
        double residualTolerance = 0.0;
    } refusal;
    const LemkeSolver::Product* product = nullptr;  // checkGuess's w (set only during that call)
    BlockFactor blockFactor;        // the warm-start check's factorisation (keeps its symbolic analysis)
    std::vector<double> bStore;     // b of a problem taken over by takeSparse
    int m = 0;
    std::uint64_t basicEntries = 0;   // entries of the basic columns of [A | d] (pivotCost), kept with colVar
    std::vector<int> rowIdx, posRow;  // block row p <-> index i (posRow[i] = -1: w_i basic)
    std::vector<int> colVar, posCol;  // block column q <-> variable (0..n-1: z_j, n: z0); posCol has n + 1 entries
    std::vector<double> zval;         // (n + 1) value of the column variable at block position q
    std::vector<double> wval;         // (n) value of w_i while it is basic
    // Degeneracy: b is treated as b + eps p for a fixed generic p > 0 and an infinitesimal eps; zval2/wval2 carry
    // the eps coefficient of every basic value, updated by the same pivots. Ratio ties (contact LCPs are full of
    // them: every resting contact has b_i = 0) are broken by these coefficients first.
    std::vector<double> p;            // (n) perturbation direction
    std::vector<double> bPerturbed;   // (n) b + delta max|b| p, the right-hand side pivoted on
    std::vector<double> zval2;        // (n + 1)
    std::vector<double> wval2;        // (n)
    std::vector<double> dy, dw, rhs;  // rhs: (n + 1) scratch right-hand side by row index, kept all zero
    std::vector<Candidate> cands, tied;
    double aMaxA = 0.0;           // max |A_ij|
    double aMax = 0.0, bMax = 0.0;  // aMax also covers the covering vector d

    // ---- The block, as an earlier block plus a border ------------------------------------------------------------
    // The block B (rows rowIdx, columns colVar) is not inverted. It is kept as B0, the block at the last
    // refactorisation (rows r0Row, columns c0Var, LU in f0), plus a border that records what changed since: columns
    // that entered (ColIn) and rows of B0 that left (their equations get a free slack column), rows that entered
    // (RowIn) and columns of B0 that left (a row pins them to zero). B x = r is then the bordered system
    //     [B0 W] [x0]   [r0]        W = [A(R0, ColIn) | unit columns of the left rows]
    //     [Y  Z] [xb] = [rb],       Y = [A(RowIn, C0) ; unit rows of the left columns],
    // solved through S = Z - Y B0^-1 W (q x q, q = border size) and G = B0^-1 W: xb = S^-1 (rb - Y u),
    // x0 = u - G xb with u = B0^-1 r0. Every pivot changes the border by one column and one row (added or removed),
    // which is one of four rank-one updates of Sinv = S^-1 (grow, shrink, replace a column, replace a row), each
    // O(q^2), plus one sparse solve with B0 for a new border column. A pivot costs O(nnz(LU) + q (q + k0)) instead
    // of the O(m^2) of an explicit inverse, and a warm start factorises its guess once instead of inverting it.
    // The border is folded into a fresh B0 when it grows past maxBorder().
    struct BorderEntry {
        // A column: the slack of R0 row idx when `left`, else column variable idx entered.
        // A row: C0 column variable idx left when `left`, else row idx entered.
        bool left;
        int idx;
    };
    int k0 = 0;
    std::vector<int> r0Row, c0Var;     // B0 position -> row index / column variable
    std::vector<int> pos0Row, pos0Col;  // row index (n) / column variable (n + 1) -> B0 position, or -1
    std::vector<BorderEntry> bcol, brow;
    std::vector<int> bcolOfVar, browOfVar;  // (n + 1) column variable -> border column (ColIn) / row (C0 left), or -1
    std::vector<int> bcolOfRow, browOfRow;  // (n) row index -> border column (R0 left) / row (RowIn), or -1
    int qb = 0, scap = 0;
    std::vector<double> G;     // column t of G at G[t * k0]
    std::vector<double> Sinv;  // Sinv[t * scap + s]: border column t by border row s
    std::vector<double> u, sx, sy, sc, sr;  // scratch

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
        symmetricHint = false;
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
        symmetricHint = lcp.symmetricHint;
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

    /// dw[i] = change of basic w_i per unit of the entering variable, given dy. enteringVar >= 0 adds its column.
    void computeDw(int enteringVar) {
        std::fill(dw.begin(), dw.end(), 0.0);
        for (int q = 0; q < m; ++q) {
            if (dy[std::size_t(q)] != 0.0) addColumn(colVar[std::size_t(q)], dy[std::size_t(q)], dw.data());
        }
        if (enteringVar >= 0) addColumn(enteringVar, 1.0, dw.data());
    }

    static std::size_t at(int i) { return std::size_t(i); }

    BlockFactor& factor() { return factors[current]; }

    /// [A | d](i, var), one entry (the columns of a row ascend).
    double entry(int i, int var) const {
        if (var == n) return d[at(i)];
        const int* first = rowCol.data() + rowStart[at(i)];
        const int* last = rowCol.data() + rowStart[at(i) + 1];
        const int* it = std::lower_bound(first, last, var);
        return it != last && *it == var ? rowVal[std::size_t(it - rowCol.data())] : 0.0;
    }

    /// Row i of [A | d] restricted to the columns that `pos` places (pos0Col: B0's; posCol: the block's), times v
    /// (by those positions).
    double rowDot(int i, const std::vector<int>& pos, const double* v) const {
        double s = 0.0;
        for (int t = rowStart[at(i)]; t < rowStart[at(i) + 1]; ++t) {
            const int c = pos[at(rowCol[at(t)])];
            if (c >= 0) s += rowVal[at(t)] * v[c];
        }
        const int c0 = pos[at(n)];
        if (c0 >= 0) s += d[at(i)] * v[c0];
        return s;
    }
    double rowDotB0(int i, const double* v) const { return rowDot(i, pos0Col, v); }

    /// An empty block for a solve of size n: B0 is 0 x 0 and the border is empty.
    void resetBlock() {
        pos0Row.assign(at(n), -1);
        pos0Col.assign(at(n) + 1, -1);
        bcolOfVar.assign(at(n) + 1, -1);
        browOfVar.assign(at(n) + 1, -1);
        bcolOfRow.assign(at(n), -1);
        browOfRow.assign(at(n), -1);
        r0Row.clear();
        c0Var.clear();
        bcol.clear();
        brow.clear();
        k0 = 0;
        qb = 0;
        borderLimit = 0;
        triplets.clear();
        factor().factorEntries(0, triplets);
        rhs.assign(at(n) + 1, 0.0);
    }

    /// The border size past which the block is refactorised: a pivot costs O(q (q + k0)) on top of the O(nnz(LU))
    /// sparse solves, so the border stays a small multiple of the solve cost.
    int maxBorder() const { return std::max(borderLimit, std::max(32, int(std::sqrt(double(k0)) * 4.0))); }

    /// The work of one pivot (the unit of LcpOptions::maxWork): the solves with B0, the border, the change of w (the
    /// entries of A's basic columns, computeDw) and the ratio test over the w rows. The basic columns are what makes a
    /// 3D pivot dearer than a 2D one of the same size: a 3D contact has six unknowns coupled to every contact of its
    /// two bodies.
    std::uint64_t pivotCost() const {
        return 2 * factors[current].work() + std::uint64_t(qb) * std::uint64_t(qb + 2 * k0) + basicEntries +
               std::uint64_t(n) + 1;
    }

    /// Entries of column `var` of [A | d] (d, the z0 column, counts n); the columns must be ready.
    std::uint64_t columnEntries(int var) const {
        return var < n ? std::uint64_t(colStart[at(var) + 1] - colStart[at(var)]) : std::uint64_t(n);
    }

    /// Makes the current block B0 with a fresh LU and an empty border. False, with nothing changed, when the block
    /// is singular or so badly conditioned (|B^-1 1| |B| > 1e14) that the pivots that follow would be rounding noise.
    bool refactor() {
        triplets.clear();
        double scale = 0.0;
        const int q0 = posCol[at(n)];
        for (int p = 0; p < m; ++p) {
            const int i = rowIdx[at(p)];
            for (int k = rowStart[at(i)]; k < rowStart[at(i) + 1]; ++k) {
                const int q = posCol[at(rowCol[at(k)])];
                if (q < 0) continue;
                triplets.emplace_back(p, q, rowVal[at(k)]);
                scale = std::max(scale, std::fabs(rowVal[at(k)]));
            }
            if (q0 >= 0 && d[at(i)] != 0.0) {
                triplets.emplace_back(p, q0, d[at(i)]);
                scale = std::max(scale, std::fabs(d[at(i)]));
            }
        }
        BlockFactor& fresh = factors[1 - current];
        if (!fresh.factorEntries(m, triplets)) return false;
        u.assign(at(m), 1.0);
        fresh.solve(u.data());
        double xMax = 0.0;
        for (int q = 0; q < m; ++q) {
            if (!std::isfinite(u[at(q)])) return false;
            xMax = std::max(xMax, std::fabs(u[at(q)]));
        }
        if (!(xMax * scale <= 1e14)) return false;
        current = 1 - current;
        for (int i : r0Row) pos0Row[at(i)] = -1;
        for (int v : c0Var) pos0Col[at(v)] = -1;
        for (int t = 0; t < qb; ++t) mapColumn(t, false);
        for (int s = 0; s < qb; ++s) mapRow(s, false);
        bcol.clear();
        brow.clear();
        qb = 0;
        borderLimit = 0;
        k0 = m;
        G.resize(at(scap) * at(k0));
        r0Row.assign(rowIdx.begin(), rowIdx.begin() + m);
        c0Var.assign(colVar.begin(), colVar.begin() + m);
        for (int p = 0; p < m; ++p) pos0Row[at(r0Row[at(p)])] = p;
        for (int q = 0; q < m; ++q) pos0Col[at(c0Var[at(q)])] = q;
        return true;
    }

    /// x = B^-1 r: r by row index (only the block's rows are read), x by block column position (m entries).
    void blockSolve(const double* r, double* x) {
        u.resize(at(k0));
        for (int j = 0; j < k0; ++j) {
            const int i = r0Row[at(j)];
            u[at(j)] = bcolOfRow[at(i)] < 0 ? r[i] : 0.0;  // a row that left has a free slack: its value is moot
        }
        factor().solve(u.data());
        if (qb > 0) {
            sy.resize(at(qb));
            sx.resize(at(qb));
            for (int s = 0; s < qb; ++s) {
                const BorderEntry& e = brow[at(s)];
                sy[at(s)] = e.left ? -u[at(pos0Col[at(e.idx)])] : r[e.idx] - rowDotB0(e.idx, u.data());
            }
            for (int t = 0; t < qb; ++t) {
                const double* __restrict row = Sinv.data() + at(t) * at(scap);
                double acc = 0.0;
                for (int s = 0; s < qb; ++s) acc += row[s] * sy[at(s)];
                sx[at(t)] = acc;
            }
            for (int t = 0; t < qb; ++t) {
                const double f = sx[at(t)];
                if (f == 0.0) continue;
                const double* __restrict g = G.data() + at(t) * at(k0);
                double* __restrict uu = u.data();
                for (int j = 0; j < k0; ++j) uu[j] -= g[j] * f;
            }
        }
        for (int q = 0; q < m; ++q) {
            const int var = colVar[at(q)];
            const int t = bcolOfVar[at(var)];
            x[q] = t >= 0 ? sx[at(t)] : u[at(pos0Col[at(var)])];
        }
    }

    /// Recomputes every basic value from scratch (the entering variable is at zero between pivots).
    void recomputeValues() {
        recomputeValues(b, zval, wval);
        recomputeValues(p.data(), zval2, wval2);
    }
    void recomputeValues(const double* r, std::vector<double>& zv, std::vector<double>& wv) {
        blockSolve(r, zv.data());
        for (int q = 0; q < m; ++q) zv[at(q)] = -zv[at(q)];
        std::vector<double> w(r, r + n);
        for (int q = 0; q < m; ++q) addColumn(colVar[at(q)], zv[at(q)], w.data());
        for (int i = 0; i < n; ++i) wv[at(i)] = posRow[at(i)] < 0 ? w[at(i)] : 0.0;
    }

    /// One pivot's change of the border: the entering variable (a column variable, or the row index of a w that
    /// becomes basic) and the leaving one (a column variable, or the row index of a w that leaves the basis).
    /// Call it before the block's own bookkeeping (rowIdx, colVar, ...) changes.
    void pivotBorder(bool enterIsColumn, int enterVar, bool leaveIsColumn, int leaveIdx) {
        // One side of S gains a border column or loses a border row ...
        BorderEntry addC{false, -1};
        int remR = -1;
        if (enterIsColumn) {
            remR = browOfVar[at(enterVar)];  // a column of B0 that left comes back
            addC = {false, enterVar};
        } else {
            remR = browOfRow[at(enterVar)];  // a row that entered leaves again
            addC = {true, enterVar};
        }
        // ... the other gains a border row or loses a border column.
        BorderEntry addR{false, -1};
        int remC = -1;
        if (leaveIsColumn) {
            remC = bcolOfVar[at(leaveIdx)];
            addR = {true, leaveIdx};
        } else {
            remC = bcolOfRow[at(leaveIdx)];
            addR = {false, leaveIdx};
        }
        if (remR < 0 && remC < 0) {
            growBorder(addC, addR);
        } else if (remR < 0) {
            replaceBorderColumn(remC, addC);
        } else if (remC < 0) {
            replaceBorderRow(remR, addR);
        } else {
            shrinkBorder(remR, remC);
        }
    }

private:
    void mapColumn(int t, bool on) {
        const BorderEntry& e = bcol[at(t)];
        (e.left ? bcolOfRow : bcolOfVar)[at(e.idx)] = on ? t : -1;
    }
    void mapRow(int s, bool on) {
        const BorderEntry& e = brow[at(s)];
        (e.left ? browOfVar : browOfRow)[at(e.idx)] = on ? s : -1;
    }

    void reserveBorder(int size) {
        if (size <= scap) return;
        const int newCap = std::max({size, 2 * scap, 16});
        std::vector<double> grown(at(newCap) * at(newCap));
        for (int t = 0; t < qb; ++t) std::copy_n(Sinv.data() + at(t) * at(scap), qb, grown.data() + at(t) * at(newCap));
        Sinv.swap(grown);
        scap = newCap;
        G.resize(at(newCap) * at(k0));
    }

    /// g = B0^-1 (border column e on B0's rows).
    void borderColumnSolve(const BorderEntry& e, double* g) {
        std::fill(g, g + k0, 0.0);
        if (e.left) {
            g[pos0Row[at(e.idx)]] = 1.0;
        } else if (e.idx == n) {
            for (int j = 0; j < k0; ++j) g[j] = d[at(r0Row[at(j)])];
        } else {
            for (int k = colStart[at(e.idx)]; k < colStart[at(e.idx) + 1]; ++k) {
                const int p0 = pos0Row[at(colRow[at(k)])];
                if (p0 >= 0) g[p0] = colVal[at(k)];
            }
        }
        factor().solve(g);
    }

    /// S(r, c) = Z(r, c) - Y_r g_c for border row r and a border column whose B0^-1 W column is g.
    double schurEntry(const BorderEntry& r, const BorderEntry& c, const double* g) const {
        if (r.left) return -g[pos0Col[at(r.idx)]];
        return (c.left ? 0.0 : entry(r.idx, c.idx)) - rowDotB0(r.idx, g);
    }

    void growBorder(const BorderEntry& c, const BorderEntry& r) {
        reserveBorder(qb + 1);
        double* g = G.data() + at(qb) * at(k0);
        borderColumnSolve(c, g);
        sc.resize(at(qb) + 1);
        sr.resize(at(qb) + 1);
        sx.resize(at(qb) + 1);
        sy.resize(at(qb) + 1);
        for (int s = 0; s < qb; ++s) sc[at(s)] = schurEntry(brow[at(s)], c, g);
        for (int t = 0; t < qb; ++t) sr[at(t)] = schurEntry(r, bcol[at(t)], G.data() + at(t) * at(k0));
        const double corner = schurEntry(r, c, g);
        // a = Sinv c, b^T = r^T Sinv, sigma = corner - r^T a; the bordered inverse.
        double sigma = corner;
        for (int t = 0; t < qb; ++t) {
            const double* row = Sinv.data() + at(t) * at(scap);
            double acc = 0.0;
            for (int s = 0; s < qb; ++s) acc += row[s] * sc[at(s)];
            sx[at(t)] = acc;
            sigma -= sr[at(t)] * acc;
        }
        for (int s = 0; s < qb; ++s) sy[at(s)] = 0.0;
        for (int t = 0; t < qb; ++t) {
            const double* row = Sinv.data() + at(t) * at(scap);
            const double f = sr[at(t)];
            for (int s = 0; s < qb; ++s) sy[at(s)] += f * row[s];
        }
        for (int s = 0; s < qb; ++s) sy[at(s)] /= sigma;
        subtractOuter(Sinv.data(), at(scap), qb, sx.data(), true, sy.data(), -1);  // Sinv += a b^T / sigma
        for (int t = 0; t < qb; ++t) Sinv[at(t) * at(scap) + at(qb)] = -sx[at(t)] / sigma;
        double* last = Sinv.data() + at(qb) * at(scap);
        for (int s = 0; s < qb; ++s) last[s] = -sy[at(s)];
        last[qb] = 1.0 / sigma;
        bcol.push_back(c);
        brow.push_back(r);
        mapColumn(qb, true);
        mapRow(qb, true);
        ++qb;
    }

    void replaceBorderColumn(int tStar, const BorderEntry& c) {
        sc.resize(at(qb));
        sx.resize(at(qb));
        u.resize(at(k0));
        borderColumnSolve(c, u.data());
        for (int s = 0; s < qb; ++s) sc[at(s)] = schurEntry(brow[at(s)], c, u.data());
        for (int t = 0; t < qb; ++t) {
            const double* row = Sinv.data() + at(t) * at(scap);
            double acc = 0.0;
            for (int s = 0; s < qb; ++s) acc += row[s] * sc[at(s)];
            sx[at(t)] = acc;
        }
        // Sinv' = Sinv - (a - e_t*) (row t* of Sinv) / a_t*: row t* scales, the others lose a multiple of it.
        double* pr = Sinv.data() + at(tStar) * at(scap);
        const double inv = 1.0 / sx[at(tStar)];
        for (int s = 0; s < qb; ++s) pr[s] *= inv;
        subtractOuter(Sinv.data(), at(scap), qb, sx.data(), false, pr, tStar);
        std::copy_n(u.data(), k0, G.data() + at(tStar) * at(k0));
        mapColumn(tStar, false);
        bcol[at(tStar)] = c;
        mapColumn(tStar, true);
    }

    void replaceBorderRow(int sStar, const BorderEntry& r) {
        sr.resize(at(qb));
        sy.resize(at(qb));
        sc.resize(at(qb));
        for (int t = 0; t < qb; ++t) sr[at(t)] = schurEntry(r, bcol[at(t)], G.data() + at(t) * at(k0));
        for (int s = 0; s < qb; ++s) sy[at(s)] = 0.0;
        for (int t = 0; t < qb; ++t) {
            const double* row = Sinv.data() + at(t) * at(scap);
            const double f = sr[at(t)];
            for (int s = 0; s < qb; ++s) sy[at(s)] += f * row[s];
            sc[at(t)] = row[sStar];
        }
        // Sinv' = Sinv - (column s* of Sinv) (b - e_s*)^T / b_s*.
        const double piv = sy[at(sStar)];
        for (int s = 0; s < qb; ++s) sy[at(s)] = (sy[at(s)] - (s == sStar ? 1.0 : 0.0)) / piv;
        subtractOuter(Sinv.data(), at(scap), qb, sc.data(), false, sy.data(), -1);
        mapRow(sStar, false);
        brow[at(sStar)] = r;
        mapRow(sStar, true);
    }

    void shrinkBorder(int sStar, int tStar) {
        // The inverse without row s* and column t* of S: Sinv_{-t*,-s*} - Sinv_{-t*,s*} Sinv_{t*,-s*} / Sinv_{t*,s*}.
        sc.resize(at(qb));
        sy.resize(at(qb));
        double* pr = Sinv.data() + at(tStar) * at(scap);
        const double piv = pr[sStar];
        for (int s = 0; s < qb; ++s) sy[at(s)] = pr[s] / piv;
        for (int t = 0; t < qb; ++t) sc[at(t)] = Sinv[at(t) * at(scap) + at(sStar)];
        subtractOuter(Sinv.data(), at(scap), qb, sc.data(), false, sy.data(), tStar);
        mapColumn(tStar, false);
        mapRow(sStar, false);
        const int last = qb - 1;
        if (tStar != last) {
            std::copy_n(Sinv.data() + at(last) * at(scap), qb, pr);
            std::copy_n(G.data() + at(last) * at(k0), k0, G.data() + at(tStar) * at(k0));
            bcol[at(tStar)] = bcol[at(last)];
            mapColumn(tStar, true);
        }
        if (sStar != last) {
            for (int t = 0; t < last; ++t) Sinv[at(t) * at(scap) + at(sStar)] = Sinv[at(t) * at(scap) + at(last)];
            brow[at(sStar)] = brow[at(last)];
            mapRow(sStar, true);
        }
        bcol.pop_back();
        brow.pop_back();
        qb = last;
    }

public:
    /// Breaks a tie among candidates lexicographically (min test: smallest; start test: largest), then by index.
    /// The lexicographic key of candidate c at index k is d(value of c)/d(b_k), from column k of B^-1 (one solve
    /// per k that is a block row; most ties end within a few k).
    int breakTie(std::vector<Candidate>& tied, bool takeMax) {
        std::vector<std::size_t> alive(tied.size());
        for (std::size_t t = 0; t < tied.size(); ++t) alive[t] = t;
        std::vector<double> val(tied.size());
        std::vector<double> column(at(m));
        for (int k = 0; k < n && alive.size() > 1; ++k) {
            const bool inBlock = posRow[at(k)] >= 0;
            if (inBlock) {
                rhs[at(k)] = 1.0;
                blockSolve(rhs.data(), column.data());
                rhs[at(k)] = 0.0;
            }
            double best = 0.0, mag = 0.0;
            bool first = true, finite = true;
            for (std::size_t t : alive) {
                const Candidate& c = tied[t];
                double sensitivity;
                if (c.isColumn) {
                    sensitivity = inBlock ? -column[at(c.pos)] : 0.0;
                } else {
                    sensitivity = (k == c.pos ? 1.0 : 0.0) - (inBlock ? rowDot(c.pos, posCol, column.data()) : 0.0);
                }
                // Ratio of the perturbed value: value(eps) / -delta (min test) or -value(eps) / delta (start test).
                val[t] = -sensitivity / c.delta;
                finite = finite && std::isfinite(val[t]);
                mag = std::max(mag, std::fabs(val[t]));
                if (first || (takeMax ? val[t] > best : val[t] < best)) best = val[t];
                first = false;
            }
            if (!finite) break;  // a column that overflowed orders nothing: the lowest index decides
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

    BlockFactor factors[2];  // B0's LU and the spare a refactorisation writes into (kept if it fails)
    int current = 0;
    int borderLimit = 0;  // raised when a refactorisation fails, so it is not retried every pivot
    std::vector<Eigen::Triplet<double>> triplets;
};


}  // namespace unison
