// core/body_space_solve.h — the sparse linear algebra the active-set path (core/active_set_impl.h) and its
// interior-point restart (core/interior_point_impl.h) share: right-preconditioned GMRES and the assembly of a
// column-major matrix from triplets, both in index order so that their results are the same bits everywhere.
#pragma once

#include <Eigen/SparseCore>

#include "symmetric_pattern_lu.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace unison {

namespace detail {

// Storage of gmresRight, kept across the steps of one active-set solve.
struct GmresWorkspace {
    std::vector<Eigen::VectorXd> basis, preconditioned;  // Arnoldi vectors V_j and P^-1 V_j
    std::vector<double> h, cs, sn, g, y;                // Hessenberg columns (rotated), Givens rotations, residual
};

inline double plainDot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    double s = 0.0;
    for (Eigen::Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
}

// Right-preconditioned restarted GMRES (Saad & Schultz): x with A x = b, starting from P^-1 b, Arnoldi with
// modified Gram-Schmidt and Givens rotations, at most kGmresIterations preconditioned products in all, until the true
// residual is a backward error of kGmresTolerance: ||b - A x|| <= tol (||A||_inf ||x0|| + ||b||), x0 = P^-1 b (the
// proximal term leaves A ill-conditioned along the redundant rows, so a residual relative to ||b|| alone can be
// out of reach of any solve in doubles). Every reduction is a plain loop in index order (square roots only), so the
// answer is the same bits everywhere. Adds to `work` the products it made (`applyWork` each).
constexpr int kGmresIterations = 60;
constexpr double kGmresTolerance = 1e-12;
template <class Preconditioner>
bool gmresRight(const Eigen::SparseMatrix<double>& A, const Preconditioner& P, const Eigen::VectorXd& b,
                Eigen::VectorXd& x, GmresWorkspace& ws, std::uint64_t applyWork, std::uint64_t& work) {
    const Eigen::Index n = b.size();
    const std::uint64_t vectorWork = std::uint64_t(n);
    x = P.solve(b);
    work += applyWork;
    // One pass over A for its row sums (the norm in the tolerance) and the first residual b - A x, accumulated per
    // entry in column order onto b as Eigen evaluates b - A * x below (the same bits).
    std::vector<double> rowSum(std::size_t(n), 0.0);
    Eigen::VectorXd r0 = b;
    for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
        const double xj = -x[j];
        for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
            rowSum[std::size_t(it.row())] += std::fabs(it.value());
            r0[it.row()] += it.value() * xj;
        }
    }
    double normA = 0.0;
    for (double v : rowSum) normA = std::max(normA, v);
    const double tol = kGmresTolerance * (normA * std::sqrt(plainDot(x, x)) + std::sqrt(plainDot(b, b)));
    bool first = true;
    int used = 0;
    const int m = kGmresIterations;
    ws.basis.resize(std::size_t(m + 1));
    ws.preconditioned.resize(std::size_t(m));
    ws.h.assign(std::size_t((m + 1) * m), 0.0);
    ws.cs.assign(std::size_t(m), 0.0);
    ws.sn.assign(std::size_t(m), 0.0);
    ws.g.assign(std::size_t(m + 1), 0.0);
    ws.y.assign(std::size_t(m), 0.0);
    auto H = [&](int i, int j) -> double& { return ws.h[std::size_t(j * (m + 1) + i)]; };
    for (;;) {
        Eigen::VectorXd r = first ? r0 : Eigen::VectorXd(b - A * x);
        first = false;
        work += applyWork;
        const double beta = std::sqrt(plainDot(r, r));
        if (!(beta > tol)) return beta <= tol;  // also false for a NaN residual
        if (used >= m) return false;
        ws.basis[0] = r / beta;
        std::fill(ws.g.begin(), ws.g.end(), 0.0);
        ws.g[0] = beta;
        int k = 0;
        for (int j = 0; used < m; ++j) {
            ++used;
            k = j + 1;
            ws.preconditioned[std::size_t(j)] = P.solve(ws.basis[std::size_t(j)]);
            Eigen::VectorXd w = A * ws.preconditioned[std::size_t(j)];
            work += applyWork + std::uint64_t(2 * (j + 2)) * vectorWork;
            for (int i = 0; i <= j; ++i) {
                H(i, j) = plainDot(w, ws.basis[std::size_t(i)]);
                w -= H(i, j) * ws.basis[std::size_t(i)];
            }
            const double wn = std::sqrt(plainDot(w, w));
            for (int i = 0; i < j; ++i) {
                const double a = H(i, j), c = H(i + 1, j);
                H(i, j) = ws.cs[std::size_t(i)] * a + ws.sn[std::size_t(i)] * c;
                H(i + 1, j) = -ws.sn[std::size_t(i)] * a + ws.cs[std::size_t(i)] * c;
            }
            const double a = H(j, j);
            const double rho = std::sqrt(a * a + wn * wn);
            if (!(rho > 0.0)) {  // a breakdown with H(j, j) = 0: A is singular on the Krylov space
                k = j;
                break;
            }
            ws.cs[std::size_t(j)] = a / rho;
            ws.sn[std::size_t(j)] = wn / rho;
            H(j, j) = rho;
            ws.g[std::size_t(j + 1)] = -ws.sn[std::size_t(j)] * ws.g[std::size_t(j)];
            ws.g[std::size_t(j)] = ws.cs[std::size_t(j)] * ws.g[std::size_t(j)];
            if (std::fabs(ws.g[std::size_t(j + 1)]) <= tol || !(wn > 0.0)) break;
            ws.basis[std::size_t(j + 1)] = w / wn;
        }
        for (int i = k - 1; i >= 0; --i) {
            double v = ws.g[std::size_t(i)];
            for (int l = i + 1; l < k; ++l) v -= H(i, l) * ws.y[std::size_t(l)];
            ws.y[std::size_t(i)] = v / H(i, i);
        }
        for (int i = 0; i < k; ++i) x += ws.y[std::size_t(i)] * ws.preconditioned[std::size_t(i)];
        work += std::uint64_t(k) * vectorWork;
    }
}

// Storage of assembleColumns, kept across the steps of one active-set solve (and, in ActiveSetScratch, across
// solves). The plan is that of the last assembly made with one (assembleColumns with `plan`): the (row, column) of
// each entry in the order given, the place in the matrix's values each went to, and whether it was the first there.
struct ColumnAssembly {
    std::vector<int> start, fill, rows, origin;
    std::vector<int> rowStart, byRow;  // the entries bucketed by row (long columns)
    std::vector<double> values;
    int planSize = -1;
    int lastSize = -1;  // the n of the (row, column) pairs in planRowCol when no plan is recorded (assembleOrRefill)
    std::vector<int> planRowCol, planSlot;
    std::vector<std::uint8_t> planFirst;
};

// Entries per column (on average) from which assembleColumns buckets them by row before its insertion sort.
constexpr std::size_t kBucketRowsPerColumn = 32;

// The column-major n x n matrix of `entries` (row, column, value): duplicates summed in the order given, rows ascending
// within each column. The same matrix, to the bit, as Eigen's setFromTriplets, which sums in the same order, without
// its row-major intermediate. With `plan`, also records where each entry went (ColumnAssembly), for refillColumns.
template <bool kPlan = false>
void assembleColumns(int n, const std::vector<Eigen::Triplet<double>>& entries, Eigen::SparseMatrix<double>& out,
                     ColumnAssembly& ws) {
    ws.planSize = -1;  // the plan describes out's pattern only once a planned assembly completes
    ws.lastSize = -1;
    ws.start.assign(std::size_t(n) + 1, 0);
    for (const Eigen::Triplet<double>& e : entries) ++ws.start[std::size_t(e.col()) + 1];
    for (int j = 0; j < n; ++j) ws.start[std::size_t(j) + 1] += ws.start[std::size_t(j)];
    ws.fill.assign(ws.start.begin(), ws.start.end() - 1);
    ws.rows.resize(entries.size());
    ws.values.resize(entries.size());
    if (kPlan) ws.origin.resize(entries.size());
    // Long columns (the interior point's body systems: dozens of entries per column) are bucketed by row first, then
    // by column, both stable: each column's entries come out in row order, equal rows in the order given, and the
    // insertion sort below finds them sorted. Short columns go to the insertion sort directly.
    const bool bucketRows = entries.size() >= kBucketRowsPerColumn * std::size_t(n);
    if (bucketRows) {
        ws.rowStart.assign(std::size_t(n) + 1, 0);
        for (const Eigen::Triplet<double>& e : entries) ++ws.rowStart[std::size_t(e.row()) + 1];
        for (int r = 0; r < n; ++r) ws.rowStart[std::size_t(r) + 1] += ws.rowStart[std::size_t(r)];
        ws.byRow.resize(entries.size());
        for (std::size_t t = 0; t < entries.size(); ++t)
            ws.byRow[std::size_t(ws.rowStart[std::size_t(entries[t].row())]++)] = int(t);
    }
    for (std::size_t u = 0; u < entries.size(); ++u) {
        const std::size_t t = bucketRows ? std::size_t(ws.byRow[u]) : u;
        const Eigen::Triplet<double>& e = entries[t];
        const int p = ws.fill[std::size_t(e.col())]++;
        ws.rows[std::size_t(p)] = e.row();
        ws.values[std::size_t(p)] = e.value();
        if (kPlan) ws.origin[std::size_t(p)] = int(t);
    }
    if (kPlan) {
        ws.planRowCol.resize(2 * entries.size());
        ws.planSlot.resize(entries.size());
        ws.planFirst.resize(entries.size());
        for (std::size_t t = 0; t < entries.size(); ++t) {
            ws.planRowCol[2 * t] = entries[t].row();
            ws.planRowCol[2 * t + 1] = entries[t].col();
        }
    }
    int w = 0;
    for (int j = 0, b = ws.start[0]; j < n; ++j) {
        const int e = ws.start[std::size_t(j) + 1];
        for (int p = b + 1; p < e; ++p) {  // a stable insertion sort by row (columns hold a few dozen entries)
            const int r = ws.rows[std::size_t(p)];
            const double v = ws.values[std::size_t(p)];
            const int o = kPlan ? ws.origin[std::size_t(p)] : 0;
            int q = p;
            for (; q > b && ws.rows[std::size_t(q) - 1] > r; --q) {
                ws.rows[std::size_t(q)] = ws.rows[std::size_t(q) - 1];
                ws.values[std::size_t(q)] = ws.values[std::size_t(q) - 1];
                if (kPlan) ws.origin[std::size_t(q)] = ws.origin[std::size_t(q) - 1];
            }
            ws.rows[std::size_t(q)] = r;
            ws.values[std::size_t(q)] = v;
            if (kPlan) ws.origin[std::size_t(q)] = o;
        }
        ws.start[std::size_t(j)] = w;
        for (int p = b; p < e; ++p) {
            const bool merge = w > ws.start[std::size_t(j)] && ws.rows[std::size_t(w) - 1] == ws.rows[std::size_t(p)];
            if (merge) {
                ws.values[std::size_t(w) - 1] += ws.values[std::size_t(p)];
            } else {
                ws.rows[std::size_t(w)] = ws.rows[std::size_t(p)];
                ws.values[std::size_t(w)] = ws.values[std::size_t(p)];
                ++w;
            }
            if (kPlan) {
                ws.planSlot[std::size_t(ws.origin[std::size_t(p)])] = w - 1;
                ws.planFirst[std::size_t(ws.origin[std::size_t(p)])] = merge ? 0 : 1;
            }
        }
        b = e;
    }
    ws.start[std::size_t(n)] = w;
    out.resize(n, n);
    out.resizeNonZeros(w);
    std::copy(ws.start.begin(), ws.start.end(), out.outerIndexPtr());
    std::copy(ws.rows.begin(), ws.rows.begin() + w, out.innerIndexPtr());
    std::copy(ws.values.begin(), ws.values.begin() + w, out.valuePtr());
    if (kPlan) ws.planSize = n;
}

// When `entries` has the (row, column) sequence of the plan of the last planned assembly into `out` (n x n, and out
// not changed since but for its values), writes their sums into out's values and returns true: the same sums in the
// same order as assembleColumns, so the same bits, without the sort. Otherwise returns false and leaves out as it is.
inline bool refillColumns(int n, const std::vector<Eigen::Triplet<double>>& entries, Eigen::SparseMatrix<double>& out,
                          const ColumnAssembly& ws) {
    if (ws.planSize != n || out.rows() != n || ws.planSlot.size() != entries.size()) return false;
    const int* rc = ws.planRowCol.data();
    for (std::size_t t = 0; t < entries.size(); ++t) {
        if (entries[t].row() != rc[2 * t] || entries[t].col() != rc[2 * t + 1]) return false;
    }
    double* values = out.valuePtr();
    const int* slot = ws.planSlot.data();
    const std::uint8_t* first = ws.planFirst.data();
    for (std::size_t t = 0; t < entries.size(); ++t) {
        if (first[t])
            values[slot[t]] = entries[t].value();
        else
            values[slot[t]] += entries[t].value();
    }
    return true;
}

// Assembles `out` from `entries` as assembleColumns does, or refills it (refillColumns, returning true) when the
// entries repeat those of the last call with a plan. Entry sequences of at least `minPlan` entries are remembered;
// the plan is recorded when a sequence comes the second time in a row, so systems whose pattern keeps changing (a
// landing pile's active-set iterations) pay only a copy of their (row, column) pairs.
inline bool assembleOrRefill(int n, const std::vector<Eigen::Triplet<double>>& entries,
                             Eigen::SparseMatrix<double>& out, ColumnAssembly& ws, std::size_t minPlan) {
    if (refillColumns(n, entries, out, ws)) return true;
    bool repeat = ws.lastSize == n && ws.planRowCol.size() == 2 * entries.size();
    for (std::size_t t = 0; t < entries.size() && repeat; ++t)
        repeat = entries[t].row() == ws.planRowCol[2 * t] && entries[t].col() == ws.planRowCol[2 * t + 1];
    if (repeat && entries.size() >= minPlan) {
        assembleColumns<true>(n, entries, out, ws);
    } else {
        assembleColumns(n, entries, out, ws);
        if (entries.size() >= minPlan) {
            ws.planRowCol.resize(2 * entries.size());
            for (std::size_t t = 0; t < entries.size(); ++t) {
                ws.planRowCol[2 * t] = entries[t].row();
                ws.planRowCol[2 * t + 1] = entries[t].col();
            }
            ws.lastSize = n;
        }
    }
    return false;
}

// What the interior-point restart (core/interior_point_impl.h) keeps between calls: its body-space system (the
// pattern built from the contacts' degrees of freedom), the factorisation's analysis, and which entries it reads. A
// call whose contacts couple the same degrees of freedom as the last call's (planKey) refills the values and reuses
// the rest.
struct InteriorPointScratch {
    std::vector<int> readPos, readStart, diagPos;
    std::vector<std::uint8_t> readCode;
    std::vector<int> planKey;            // ndof, then per contact its sides' first degrees of freedom and locked mask
    std::vector<int> nbrStart, nbr, outer, inner;  // the pattern's construction
    std::size_t entryCount = 0;          // the mass diagonal's and the contacts' entries (work units)
    Eigen::SparseMatrix<double> Kb;
    SymmetricPatternLu factor;
    std::uint64_t refills = 0;  // calls whose system was refilled (a count, for tests)
};

// One island system of the 3D path (core/active_set3_impl.h): the pattern of its matrix over all the island's
// unknowns, where each entry's value goes (planSlot, in the order the path writes them) and the analysed
// factorisation. The pattern depends only on the degrees of freedom and on which two bodies' degrees of freedom each
// contact couples (sides), so an island with the same ones reuses it as it stands.
struct BoxSystem {
    int ndof = -1;
    std::vector<int> sides;  // per contact, the first degree of freedom of each of its bodies (-1: immovable)
    Eigen::SparseMatrix<double> K;
    std::vector<int> planSlot;
    SymmetricPatternLu factor;
    std::uint64_t lastUse = 0;
};

}  // namespace detail

/// What the active-set path keeps between solves (ActiveSetOptions::scratch): buffers that keep their capacity, and
/// the body-space system of the last iteration with its assembly plan and its factorisation's analysis. A settled
/// island whose system has last step's pattern then refills its values in place and skips the sort and the pattern
/// analysis. It changes the cost, never the answer.
struct ActiveSetScratch {
    std::vector<Eigen::Triplet<double>> triplets, slipTriplets;
    detail::ColumnAssembly assembly;
    Eigen::SparseMatrix<double> K;
    SymmetricPatternLu factor;
    bool factorHoldsK = false;  ///< factor's analysis is that of K's pattern
    std::uint64_t refills = 0;  ///< iterations whose system was refilled in place (a count, for tests)
    detail::InteriorPointScratch interiorPoint;  ///< the interior-point restart's
    /// The 3D path's island systems, the least recently used replaced first: a step of a heap solves a few islands
    /// whose contacts stay the same for several steps.
    std::vector<detail::BoxSystem> boxSystems;
    std::uint64_t boxUses = 0;
    static constexpr std::size_t kBoxSystems = 8;
    /// The kept system with these degrees of freedom and sides, or the least recently used one emptied for them.
    detail::BoxSystem& boxSystem(int ndof, const std::vector<int>& sides) {
        ++boxUses;
        detail::BoxSystem* oldest = nullptr;
        for (detail::BoxSystem& b : boxSystems) {
            if (b.ndof == ndof && b.sides == sides) {
                b.lastUse = boxUses;
                return b;
            }
            if (!oldest || b.lastUse < oldest->lastUse) oldest = &b;
        }
        if (boxSystems.size() < kBoxSystems) {
            boxSystems.emplace_back();
            oldest = &boxSystems.back();
        }
        oldest->ndof = ndof;
        oldest->sides = sides;
        oldest->planSlot.clear();
        oldest->lastUse = boxUses;
        return *oldest;
    }
};

}  // namespace unison
