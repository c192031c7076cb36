// core/symmetric_pattern_lu.h — an LDU factorisation without pivoting of a sparse square matrix whose nonzero pattern
// is symmetric (its values need not be), in a fill-reducing symmetric order (AMD of the pattern).
//
// Owns: the factors L (unit lower), D, U (unit upper) of P A P^T, and solves with them. The analysis of a pattern (its
// ordering, elimination tree and where each entry goes) is shared: analyzePattern reuses it while the pattern stays
// the same, and a SymmetricPatternCache keeps the analyses of the patterns seen in recent steps (a settled island's
// system has the same pattern step after step, and its AMD ordering costs more than its factorisation).
//
// It is the factorisation of the active-set path's body-space system [M, J~^T; J, -eps G] (core/active_set_impl.h):
// the pattern is symmetric because a slipping contact's tangent column touches the same bodies as its normal row, and
// the matrix is a small perturbation of a quasi-definite one, whose LDL^T exists in any symmetric order. L and U have
// the pattern of a Cholesky factor of the pattern, so the fill is that of a symmetric factorisation, far below a
// pivoting LU's. Without pivoting nothing bounds the growth of the factors: callers check what a solve gives (the
// active-set path runs it as GMRES's preconditioner, with a pivoting LU behind it).
//
// The numeric phase is the up-looking one of a sparse LDL^T (row k of L and column k of U from sparse triangular solves
// over the elimination tree), done twice per row with the same pattern: L's and U's entries are stored interleaved,
// and one two-lane multiply and subtract updates both (each lane is the scalar operation, so the bits are the same
// as one at a time). A run of up to four consecutive columns that chain in the elimination tree (each the only child
// of the next, with the next's pattern plus that row; a body's degrees of freedom, mostly) and lie next to each other
// in a row's reach is eliminated in one pass over its shared rows: each entry is loaded and stored once and gets its
// subtractions in column order, as column by column. With symmetric values (L D L^T) only L is computed, in its own
// array. Every loop runs in index order, so the factors are the same bits on every build.
#pragma once

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <unordered_map>
#include <vector>

namespace unison {

/// What SymmetricPatternLu knows of one pattern before it sees values: a pure function of the pattern (the index
/// arrays of a compressed column-major matrix).
struct SymmetricPatternAnalysis {
    int n = 0;
    Eigen::Index nonZeros = 0;
    bool symmetric = false;                  // false: factorize refuses the pattern
    std::vector<int> perm, iperm;            // AMD order: new index -> old index, and back
    std::vector<int> parent, colPtr;         // elimination tree; where each column of L (row of U) starts
    std::vector<int> upperStart, upperAt, upperRow;  // column k of P A P^T on and above the diagonal: a's entries
    std::vector<int> lowerStart, lowerAt, lowerCol;  // row k of P A P^T left of the diagonal: a's entries
    std::vector<int> reachStart, reach;      // row k of L: its columns in the order factorize eliminates them
    std::vector<int> lowerRow;               // column j of L below the diagonal: its rows, from colPtr[j]
    // Per entry of reach: at the first of a run of s consecutive columns i, i + 1, ..., i + s - 1 (s <= kMaxRun),
    // each the only child of the next in the tree with the next's pattern plus that next row, s; 0 at the others.
    // factorize eliminates such a run in one pass over its shared rows (the same operations in the same order).
    std::vector<std::uint8_t> reachRun;
    static constexpr int kMaxRun = 4;  // longer runs measured slower

    /// Temporaries of `of` whose capacity a caller keeps from one analysis to the next (its contents never matter): a
    /// step's new patterns would otherwise each take fresh memory for the ordering's copy of the pattern, and the
    /// first touch of each fresh page costs a page fault.
    struct Workspace {
        Eigen::SparseMatrix<char> pattern;  // the minimum-degree routine's copy of the pattern (it overwrites it)
        std::vector<int> position;
    };
    /// The analysis of `a` (square, compressed). `workspace` (nullptr: a local one) holds the temporaries.
    static std::shared_ptr<const SymmetricPatternAnalysis> of(const Eigen::SparseMatrix<double>& a,
                                                              Workspace* workspace = nullptr);
    std::size_t bytes() const {
        return sizeof(*this) + sizeof(int) * (perm.size() + iperm.size() + parent.size() + colPtr.size() +
                                              upperStart.size() + upperAt.size() + upperRow.size() +
                                              lowerStart.size() + lowerAt.size() + lowerCol.size() +
                                              reachStart.size() + reach.size() + lowerRow.size()) +
               reachRun.size();
    }
};

/// The analyses of the patterns met recently, found again by the pattern itself (its index arrays, compared in full;
/// a 64-bit hash only picks the candidate). Whether a pattern is found never changes a result, only its cost: an
/// analysis is a pure function of the pattern. Bounded: nextGeneration() (the world calls it once per step) drops the
/// entries not used in the last few generations, and a pattern that would take the cache past maxBytes is not kept.
class SymmetricPatternCache {
public:
    static constexpr std::size_t kDefaultBytes = std::size_t(64) << 20;
    explicit SymmetricPatternCache(std::size_t maxBytes = kDefaultBytes) : maxBytes_(maxBytes) {}

    /// The analysis of `a` (square, compressed): the one kept for its pattern, or a new one, kept when it fits.
    /// `keyOut` (optional) receives the key keep() finds it by.
    std::shared_ptr<const SymmetricPatternAnalysis> analysisOf(const Eigen::SparseMatrix<double>& a,
                                                               std::uint64_t* keyOut = nullptr) {
        const std::uint64_t key = hashOf(a);
        if (keyOut) *keyOut = key;
        const auto it = entries_.find(key);
        if (it != entries_.end() && samePattern(it->second, a)) {
            ++hits_;
            it->second.generation = generation_;
            return it->second.analysis;
        }
        ++misses_;
        std::shared_ptr<const SymmetricPatternAnalysis> analysis = SymmetricPatternAnalysis::of(a, &workspace_);
        if (it != entries_.end()) {  // a different pattern with the same hash: the newer one replaces it
            bytes_ -= it->second.bytes;
            entries_.erase(it);
        }
        const std::size_t outer = std::size_t(a.outerSize()) + 1, inner = std::size_t(a.nonZeros());
        const std::size_t size = analysis->bytes() + sizeof(int) * (outer + inner) + sizeof(Entry);
        // Room is made first from the entries that only the longer keeping of small ones has left (those the
        // kKeepGenerations rule would have dropped at the end of the last generation).
        if (bytes_ + size > maxBytes_) dropUnused(kKeepGenerations + 1, kKeepGenerations + 1);
        if (bytes_ + size > maxBytes_) return analysis;
        Entry& e = entries_[key];
        e.outer.assign(a.outerIndexPtr(), a.outerIndexPtr() + outer);
        e.inner.assign(a.innerIndexPtr(), a.innerIndexPtr() + inner);
        e.analysis = analysis;
        e.generation = generation_;
        e.bytes = size;
        bytes_ += size;
        return analysis;
    }
    /// The analysis of `a` with this cache's workspace, neither looked up nor kept: for patterns that do not come
    /// back, whose analyses would only hold memory until they are dropped.
    std::shared_ptr<const SymmetricPatternAnalysis> analysisOnce(const Eigen::SparseMatrix<double>& a) {
        return SymmetricPatternAnalysis::of(a, &workspace_);
    }
    /// Marks the entry of `key` as used in this generation, as a call of analysisOf that found it would, when it
    /// holds `analysis` (a caller that kept an analysis and its pattern skips the look-up).
    void keep(std::uint64_t key, const SymmetricPatternAnalysis* analysis) {
        const auto it = entries_.find(key);
        if (it != entries_.end() && it->second.analysis.get() == analysis) it->second.generation = generation_;
    }
    /// Ends a generation: drops the entries that no analysisOf call used in it nor in the kKeepGenerations - 1 before
    /// it (a settled pile can alternate between two faces, so a pattern may return every other step). Entries of at
    /// most kSmallEntryBytes (islands of a few hundred contacts) stay kKeepSmallGenerations: the faces of a settled
    /// small pile come back after tens of steps, and an analysis costs several of its factorisations there.
    static constexpr std::uint64_t kKeepGenerations = 4;
    static constexpr std::uint64_t kKeepSmallGenerations = 64;
    static constexpr std::size_t kSmallEntryBytes = std::size_t(1) << 20;
    void nextGeneration() {
        dropUnused(kKeepSmallGenerations, kKeepGenerations);
        ++generation_;
    }
    std::size_t size() const { return entries_.size(); }
    std::size_t bytes() const { return bytes_; }
    std::uint64_t hits() const { return hits_; }
    std::uint64_t misses() const { return misses_; }

private:
    // Drops the entries unused in the current generation and the `keep` - 1 before it: `keepSmall` for entries of at
    // most kSmallEntryBytes.
    void dropUnused(std::uint64_t keepSmall, std::uint64_t keep) {
        for (auto it = entries_.begin(); it != entries_.end();) {
            const std::uint64_t generations = it->second.bytes <= kSmallEntryBytes ? keepSmall : keep;
            if (generation_ - it->second.generation >= generations) {
                bytes_ -= it->second.bytes;
                it = entries_.erase(it);
            } else {
                ++it;
            }
        }
    }
    struct Entry {
        std::vector<int> outer, inner;
        std::shared_ptr<const SymmetricPatternAnalysis> analysis;
        std::uint64_t generation = 0;
        std::size_t bytes = 0;
    };
    static std::uint64_t hashOf(const Eigen::SparseMatrix<double>& a) {
        std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a over the index arrays, one int at a time
        auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 0x100000001b3ull; };
        mix(std::uint64_t(a.rows()));
        mix(std::uint64_t(a.nonZeros()));
        for (Eigen::Index j = 0; j <= a.outerSize(); ++j) mix(std::uint32_t(a.outerIndexPtr()[j]));
        for (Eigen::Index p = 0; p < a.nonZeros(); ++p) mix(std::uint32_t(a.innerIndexPtr()[p]));
        return h;
    }
    static bool samePattern(const Entry& e, const Eigen::SparseMatrix<double>& a) {
        if (e.outer.size() != std::size_t(a.outerSize()) + 1 || e.inner.size() != std::size_t(a.nonZeros()))
            return false;
        return std::equal(e.outer.begin(), e.outer.end(), a.outerIndexPtr()) &&
               std::equal(e.inner.begin(), e.inner.end(), a.innerIndexPtr());
    }

    std::unordered_map<std::uint64_t, Entry> entries_;
    SymmetricPatternAnalysis::Workspace workspace_;
    std::size_t maxBytes_ = kDefaultBytes, bytes_ = 0;
    std::uint64_t generation_ = 0, hits_ = 0, misses_ = 0;
};

class SymmetricPatternLu {
#if defined(__GNUC__) || defined(__clang__)
    using Pair = double __attribute__((vector_size(16)));  // two doubles (GCC and Clang vector extension)
#endif

public:
    /// The ordering and the elimination tree of `a`'s pattern (square, column-major): found in `cache` when it holds
    /// the pattern, computed (and offered to it) otherwise. A pattern that is not symmetric is remembered as such,
    /// and factorize refuses it.
    void analyzePattern(const Eigen::SparseMatrix<double>& a, SymmetricPatternCache* cache = nullptr) {
        analyse(a, cache, true);
    }

    /// As analyzePattern for a pattern that is not expected back: analysed with `cache`'s workspace (when given) and
    /// not offered to it.
    void analyzePatternOnce(const Eigen::SparseMatrix<double>& a, SymmetricPatternCache* cache) {
        analyse(a, cache, false);
    }

    /// For a caller that keeps this analysis for a matrix of the same pattern: marks it used in `cache` (when it came
    /// from there), so that the cache keeps it as if analyzePattern had looked it up.
    void keepAnalysis(SymmetricPatternCache* cache) const {
        if (cache && an_) cache->keep(key_, an_.get());
    }

    /// Factors `a` (the pattern analyzePattern saw). False when a pivot is zero or not finite. With `symmetricValues`
    /// the caller promises a = a^T: only L is computed (U = L^T), half the work.
    bool factorize(const Eigen::SparseMatrix<double>& a, bool symmetricValues = false) {
        if (!a.isCompressed()) {
            Eigen::SparseMatrix<double> compressed = a;
            compressed.makeCompressed();
            return factorize(compressed, symmetricValues);
        }
        if (!an_ || !an_->symmetric || int(a.rows()) != an_->n || a.nonZeros() != an_->nonZeros) return false;
        const SymmetricPatternAnalysis& an = *an_;
        const int n = an.n;
        const double* value = a.valuePtr();
        d_.assign(std::size_t(n), 0.0);
        filled_.assign(std::size_t(n), 0);
        symmetric_ = symmetricValues;
        if (symmetricValues) return factorizeSymmetric(value);
        yz_.assign(2 * std::size_t(n), 0.0);
        lu_.resize(2 * nnz_);
        const int* lowerRow = an.lowerRow.data();
        double* lu = lu_.data();
        double* yz = yz_.data();
        for (int k = 0; k < n; ++k) {
            // Column k of P A P^T above the diagonal into y and row k left of it into z; their common pattern (the
            // rows of L reached from it through the elimination tree) is an.reach in topological order. y and z
            // are interleaved (yz[2 i], yz[2 i + 1]), as are L's and U's entries (lu[2 p], lu[2 p + 1]): the
            // elimination of one column updates both with the same row indices.
            for (int e = an.upperStart[std::size_t(k)]; e < an.upperStart[std::size_t(k) + 1]; ++e)
                yz[2 * std::size_t(an.upperRow[std::size_t(e)])] += value[an.upperAt[std::size_t(e)]];
            double dk = yz[2 * std::size_t(k)];
            yz[2 * std::size_t(k)] = 0.0;
            const int r0 = an.reachStart[std::size_t(k)], r1 = an.reachStart[std::size_t(k) + 1];
            for (int e = an.lowerStart[std::size_t(k)]; e < an.lowerStart[std::size_t(k) + 1]; ++e) {
                yz[2 * std::size_t(an.lowerCol[std::size_t(e)]) + 1] += value[an.lowerAt[std::size_t(e)]];
            }
            for (int t = r0; t < r1;) {
                const int i = an.reach[std::size_t(t)];
#if defined(__GNUC__) || defined(__clang__)
                if (const int run = an.reachRun[std::size_t(t)]; run > 1) {
                    switch (run) {
                        case 2: eliminateRunPair<2>(i, lowerRow, lu, yz, dk); break;
                        case 3: eliminateRunPair<3>(i, lowerRow, lu, yz, dk); break;
                        default: eliminateRunPair<4>(i, lowerRow, lu, yz, dk); break;
                    }
                    t += run;
                    continue;
                }
#endif
                ++t;
                const double yi = yz[2 * std::size_t(i)], zi = yz[2 * std::size_t(i) + 1];
                yz[2 * std::size_t(i)] = 0.0;
                yz[2 * std::size_t(i) + 1] = 0.0;
                const int begin = an.colPtr[std::size_t(i)], end = begin + filled_[std::size_t(i)];
                // Both updates as one two-lane operation: lane by lane the same multiplication and subtraction, so
                // the same bits as the scalar form (no reduction, and -ffp-contract=off keeps them unfused).
#if defined(__GNUC__) || defined(__clang__)
                const Pair yzi = {yi, zi};
#pragma GCC unroll 4
                for (int p = begin; p < end; ++p) {
                    double* target = yz + 2 * std::size_t(lowerRow[p]);
                    Pair t, f;
                    std::memcpy(&t, target, sizeof t);
                    std::memcpy(&f, lu + 2 * std::size_t(p), sizeof f);
                    t -= f * yzi;
                    std::memcpy(target, &t, sizeof t);
                }
#else
                for (int p = begin; p < end; ++p) {
                    double* target = yz + 2 * std::size_t(lowerRow[p]);
                    target[0] -= lu[2 * std::size_t(p)] * yi;
                    target[1] -= lu[2 * std::size_t(p) + 1] * zi;
                }
#endif
                const double lki = zi / d_[std::size_t(i)];  // L(k, i)
                const double uik = yi / d_[std::size_t(i)];  // U(i, k)
                dk -= lki * yi;
                lu[2 * std::size_t(end)] = lki;
                lu[2 * std::size_t(end) + 1] = uik;
                ++filled_[std::size_t(i)];
            }
            if (!(dk != 0.0) || !std::isfinite(dk)) return false;
            d_[std::size_t(k)] = dk;
        }
        return true;
    }

    /// The analysed order's inverse permutation (old index -> new), the one readsSymmetric compares; nullptr when
    /// the pattern is not symmetric (then every entry is read).
    const int* symmetricOrder() const { return an_ && an_->symmetric ? an_->iperm.data() : nullptr; }
    /// Whether factorize(a, true) reads a's entry (row, col) of the analysed pattern: it reads only those on and above
    /// the diagonal of P A P^T, so a caller promising symmetric values need not compute the others.
    /// (A pattern factorize refuses has no order: every entry counts as read.)
    bool readsSymmetric(int row, int col) const {
        if (!an_ || !an_->symmetric) return true;
        return an_->iperm[std::size_t(row)] <= an_->iperm[std::size_t(col)];
    }

    /// x with A x = b, from the last factorisation.
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
        const SymmetricPatternAnalysis& an = *an_;
        const int n = an.n;
        std::vector<double>& w = work_;
        w.resize(std::size_t(n));
        for (int k = 0; k < n; ++k) w[std::size_t(k)] = b[an.perm[std::size_t(k)]];
        // L's entry p at lower[stride p], U's at upper[stride p] (the same array after an L D L^T factorisation).
        const double* lower = symmetric_ ? l_.data() : lu_.data();
        const double* upper = symmetric_ ? l_.data() : lu_.data() + 1;
        const std::size_t stride = symmetric_ ? 1 : 2;
        for (int j = 0; j < n; ++j) {  // L w' = w
            const double wj = w[std::size_t(j)];
            if (wj == 0.0) continue;
            int p = an.colPtr[std::size_t(j)];
            const int end = an.colPtr[std::size_t(j) + 1];
#if defined(__GNUC__) || defined(__clang__)
            // Two rows at a time, lane by lane the scalar loop's operations (the rows of a column are distinct).
            const Pair wjj = {wj, wj};
            for (; p + 1 < end; p += 2) {
                double* t0 = w.data() + an.lowerRow[std::size_t(p)];
                double* t1 = w.data() + an.lowerRow[std::size_t(p) + 1];
                const Pair lp = {lower[stride * std::size_t(p)], lower[stride * (std::size_t(p) + 1)]};
                Pair t = {*t0, *t1};
                t -= lp * wjj;
                *t0 = t[0];
                *t1 = t[1];
            }
#endif
            for (; p < end; ++p)
                w[std::size_t(an.lowerRow[std::size_t(p)])] -= lower[stride * std::size_t(p)] * wj;
        }
        for (int j = 0; j < n; ++j) w[std::size_t(j)] /= d_[std::size_t(j)];
        for (int j = n - 1; j >= 0; --j) {  // U w'' = w'
            double s = w[std::size_t(j)];
            for (int p = an.colPtr[std::size_t(j)]; p < an.colPtr[std::size_t(j) + 1]; ++p)
                s -= upper[stride * std::size_t(p)] * w[std::size_t(an.lowerRow[std::size_t(p)])];
            w[std::size_t(j)] = s;
        }
        Eigen::VectorXd x(n);
        for (int k = 0; k < n; ++k) x[an.perm[std::size_t(k)]] = w[std::size_t(k)];
        return x;
    }

    /// Entries of L below its diagonal (U above it has as many).
    std::size_t factorNonZeros() const { return nnz_; }

private:
    // The L D L^T form of factorize: L's entries in their own array (l_[p]) and one running row (y_), so the
    // elimination's loads are consecutive; the operations are those of the L D U form with y = z.
    bool factorizeSymmetric(const double* value) {
        const SymmetricPatternAnalysis& an = *an_;
        const int n = an.n;
        const int* lowerRow = an.lowerRow.data();
        l_.resize(nnz_);
        y_.assign(std::size_t(n), 0.0);
        double* l = l_.data();
        double* y = y_.data();
        for (int k = 0; k < n; ++k) {
            for (int e = an.upperStart[std::size_t(k)]; e < an.upperStart[std::size_t(k) + 1]; ++e)
                y[an.upperRow[std::size_t(e)]] += value[an.upperAt[std::size_t(e)]];
            double dk = y[k];
            y[k] = 0.0;
            for (int t = an.reachStart[std::size_t(k)]; t < an.reachStart[std::size_t(k) + 1];) {
                const int i = an.reach[std::size_t(t)];
                const int run = an.reachRun[std::size_t(t)];
                t += run;
                if (run == 1) {
                    const double yi = y[i];
                    y[i] = 0.0;
                    const int begin = an.colPtr[std::size_t(i)], end = begin + filled_[std::size_t(i)];
#pragma GCC unroll 4
                    for (int p = begin; p < end; ++p) y[lowerRow[p]] -= l[p] * yi;
                    const double lki = yi / d_[std::size_t(i)];  // L(k, i) = U(i, k)
                    dk -= lki * yi;
                    l[end] = lki;
                    ++filled_[std::size_t(i)];
                    continue;
                }
                switch (run) {
                    case 2: eliminateRun<2>(i, lowerRow, l, y, dk); break;
                    case 3: eliminateRun<3>(i, lowerRow, l, y, dk); break;
                    default: eliminateRun<4>(i, lowerRow, l, y, dk); break;
                }
            }
            if (!(dk != 0.0) || !std::isfinite(dk)) return false;
            d_[std::size_t(k)] = dk;
        }
        return true;
    }

#if defined(__GNUC__) || defined(__clang__)
    // eliminateRun's two-lane form for the L D U branch: L's and U's entries together, y and z together.
    template <int S>
    void eliminateRunPair(int i, const int* lowerRow, double* lu, double* yz, double& dk) {
        const SymmetricPatternAnalysis& an = *an_;
        Pair yzv[S];
        const double* col[S];
        auto load = [](const double* at) {
            Pair v;
            std::memcpy(&v, at, sizeof v);
            return v;
        };
#pragma GCC unroll 4
        for (int g = 0; g < S; ++g) {
            const double* lg = lu + 2 * std::size_t(an.colPtr[std::size_t(i + g)]);
            yzv[g] = load(yz + 2 * std::size_t(i + g));
            yz[2 * std::size_t(i + g)] = 0.0;
            yz[2 * std::size_t(i + g) + 1] = 0.0;
#pragma GCC unroll 4
            for (int h = g + 1; h < S; ++h) {
                const Pair v = load(yz + 2 * std::size_t(i + h)) - load(lg + 2 * (h - g - 1)) * yzv[g];
                std::memcpy(yz + 2 * std::size_t(i + h), &v, sizeof v);
            }
            col[g] = lg + 2 * (S - 1 - g);
        }
        const int m = filled_[std::size_t(i + S - 1)];
        const int* rows = lowerRow + an.colPtr[std::size_t(i + S - 1)];
        for (int q = 0; q < m; ++q) {
            double* target = yz + 2 * std::size_t(rows[q]);
            Pair v = load(target);
#pragma GCC unroll 4
            for (int g = 0; g < S; ++g) v -= load(col[g] + 2 * q) * yzv[g];
            std::memcpy(target, &v, sizeof v);
        }
        // Row k's entries L(k, i + g) and U(i + g, k) in column order, and their share of its diagonal, as one
        // column at a time.
#pragma GCC unroll 4
        for (int g = 0; g < S; ++g) {
            const std::size_t ig = std::size_t(i + g);
            const double yi = yzv[g][0], zi = yzv[g][1];
            const double lki = zi / d_[ig], uik = yi / d_[ig];
            dk -= lki * yi;
            const std::size_t end = std::size_t(an.colPtr[ig] + filled_[ig]);
            lu[2 * end] = lki;
            lu[2 * end + 1] = uik;
            ++filled_[ig];
        }
    }
#endif

    // The elimination of the run of S chained columns i, ..., i + S - 1 from the running row y (row k), then row k's
    // entries L(k, i + g) and their share of its diagonal dk. Column i + g's filled entries are rows i + g + 1, ...,
    // i + S - 1 followed by the m rows column i + S - 1 has filled; each y entry gets its subtractions in column
    // order, as one column at a time.
    template <int S>
    void eliminateRun(int i, const int* lowerRow, double* l, double* y, double& dk) {
        const SymmetricPatternAnalysis& an = *an_;
        double yv[S];
        const double* col[S];
#pragma GCC unroll 4
        for (int g = 0; g < S; ++g) {
            const double* lg = l + an.colPtr[std::size_t(i + g)];
            yv[g] = y[i + g];
            y[i + g] = 0.0;
#pragma GCC unroll 4
            for (int h = g + 1; h < S; ++h) y[i + h] -= lg[h - g - 1] * yv[g];
            col[g] = lg + (S - 1 - g);
        }
        const int last = an.colPtr[std::size_t(i + S - 1)];
        const int m = filled_[std::size_t(i + S - 1)];
        const int* rows = lowerRow + last;
        int q = 0;
#if defined(__GNUC__) || defined(__clang__)
        // Two rows at a time as one two-lane operation: lane by lane the same multiplications and subtractions in
        // the same order, so the same bits as the scalar loop below (the rows of a column are distinct).
        Pair yg[S];
        for (int g = 0; g < S; ++g) yg[g] = Pair{yv[g], yv[g]};
        for (; q + 1 < m; q += 2) {
            double* t0 = y + rows[q];
            double* t1 = y + rows[q + 1];
            Pair v = {*t0, *t1};
#pragma GCC unroll 4
            for (int g = 0; g < S; ++g) {
                Pair c;
                std::memcpy(&c, col[g] + q, sizeof c);
                v -= c * yg[g];
            }
            *t0 = v[0];
            *t1 = v[1];
        }
#endif
        for (; q < m; ++q) {
            double v = y[rows[q]];
#pragma GCC unroll 4
            for (int g = 0; g < S; ++g) v -= col[g][q] * yv[g];
            y[rows[q]] = v;
        }
        // Row k's entries L(k, i + g) in column order, and their share of its diagonal, as one column at a time.
#pragma GCC unroll 4
        for (int g = 0; g < S; ++g) {
            const std::size_t ig = std::size_t(i + g);
            const double lki = yv[g] / d_[ig];
            dk -= lki * yv[g];
            l[an.colPtr[ig] + filled_[ig]] = lki;
            ++filled_[ig];
        }
    }

    std::shared_ptr<const SymmetricPatternAnalysis> an_;
    std::uint64_t key_ = 0;  // an_'s key in the cache it came from (keepAnalysis)

    // analyzePattern (keep: offered to `cache`) and analyzePatternOnce (not).
    void analyse(const Eigen::SparseMatrix<double>& a, SymmetricPatternCache* cache, bool keep) {
        if (!a.isCompressed()) {  // the index arrays are those of compressed storage
            Eigen::SparseMatrix<double> compressed = a;
            compressed.makeCompressed();
            analyse(compressed, cache, keep);
            return;
        }
        key_ = 0;
        an_ = !cache ? SymmetricPatternAnalysis::of(a) : keep ? cache->analysisOf(a, &key_) : cache->analysisOnce(a);
        // The factors' arrays are sized by factorize; it writes every entry before reading it.
        nnz_ = an_->symmetric ? std::size_t(an_->colPtr[std::size_t(an_->n)]) : 0;
    }
    std::vector<double> lu_, d_;  // L(row, j) and U(j, row) of column j's entry p at lu_[2 p], lu_[2 p + 1]
    std::vector<double> l_;       // L(row, j) at l_[p] after a factorisation of symmetric values (symmetric_)
    std::size_t nnz_ = 0;         // entries of L below its diagonal
    bool symmetric_ = false;
    std::vector<int> filled_;  // factorize's scratch
    std::vector<double> yz_, y_;
    mutable std::vector<double> work_;
};

inline std::shared_ptr<const SymmetricPatternAnalysis> SymmetricPatternAnalysis::of(const Eigen::SparseMatrix<double>& a,
                                                                                   Workspace* workspace) {
    Workspace local;
    Workspace& ws = workspace ? *workspace : local;
    auto out = std::make_shared<SymmetricPatternAnalysis>();
    SymmetricPatternAnalysis& r = *out;
    const int n = int(a.rows());
    r.n = n;
    r.nonZeros = a.nonZeros();
    if (a.rows() != a.cols()) return out;
    // A symmetric pattern in sorted order: walking the columns in order and handing each entry (i, j) the next unused
    // entry of column i, that entry is always (j, i) and every entry is handed out once. The walk also records where
    // each entry's transposed partner is stored, which factorize reads row k through.
    if (!a.isCompressed()) return out;
    const int* outer = a.outerIndexPtr();
    const int* inner = a.innerIndexPtr();
    std::vector<int>& position = ws.position;  // entry (i, j) -> the entry (j, i), both in a's storage
    position.resize(std::size_t(a.nonZeros()));
    {
        std::vector<int> next(outer, outer + n);
        for (int j = 0; j < n; ++j) {
            for (int p = outer[j]; p < outer[j + 1]; ++p) {
                const int i = inner[p];
                const int q = next[std::size_t(i)]++;
                if (q >= outer[i + 1] || inner[q] != j) return out;
                position[std::size_t(p)] = q;
            }
        }
    }
    r.symmetric = true;
    // Eigen's AMDOrdering orders the pattern of a + a^T, which for a symmetric pattern in sorted order is a's own
    // index arrays: its minimum-degree routine runs on a copy of a's index arrays (it overwrites its argument and
    // reads no values) for the same order. The copy is made with the room the routine grows it to (nnz + nnz / 5 +
    // 2 n), so that a kept workspace is not reallocated.
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pinv;
    {
        Eigen::SparseMatrix<char>& pattern = ws.pattern;
        const Eigen::Index nnz = a.nonZeros();
        pattern.resize(n, n);
        pattern.resizeNonZeros(nnz + nnz / 5 + 2 * Eigen::Index(n));
        pattern.resizeNonZeros(nnz);
        std::copy(outer, outer + n + 1, pattern.outerIndexPtr());
        std::copy(inner, inner + nnz, pattern.innerIndexPtr());
        Eigen::internal::minimum_degree_ordering(pattern, pinv);
    }
    r.perm.assign(pinv.indices().data(), pinv.indices().data() + n);  // new index -> old index
    r.iperm.assign(std::size_t(n), 0);
    for (int k = 0; k < n; ++k) r.iperm[std::size_t(r.perm[std::size_t(k)])] = k;
    // The elimination tree, the column counts of L, and each row's reach through the tree in the topological order
    // factorize eliminates it: for each entry of column k above the diagonal, in storage order, the path up to an
    // already reached node, that path put before the ones found earlier.
    r.parent.assign(std::size_t(n), -1);
    r.reachStart.assign(std::size_t(n) + 1, 0);
    std::vector<int> count(std::size_t(n), 0), flag(std::size_t(n), -1);
    std::vector<int> path(static_cast<std::size_t>(n), 0), order(static_cast<std::size_t>(n), 0);
    r.reach.reserve(std::size_t(a.nonZeros()));
    for (int k = 0; k < n; ++k) {
        flag[std::size_t(k)] = k;
        int top = n;
        const int old = r.perm[std::size_t(k)];
        for (int p = outer[old]; p < outer[old + 1]; ++p) {
            int i = r.iperm[std::size_t(inner[p])];
            if (i >= k) continue;
            int len = 0;
            for (; flag[std::size_t(i)] != k; i = r.parent[std::size_t(i)]) {
                if (r.parent[std::size_t(i)] == -1) r.parent[std::size_t(i)] = k;
                ++count[std::size_t(i)];
                flag[std::size_t(i)] = k;
                path[std::size_t(len++)] = i;
            }
            while (len > 0) order[std::size_t(--top)] = path[std::size_t(--len)];
        }
        r.reach.insert(r.reach.end(), order.begin() + top, order.end());
        r.reachStart[std::size_t(k) + 1] = int(r.reach.size());
    }
    // Where factorize reads column k (rows <= k) and row k (columns < k) of P A P^T in a's values.
    r.upperStart.assign(std::size_t(n) + 1, 0);
    r.lowerStart.assign(std::size_t(n) + 1, 0);
    const std::size_t half = (std::size_t(a.nonZeros()) + std::size_t(n)) / 2;  // entries on and above the diagonal
    r.upperAt.reserve(half);
    r.upperRow.reserve(half);
    r.lowerAt.reserve(half);
    r.lowerCol.reserve(half);
    for (int k = 0; k < n; ++k) {
        const int old = r.perm[std::size_t(k)];
        for (int p = outer[old]; p < outer[old + 1]; ++p) {
            const int i = r.iperm[std::size_t(inner[p])];
            if (i > k) continue;
            r.upperAt.push_back(p);
            r.upperRow.push_back(i);
        }
        for (int p = outer[old]; p < outer[old + 1]; ++p) {  // row old of a: its column's entries, transposed
            const int j = r.iperm[std::size_t(inner[p])];
            if (j >= k) continue;
            r.lowerAt.push_back(position[std::size_t(p)]);
            r.lowerCol.push_back(j);
        }
        r.upperStart[std::size_t(k) + 1] = int(r.upperAt.size());
        r.lowerStart[std::size_t(k) + 1] = int(r.lowerAt.size());
    }
    r.colPtr.assign(std::size_t(n) + 1, 0);
    for (int k = 0; k < n; ++k) r.colPtr[std::size_t(k) + 1] = r.colPtr[std::size_t(k)] + count[std::size_t(k)];
    // The rows of each column of L, in increasing order (row k enters the columns of its reach).
    r.lowerRow.assign(std::size_t(r.colPtr[std::size_t(n)]), 0);
    std::vector<int> filled(static_cast<std::size_t>(n), 0);
    for (int k = 0; k < n; ++k) {
        for (int t = r.reachStart[std::size_t(k)]; t < r.reachStart[std::size_t(k) + 1]; ++t) {
            const int i = r.reach[std::size_t(t)];
            r.lowerRow[std::size_t(r.colPtr[std::size_t(i)] + filled[std::size_t(i)]++)] = k;
        }
    }
    // Column j chains into j + 1 when its pattern is j + 1's plus row j + 1 itself: then any row that reaches one
    // reaches both, and where the two are next to each other in a reach their entries can be eliminated together.
    std::vector<std::uint8_t> chain(std::size_t(n), 0);
    for (int j = 0; j + 1 < n; ++j)
        chain[std::size_t(j)] =
            r.parent[std::size_t(j)] == j + 1 && count[std::size_t(j)] == count[std::size_t(j) + 1] + 1;
    r.reachRun.assign(r.reach.size(), 0);
    for (int k = 0; k < n; ++k) {
        const int end = r.reachStart[std::size_t(k) + 1];
        for (int t = r.reachStart[std::size_t(k)]; t < end;) {
            int s = 1;
            while (s < kMaxRun && t + s < end && chain[std::size_t(r.reach[std::size_t(t + s - 1)])] &&
                   r.reach[std::size_t(t + s)] == r.reach[std::size_t(t + s - 1)] + 1)
                ++s;
            r.reachRun[std::size_t(t)] = std::uint8_t(s);
            t += s;
        }
    }
    return out;
}

}  // namespace unison

