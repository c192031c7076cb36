// core/symmetric_pattern_lu.h — an LDU factorisation without pivoting of a sparse square matrix whose nonzero pattern
// is symmetric (its values need not be), in a fill-reducing symmetric order (AMD of the pattern).
//
// Owns: the ordering and elimination tree of one pattern (analyzePattern, reused while the pattern stays the same),
// the factors L (unit lower), D, U (unit upper) of P A P^T, and solves with them.
//
// It is the factorisation of the active-set path's body-space system [M, J~^T; J, -eps G] (core/active_set_impl.h):
// the pattern is symmetric because a slipping contact's tangent column touches the same bodies as its normal row, and
// the matrix is a small perturbation of a quasi-definite one, whose LDL^T exists in any symmetric order. L and U have
// the pattern of a Cholesky factor of the pattern, so the fill is that of a symmetric factorisation, far below a
// pivoting LU's. Without pivoting nothing bounds the growth of the factors: callers check what a solve gives (the
// active-set path runs it as GMRES's preconditioner, with a pivoting LU behind it).
//
// The numeric phase is the up-looking one of a sparse LDL^T (row k of L and column k of U from sparse triangular solves
// over the elimination tree), done twice per row with the same pattern. Every loop runs in index order, so the factors
// are the same bits on every build.
#pragma once

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

#include <cmath>
#include <cstddef>
#include <vector>

namespace unison {

class SymmetricPatternLu {
public:
    /// The ordering and the elimination tree of `a`'s pattern (square, column-major). A pattern that is not
    /// symmetric is remembered as such, and factorize refuses it.
    void analyzePattern(const Eigen::SparseMatrix<double>& a) {
        if (!a.isCompressed()) {  // the index arrays below are those of compressed storage
            Eigen::SparseMatrix<double> compressed = a;
            compressed.makeCompressed();
            analyzePattern(compressed);
            return;
        }
        n_ = int(a.rows());
        nonZeros_ = a.nonZeros();
        analysed_ = a.rows() == a.cols() && symmetricPattern(a);
        if (!analysed_) return;
        Eigen::AMDOrdering<int> amd;
        Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pinv;
        amd(a, pinv);
        perm_.assign(pinv.indices().data(), pinv.indices().data() + n_);  // new index -> old index
        iperm_.assign(std::size_t(n_), 0);
        for (int k = 0; k < n_; ++k) iperm_[std::size_t(perm_[std::size_t(k)])] = k;
        parent_.assign(std::size_t(n_), -1);
        std::vector<int> count(std::size_t(n_), 0);
        flag_.assign(std::size_t(n_), -1);
        for (int k = 0; k < n_; ++k) {
            flag_[std::size_t(k)] = k;
            for (Eigen::SparseMatrix<double>::InnerIterator it(a, perm_[std::size_t(k)]); it; ++it) {
                int i = iperm_[std::size_t(it.row())];
                if (i >= k) continue;
                for (; flag_[std::size_t(i)] != k; i = parent_[std::size_t(i)]) {
                    if (parent_[std::size_t(i)] == -1) parent_[std::size_t(i)] = k;
                    ++count[std::size_t(i)];
                    flag_[std::size_t(i)] = k;
                }
            }
        }
        // Where factorize reads column k (rows <= k) and row k (columns < k) of P A P^T in a's values.
        const Eigen::SparseMatrix<double> at = a.transpose();
        std::vector<int> position(std::size_t(a.nonZeros()));  // at's entry -> a's entry (same pattern)
        {
            std::vector<int> next(a.outerIndexPtr(), a.outerIndexPtr() + n_);
            for (int j = 0; j < n_; ++j) {
                for (int p = at.outerIndexPtr()[j]; p < at.outerIndexPtr()[j + 1]; ++p) {
                    position[std::size_t(p)] = next[std::size_t(at.innerIndexPtr()[p])]++;
                }
            }
        }
        upperStart_.assign(std::size_t(n_) + 1, 0);
        lowerStart_.assign(std::size_t(n_) + 1, 0);
        upperAt_.clear();
        upperRow_.clear();
        lowerAt_.clear();
        lowerCol_.clear();
        for (int k = 0; k < n_; ++k) {
            const int old = perm_[std::size_t(k)];
            for (int p = a.outerIndexPtr()[old]; p < a.outerIndexPtr()[old + 1]; ++p) {
                const int i = iperm_[std::size_t(a.innerIndexPtr()[p])];
                if (i > k) continue;
                upperAt_.push_back(p);
                upperRow_.push_back(i);
            }
            for (int p = at.outerIndexPtr()[old]; p < at.outerIndexPtr()[old + 1]; ++p) {
                const int j = iperm_[std::size_t(at.innerIndexPtr()[p])];
                if (j >= k) continue;
                lowerAt_.push_back(position[std::size_t(p)]);
                lowerCol_.push_back(j);
            }
            upperStart_[std::size_t(k) + 1] = int(upperAt_.size());
            lowerStart_[std::size_t(k) + 1] = int(lowerAt_.size());
        }
        colPtr_.assign(std::size_t(n_) + 1, 0);
        for (int k = 0; k < n_; ++k) colPtr_[std::size_t(k) + 1] = colPtr_[std::size_t(k)] + count[std::size_t(k)];
        const std::size_t nnz = std::size_t(colPtr_[std::size_t(n_)]);
        rowIdx_.assign(nnz, 0);
        lx_.assign(nnz, 0.0);
        ux_.assign(nnz, 0.0);
    }

    /// Factors `a` (the pattern analyzePattern saw). False when a pivot is zero or not finite.
    bool factorize(const Eigen::SparseMatrix<double>& a) {
        if (!a.isCompressed()) {
            Eigen::SparseMatrix<double> compressed = a;
            compressed.makeCompressed();
            return factorize(compressed);
        }
        if (!analysed_ || int(a.rows()) != n_ || a.nonZeros() != nonZeros_) return false;
        const double* value = a.valuePtr();
        d_.assign(std::size_t(n_), 0.0);
        y_.assign(std::size_t(n_), 0.0);
        z_.assign(std::size_t(n_), 0.0);
        pattern_.assign(std::size_t(n_), 0);
        filled_.assign(std::size_t(n_), 0);
        flag_.assign(std::size_t(n_), -1);
        for (int k = 0; k < n_; ++k) {
            // Column k of P A P^T above the diagonal into y, row k left of it into z, and their common pattern (the
            // rows of L reached from it through the elimination tree) in topological order at pattern_[top..n).
            int top = n_;
            flag_[std::size_t(k)] = k;
            for (int e = upperStart_[std::size_t(k)]; e < upperStart_[std::size_t(k) + 1]; ++e) {
                int i = upperRow_[std::size_t(e)];
                y_[std::size_t(i)] += value[upperAt_[std::size_t(e)]];
                int len = 0;
                for (; flag_[std::size_t(i)] != k; i = parent_[std::size_t(i)]) {
                    pattern_[std::size_t(len++)] = i;
                    flag_[std::size_t(i)] = k;
                }
                while (len > 0) pattern_[std::size_t(--top)] = pattern_[std::size_t(--len)];
            }
            for (int e = lowerStart_[std::size_t(k)]; e < lowerStart_[std::size_t(k) + 1]; ++e) {
                z_[std::size_t(lowerCol_[std::size_t(e)])] += value[lowerAt_[std::size_t(e)]];
            }
            double dk = y_[std::size_t(k)];
            y_[std::size_t(k)] = 0.0;
            for (; top < n_; ++top) {
                const int i = pattern_[std::size_t(top)];
                const double yi = y_[std::size_t(i)], zi = z_[std::size_t(i)];
                y_[std::size_t(i)] = 0.0;
                z_[std::size_t(i)] = 0.0;
                const int begin = colPtr_[std::size_t(i)], end = begin + filled_[std::size_t(i)];
                for (int p = begin; p < end; ++p) {
                    y_[std::size_t(rowIdx_[std::size_t(p)])] -= lx_[std::size_t(p)] * yi;
                    z_[std::size_t(rowIdx_[std::size_t(p)])] -= ux_[std::size_t(p)] * zi;
                }
                const double lki = zi / d_[std::size_t(i)];  // L(k, i)
                const double uik = yi / d_[std::size_t(i)];  // U(i, k)
                dk -= lki * yi;
                rowIdx_[std::size_t(end)] = k;
                lx_[std::size_t(end)] = lki;
                ux_[std::size_t(end)] = uik;
                ++filled_[std::size_t(i)];
            }
            if (!(dk != 0.0) || !std::isfinite(dk)) return false;
            d_[std::size_t(k)] = dk;
        }
        return true;
    }

    /// x with A x = b, from the last factorisation.
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
        std::vector<double>& w = work_;
        w.resize(std::size_t(n_));
        for (int k = 0; k < n_; ++k) w[std::size_t(k)] = b[perm_[std::size_t(k)]];
        for (int j = 0; j < n_; ++j) {  // L w' = w
            const double wj = w[std::size_t(j)];
            if (wj == 0.0) continue;
            for (int p = colPtr_[std::size_t(j)]; p < colPtr_[std::size_t(j) + 1]; ++p)
                w[std::size_t(rowIdx_[std::size_t(p)])] -= lx_[std::size_t(p)] * wj;
        }
        for (int j = 0; j < n_; ++j) w[std::size_t(j)] /= d_[std::size_t(j)];
        for (int j = n_ - 1; j >= 0; --j) {  // U w'' = w'
            double s = w[std::size_t(j)];
            for (int p = colPtr_[std::size_t(j)]; p < colPtr_[std::size_t(j) + 1]; ++p)
                s -= ux_[std::size_t(p)] * w[std::size_t(rowIdx_[std::size_t(p)])];
            w[std::size_t(j)] = s;
        }
        Eigen::VectorXd x(n_);
        for (int k = 0; k < n_; ++k) x[perm_[std::size_t(k)]] = w[std::size_t(k)];
        return x;
    }

    /// Entries of L below its diagonal (U above it has as many).
    std::size_t factorNonZeros() const { return rowIdx_.size(); }

private:
    static bool symmetricPattern(const Eigen::SparseMatrix<double>& a) {
        const Eigen::SparseMatrix<double> at = a.transpose();
        for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
            Eigen::SparseMatrix<double>::InnerIterator p(a, j), q(at, j);
            for (; p && q; ++p, ++q) {
                if (p.row() != q.row()) return false;
            }
            if (p || q) return false;
        }
        return true;
    }

    int n_ = 0;
    Eigen::Index nonZeros_ = 0;
    bool analysed_ = false;
    std::vector<int> perm_, iperm_, parent_, colPtr_, rowIdx_;
    std::vector<int> upperStart_, upperAt_, upperRow_, lowerStart_, lowerAt_, lowerCol_;  // entries of a, per row k
    std::vector<double> lx_, ux_, d_;
    std::vector<int> flag_, pattern_, filled_;  // factorize's scratch
    std::vector<double> y_, z_;
    mutable std::vector<double> work_;
};

}  // namespace unison
