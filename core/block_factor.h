// core/block_factor.h — private to core/lcp.cpp (through lcp_workspace.h): the factorisation of one block of an
// LCP matrix that the Lemke solver solves with many times (the warm-start check's guessed basis, and the block B0
// of Lemke's basis representation). Not part of the public API; include it nowhere else.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace unison {

namespace lcp_detail {

// A block of A (a guessed basis A_{alpha,alpha}, or the Lemke block B0), factorised once for many solves: a dense LU
// with partial pivoting for small blocks (Eigen's sparse LU costs more than the whole solve there: a one-contact
// island has a 2 x 2 block); from kSymmetricMin unknowns a sparse LDL^T of its symmetric core with the few
// asymmetric unknowns (friction slacks) eliminated through a dense Schur complement (symmetricCore); Eigen's sparse
// LU otherwise.
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
            return denseLu(scale);
        }
        entries.clear();
        for (int q = 0; q < k; ++q) {
            const int i = guess[std::size_t(q)];
            for (int t = rowStart[std::size_t(i)]; t < rowStart[std::size_t(i) + 1]; ++t) {
                const int c = pos[std::size_t(rowCol[std::size_t(t)])];
                if (c >= 0) entries.emplace_back(q, c, rowVal[std::size_t(t)]);
            }
        }
        return sparseLu();
    }

    /// Factorises the k x k matrix of `entries` (row, column, value; no duplicates): dense LU with partial pivoting
    /// for k <= kDenseMax, Eigen's sparse LU otherwise (keeping its symbolic analysis while the pattern repeats).
    bool factorEntries(int size, const std::vector<Eigen::Triplet<double>>& triplets) {
        k = size;
        dense = k <= kDenseMax;
        if (dense) {
            a.assign(std::size_t(k) * std::size_t(k), 0.0);
            perm.resize(std::size_t(k));
            double scale = 0.0;
            for (const auto& t : triplets) {
                at(t.row(), t.col()) = t.value();
                scale = std::max(scale, std::fabs(t.value()));
            }
            return denseLu(scale);
        }
        entries = triplets;
        return sparseLu();
    }

    /// x := A^-1 x (x has k entries).
    void solve(double* x) const {
        if (!dense) {
            if (useLdlt) {
                solveBordered(x);
                return;
            }
            Eigen::Map<Eigen::VectorXd> v(x, k);
            const Eigen::VectorXd y = sparse.solve(v);
            v = y;
            return;
        }
        for (int c = 0; c < k; ++c) std::swap(x[c], x[perm[std::size_t(c)]]);
        for (int r = 1; r < k; ++r) {
            double s = x[r];
            for (int j = 0; j < r; ++j) s -= at(r, j) * x[j];
            x[r] = s;
        }
        for (int r = k - 1; r >= 0; --r) {
            double s = x[r];
            for (int j = r + 1; j < k; ++j) s -= at(r, j) * x[j];
            x[r] = s / at(r, r);
        }
    }

    int size() const { return k; }

    /// x := A^-1 x.
    void solve(std::vector<double>& x) const { solve(x.data()); }

    std::uint64_t work() const { return dense ? std::uint64_t(k) * std::uint64_t(k) : nonZeros; }

private:
    bool denseLu(double scale) {
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

    // The indices q whose row and column of M differ (bit for bit). The principal block on the other indices is
    // symmetric: the contact assemblers mirror A_ij and A_ji exactly, and only the friction slack unknowns (the
    // mu and E couplings) break the symmetry.
    static void asymmetricIndices(const Eigen::SparseMatrix<double>& M, std::vector<int>& out) {
        out.clear();
        const Eigen::SparseMatrix<double> T = M.transpose();
        for (Eigen::Index j = 0; j < M.cols(); ++j) {
            const int a0 = M.outerIndexPtr()[j], a1 = M.outerIndexPtr()[j + 1];
            const int t0 = T.outerIndexPtr()[j], t1 = T.outerIndexPtr()[j + 1];
            const bool same = a1 - a0 == t1 - t0 &&
                              std::equal(M.innerIndexPtr() + a0, M.innerIndexPtr() + a1, T.innerIndexPtr() + t0) &&
                              std::equal(M.valuePtr() + a0, M.valuePtr() + a1, T.valuePtr() + t0);
            if (!same) out.push_back(int(j));
        }
    }

    // A symmetric block (a guess of normal and sticking-friction unknowns is a principal block of J M^-1 J^T) that
    // is positive definite: sparse LDL^T, about half the work of the LU. False when it is not (a pivot of D <= 0 or
    // below 1e-12 of the largest): the caller uses the LU.
    bool sparseLdlt(const Eigen::SparseMatrix<double>& M) {
        if (!ldltPattern.same(M)) ldlt.analyzePattern(M);
        ldlt.factorize(M);
        if (ldlt.info() != Eigen::Success) {
            ldltPattern.forget();
            return false;
        }
        const auto& D = ldlt.vectorD();
        double dMax = 0.0;
        for (Eigen::Index i = 0; i < D.size(); ++i) dMax = std::max(dMax, D[i]);
        for (Eigen::Index i = 0; i < D.size(); ++i) {
            if (!(D[i] > 1e-12 * dMax)) return false;
        }
        return true;
    }

    // M as [C Bc; E F] with C its symmetric core (asymmetricIndices) factorised by LDL^T and the few other
    // indices (at most kBorderMax) eliminated through the dense Schur complement S = F - E C^-1 Bc. False when
    // there are more of them or C is not positive definite (the caller uses the LU).
    static constexpr int kBorderMax = 32;

public:
    // Blocks below this keep the LU. On the 3D cube piles of bench_world3d (islands of < 128 unknowns) the LDL^T
    // saved no measurable time, and the rounding-level differences of its answers took those chaotic piles over
    // 25 % more pivots in total over 7 pile sizes; on the 2D pyramids (one island of 250-500) it halves the
    // settled step (20 rows: 0.88 -> 0.51 ms).
    static constexpr int kSymmetricMin = 128;
    /// Blocks of at least this many unknowns try the LDL^T of the symmetric core. The warm-start check lowers it
    /// to kDenseMax + 1 for matrices with SparseLcp::symmetricHint (3D contacts): its block is factorised once and
    /// solved twice, and Eigen's sparse LU zero-fills its panel and supernode workspaces on every factorisation,
    /// 11 % of a settled 3D pile step's instructions under callgrind.
    int symmetricMin = kSymmetricMin;

private:
    bool symmetricCore(const Eigen::SparseMatrix<double>& M) {
        asymmetricIndices(M, borderIdx);
        const int p = int(borderIdx.size());
        if (p > kBorderMax || p == k) return false;
        place.assign(std::size_t(k), 0);  // index -> core position (>= 0) or -1 - border position
        for (int t = 0; t < p; ++t) place[std::size_t(borderIdx[std::size_t(t)])] = -1 - t;
        coreIdx.clear();
        for (int q = 0; q < k; ++q) {
            if (place[std::size_t(q)] < 0) continue;
            place[std::size_t(q)] = int(coreIdx.size());
            coreIdx.push_back(q);
        }
        const int kc = int(coreIdx.size());
        if (p == 0) {
            if (!sparseLdlt(M)) return false;
            bordered = 0;
            return true;
        }
        // Split the entries (M is column-major: column j, rows i).
        coreEntries.clear();
        std::vector<Eigen::Triplet<double>> fEntries;
        E.assign(std::size_t(p) * std::size_t(kc), 0.0);
        G.assign(std::size_t(p) * std::size_t(kc), 0.0);  // column t of Bc, then of C^-1 Bc, at G[t * kc]
        for (Eigen::Index j = 0; j < M.cols(); ++j) {
            const int pj = place[std::size_t(j)];
            for (int t = M.outerIndexPtr()[j]; t < M.outerIndexPtr()[j + 1]; ++t) {
                const int pi = place[std::size_t(M.innerIndexPtr()[t])];
                const double v = M.valuePtr()[t];
                if (pi >= 0 && pj >= 0) coreEntries.emplace_back(pi, pj, v);
                else if (pi >= 0) G[std::size_t(-1 - pj) * std::size_t(kc) + std::size_t(pi)] = v;
                else if (pj >= 0) E[std::size_t(-1 - pi) * std::size_t(kc) + std::size_t(pj)] = v;
                else fEntries.emplace_back(-1 - pi, -1 - pj, v);
            }
        }
        Eigen::SparseMatrix<double> C(kc, kc);
        C.setFromTriplets(coreEntries.begin(), coreEntries.end());
        C.makeCompressed();
        const int kSaved = k;
        k = kc;
        const bool ok = sparseLdlt(C);
        k = kSaved;
        if (!ok) return false;
        for (int t = 0; t < p; ++t) {
            Eigen::Map<Eigen::VectorXd> g(G.data() + std::size_t(t) * std::size_t(kc), kc);
            const Eigen::VectorXd y = ldlt.solve(g);
            g = y;
        }
        // S = F - E G, dense p x p (p <= kBorderMax, so the nested factor is its dense LU).
        std::vector<double> S(std::size_t(p) * std::size_t(p), 0.0);
        for (const auto& f : fEntries) S[std::size_t(f.row()) * std::size_t(p) + std::size_t(f.col())] = f.value();
        for (int r = 0; r < p; ++r) {
            const double* e = E.data() + std::size_t(r) * std::size_t(kc);
            for (int t = 0; t < p; ++t) {
                const double* g = G.data() + std::size_t(t) * std::size_t(kc);
                double acc = 0.0;
                for (int c = 0; c < kc; ++c) acc += e[c] * g[c];
                S[std::size_t(r) * std::size_t(p) + std::size_t(t)] -= acc;
            }
        }
        std::vector<Eigen::Triplet<double>> sEntries;
        for (int r = 0; r < p; ++r) {
            for (int t = 0; t < p; ++t)
                sEntries.emplace_back(r, t, S[std::size_t(r) * std::size_t(p) + std::size_t(t)]);
        }
        if (!schur) schur = std::make_unique<BlockFactor>();
        if (!schur->factorEntries(p, sEntries)) return false;
        bordered = p;
        return true;
    }

    void solveBordered(double* x) const {
        const int p = bordered, kc = k - p;
        // Scratch kept between calls: this runs twice per Lemke pivot on a large block.
        Eigen::VectorXd& rc = scratchCore;
        Eigen::VectorXd& u = scratchSolution;
        std::vector<double>& y = scratchBorder;
        rc.resize(kc);
        for (int c = 0; c < kc; ++c) rc[c] = x[coreIdx[std::size_t(c)]];
        u = ldlt.solve(rc);
        if (p == 0) {
            for (int c = 0; c < kc; ++c) x[coreIdx[std::size_t(c)]] = u[c];
            return;
        }
        y.resize(std::size_t(p));
        for (int r = 0; r < p; ++r) {
            const double* e = E.data() + std::size_t(r) * std::size_t(kc);
            double acc = 0.0;
            for (int c = 0; c < kc; ++c) acc += e[c] * u[c];
            y[std::size_t(r)] = x[borderIdx[std::size_t(r)]] - acc;
        }
        schur->solve(y.data());
        for (int t = 0; t < p; ++t) {
            const double f = y[std::size_t(t)];
            if (f == 0.0) continue;
            const double* g = G.data() + std::size_t(t) * std::size_t(kc);
            for (int c = 0; c < kc; ++c) u[c] -= g[c] * f;
        }
        for (int c = 0; c < kc; ++c) x[coreIdx[std::size_t(c)]] = u[c];
        for (int t = 0; t < p; ++t) x[borderIdx[std::size_t(t)]] = y[std::size_t(t)];
    }

    bool sparseLu() {
        Eigen::SparseMatrix<double> M(k, k);
        M.setFromTriplets(entries.begin(), entries.end());
        M.makeCompressed();
        nonZeros = std::uint64_t(M.nonZeros());
        useLdlt = k >= symmetricMin && symmetricCore(M);
        if (useLdlt) return true;
        // A resting island checks the same pattern step after step: keep the fill-reducing ordering and symbolic
        // analysis while the pattern is unchanged (the numbers come out the same as a fresh compute()).
        if (!luPattern.same(M)) sparse.analyzePattern(M);
        sparse.factorize(M);
        if (sparse.info() != Eigen::Success) luPattern.forget();  // start afresh next time
        return sparse.info() == Eigen::Success;
    }


    double& at(int r, int c) { return a[std::size_t(r) * std::size_t(k) + std::size_t(c)]; }
    double at(int r, int c) const { return a[std::size_t(r) * std::size_t(k) + std::size_t(c)]; }

    int k = 0;
    bool dense = true;
    std::vector<double> a;
    std::vector<int> perm;
    std::vector<Eigen::Triplet<double>> entries;
    std::uint64_t nonZeros = 0;
    Eigen::SparseLU<Eigen::SparseMatrix<double>> sparse;
    // The sparsity pattern a factorisation's symbolic analysis was done for. same(M) is true when M has it, and
    // otherwise remembers M's (the caller then analyses M).
    struct Pattern {
        std::vector<int> outer, inner;
        bool valid = false;
        bool same(const Eigen::SparseMatrix<double>& M) {
            const int* o = M.outerIndexPtr();
            const int* in = M.innerIndexPtr();
            const std::size_t cols = std::size_t(M.cols()), nz = std::size_t(M.nonZeros());
            if (valid && outer.size() == cols + 1 && std::equal(o, o + cols + 1, outer.begin()) && inner.size() == nz &&
                std::equal(in, in + nz, inner.begin()))
                return true;
            outer.assign(o, o + cols + 1);
            inner.assign(in, in + nz);
            valid = true;
            return false;
        }
        void forget() { valid = false; }
    };
    Pattern luPattern;
    bool useLdlt = false;  // symmetricCore() holds the factorisation
    int bordered = 0;
    std::vector<int> borderIdx, coreIdx, place;
    std::vector<Eigen::Triplet<double>> coreEntries;
    std::vector<double> E, G;
    std::unique_ptr<BlockFactor> schur;
    mutable Eigen::VectorXd scratchCore, scratchSolution;
    mutable std::vector<double> scratchBorder;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
    Pattern ldltPattern;
};

}  // namespace lcp_detail
using lcp_detail::BlockFactor;

}  // namespace unison
