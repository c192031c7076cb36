// tests/test_symmetric_lu.cpp — SymmetricPatternLu (core/symmetric_pattern_lu.h), the sparse LU on a symmetric
// pattern that the active-set path factors its systems with: answers against a dense LU, refusals, the pattern cache,
// and its paired and run-wise eliminations checked bit for bit against one entry at a time; and the column assembly
// of its systems (core/body_space_solve.h) against Eigen's setFromTriplets, bit for bit.
#include "test_support.h"

#include "body_space_solve.h"
#include "symmetric_pattern_lu.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

using namespace unison;

TEST_SUITE("symmetric_lu") {

TEST_CASE("symmetric-pattern LU: solves a perturbed quasi-definite system as a dense LU does, refuses what it cannot, and reuses analyses") {
    // [M, J~^T; J, -eps G] as the active-set path builds it: 12 bodies in a chain, each pair joined by two rows, the
    // momentum rows of every other row carrying 0.6 times a second row (a slipping contact's tangent column).
    const int bodies = 12, nb = 3 * bodies, rows = 2 * (bodies - 1), n = nb + rows;
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
    auto put = [&](int i, int j, double v) {
        entries.emplace_back(i, j, v);
        dense(i, j) += v;
    };
    for (int k = 0; k < nb; ++k) put(k, k, k % 3 == 2 ? 0.2 : 1.5);
    for (int r = 0; r < rows; ++r) {
        const int a = r / 2, col = nb + r;
        for (int s = 0; s < 2; ++s) {
            for (int c = 0; c < 3; ++c) {
                const int d = 3 * (a + s) + c;
                const double j = (s == 0 ? -1.0 : 1.0) * (0.3 + 0.1 * c + 0.05 * r);
                put(col, d, j);
                put(d, col, j + (r % 2 == 0 ? 0.6 * (0.2 - 0.07 * c) : 0.0));
            }
        }
        put(col, col, -1e-7);
    }
    Eigen::SparseMatrix<double> a(n, n);
    a.setFromTriplets(entries.begin(), entries.end());
    SymmetricPatternLu lu;
    lu.analyzePattern(a);
    REQUIRE(lu.factorize(a));
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = std::sin(0.7 * i) + (i >= nb ? 0.01 : 0.0);
    const Eigen::VectorXd x = lu.solve(b);
    const Eigen::VectorXd reference = dense.partialPivLu().solve(b);
    const double backward = (a * x - b).norm() / (a.norm() * x.norm() + b.norm());
    CHECK(backward < 1e-14);
    CHECK((x - reference).norm() <= 1e-6 * reference.norm());  // the system is ill-conditioned by design (eps 1e-7)
    // Bits repeat (a second factorisation of the same values, with the ordering reused).
    REQUIRE(lu.factorize(a));
    const Eigen::VectorXd again = lu.solve(b);
    CHECK(std::memcmp(x.data(), again.data(), sizeof(double) * std::size_t(n)) == 0);
    // A structurally zero pivot is refused, and so is a pattern that is not symmetric.
    Eigen::SparseMatrix<double> singular(2, 2);
    singular.insert(0, 1) = 1.0;
    singular.insert(1, 0) = 1.0;
    SymmetricPatternLu lu2;
    lu2.analyzePattern(singular);
    CHECK_FALSE(lu2.factorize(singular));
    Eigen::SparseMatrix<double> lopsided(2, 2);
    lopsided.insert(0, 0) = 1.0;
    lopsided.insert(1, 1) = 1.0;
    lopsided.insert(1, 0) = 1.0;
    SymmetricPatternLu lu3;
    lu3.analyzePattern(lopsided);
    CHECK_FALSE(lu3.factorize(lopsided));

    // The analysis cache: the same pattern with other values is found (and factors to the bits of a fresh analysis),
    // another pattern is not; an analysis unused for a whole generation is dropped; the size bound holds.
    SymmetricPatternCache cache;
    SymmetricPatternLu cachedLu;
    cachedLu.analyzePattern(a, &cache);
    CHECK(cache.size() == 1);
    CHECK(cache.misses() == 1);
    Eigen::SparseMatrix<double> scaled = 2.0 * a;
    cachedLu.analyzePattern(scaled, &cache);
    CHECK(cache.hits() == 1);
    REQUIRE(cachedLu.factorize(scaled));
    SymmetricPatternLu fresh;
    fresh.analyzePattern(scaled);
    REQUIRE(fresh.factorize(scaled));
    const Eigen::VectorXd viaCache = cachedLu.solve(b), viaFresh = fresh.solve(b);
    CHECK(std::memcmp(viaCache.data(), viaFresh.data(), sizeof(double) * std::size_t(n)) == 0);
    Eigen::SparseMatrix<double> other = a;
    other.coeffRef(0, n - 1) = 0.5;  // a new entry and its mirror: another symmetric pattern
    other.coeffRef(n - 1, 0) = 0.5;
    other.makeCompressed();
    cachedLu.analyzePattern(other, &cache);
    CHECK(cache.misses() == 2);
    CHECK(cache.size() == 2);
    REQUIRE(cachedLu.factorize(other));
    // Only `a` is used from here on: `other` (a small entry) survives the end of the generation it was used in and of
    // kKeepSmallGenerations - 1 more, and is dropped when a kKeepSmallGenerations-th one without it ends.
    for (std::uint64_t g = 0; g < SymmetricPatternCache::kKeepSmallGenerations; ++g) {
        cache.nextGeneration();
        CHECK(cache.size() == 2);
        cachedLu.analyzePattern(a, &cache);
    }
    cache.nextGeneration();
    CHECK(cache.size() == 1);
    cachedLu.analyzePattern(other, &cache);  // analysed again
    CHECK(cache.misses() == 3);
    // A full cache makes room from the small entries kept past kKeepGenerations, never from recent ones.
    {
        SymmetricPatternCache probe;
        SymmetricPatternLu probeLu;
        probeLu.analyzePattern(a, &probe);
        const std::size_t sizeA = probe.bytes();
        probeLu.analyzePattern(other, &probe);
        const std::size_t sizeOther = probe.bytes() - sizeA;
        SymmetricPatternCache full(sizeA + sizeOther - 1);  // room for one of the two
        SymmetricPatternLu fullLu;
        fullLu.analyzePattern(a, &full);
        for (std::uint64_t g = 0; g < SymmetricPatternCache::kKeepGenerations; ++g) full.nextGeneration();
        fullLu.analyzePattern(other, &full);  // `a` was used kKeepGenerations - 1 generations before: it stays
        CHECK(full.size() == 1);
        fullLu.analyzePattern(a, &full);
        CHECK(full.hits() == 1);
        for (std::uint64_t g = 0; g <= SymmetricPatternCache::kKeepGenerations; ++g) full.nextGeneration();
        CHECK(full.size() == 1);  // a small entry outlives kKeepGenerations
        fullLu.analyzePattern(other, &full);  // and makes room for a new one
        CHECK(full.size() == 1);
        CHECK(full.bytes() == sizeOther);
        fullLu.analyzePattern(other, &full);
        CHECK(full.hits() == 2);
    }
    // An entry above kSmallEntryBytes (a tridiagonal system of 60000 unknowns) is dropped after kKeepGenerations.
    {
        const int big = 60000;
        std::vector<Eigen::Triplet<double>> entries;
        for (int i = 0; i < big; ++i) {
            entries.emplace_back(i, i, 4.0);
            if (i + 1 < big) {
                entries.emplace_back(i, i + 1, -1.0);
                entries.emplace_back(i + 1, i, -1.0);
            }
        }
        Eigen::SparseMatrix<double> chain(big, big);
        chain.setFromTriplets(entries.begin(), entries.end());
        SymmetricPatternCache bigCache;
        SymmetricPatternLu chainLu;
        chainLu.analyzePattern(chain, &bigCache);
        REQUIRE(bigCache.size() == 1);
        CHECK(bigCache.bytes() > SymmetricPatternCache::kSmallEntryBytes);
        for (std::uint64_t g = 0; g < SymmetricPatternCache::kKeepGenerations; ++g) {
            bigCache.nextGeneration();
            CHECK(bigCache.size() == 1);
        }
        bigCache.nextGeneration();
        CHECK(bigCache.size() == 0);
        REQUIRE(chainLu.factorize(chain));  // the factor keeps its own analysis
    }
    SymmetricPatternCache tiny(64);  // smaller than any analysis: nothing is kept, answers are unchanged
    SymmetricPatternLu tinyLu;
    tinyLu.analyzePattern(a, &tiny);
    CHECK(tiny.size() == 0);
    CHECK(tiny.bytes() == 0);
    REQUIRE(tinyLu.factorize(a));
    const Eigen::VectorXd viaTiny = tinyLu.solve(b);
    CHECK(std::memcmp(viaTiny.data(), x.data(), sizeof(double) * std::size_t(n)) == 0);
}

TEST_CASE("symmetric-pattern LU: the paired and run-wise eliminations give the bits of one entry at a time") {
    // A system on a symmetric pattern (a 2D grid of 3-dof bodies with contact-like rows between neighbours), factored
    // by SymmetricPatternLu and by the textbook up-looking L D U below, written one scalar operation at a time in the
    // same order over the same analysis: with unsymmetric values (every third row carrying a slip share) through
    // the two-lane L D U branch, and with symmetric values through the L D L^T branch. Chained columns (a body's
    // degrees of freedom) are eliminated in runs by both branches.
    for (const bool symmetricValues : {false, true}) {
        CAPTURE(symmetricValues);
        const int side = 6, bodies = side * side, nb = 3 * bodies;
        std::vector<Eigen::Triplet<double>> entries;
        for (int k = 0; k < nb; ++k) entries.emplace_back(k, k, 1.0 + 0.25 * (k % 5));
        int col = nb;
        for (int y = 0; y < side; ++y) {
            for (int x = 0; x < side; ++x) {
                for (int dir = 0; dir < 2; ++dir) {
                    const int nx = x + (dir == 0 ? 1 : 0), ny = y + (dir == 1 ? 1 : 0);
                    if (nx >= side || ny >= side) continue;
                    const int ends[2] = {y * side + x, ny * side + nx};
                    for (int s = 0; s < 2; ++s) {
                        for (int c = 0; c < 3; ++c) {
                            const int d = 3 * ends[s] + c;
                            const double j = (s == 0 ? -1.0 : 1.0) * (0.4 + 0.1 * c + 0.01 * (col % 7));
                            entries.emplace_back(col, d, j);
                            const bool slip = !symmetricValues && col % 3 == 0;
                            entries.emplace_back(d, col, j + (slip ? 0.3 * std::cos(0.5 * c + col) : 0.0));
                        }
                    }
                    entries.emplace_back(col, col, -1e-6 * (1.0 + 0.1 * (col % 4)));
                    ++col;
                }
            }
        }
        const int n = col;
        Eigen::SparseMatrix<double> a(n, n);
        a.setFromTriplets(entries.begin(), entries.end());
        a.makeCompressed();
        Eigen::VectorXd b(n);
        for (int i = 0; i < n; ++i) b[i] = std::sin(0.37 * i + 0.1);
        SymmetricPatternLu lu;
        lu.analyzePattern(a);
        REQUIRE(lu.factorize(a, symmetricValues));
        const Eigen::VectorXd x = lu.solve(b);
        CHECK((a * x - b).norm() <= 1e-10 * b.norm());

        const auto an = SymmetricPatternAnalysis::of(a);
        REQUIRE(an->symmetric);
        CHECK(std::count_if(an->reachRun.begin(), an->reachRun.end(), [](std::uint8_t r) { return r > 1; }) > 0);
        const double* value = a.valuePtr();
        const std::size_t nnzL = std::size_t(an->colPtr[std::size_t(n)]);
        std::vector<double> l(nnzL, 0.0), u(nnzL, 0.0), d(std::size_t(n), 0.0);
        std::vector<double> yv(std::size_t(n), 0.0), zv(std::size_t(n), 0.0);
        std::vector<int> filled(std::size_t(n), 0);
        for (int k = 0; k < n; ++k) {
            for (int e = an->upperStart[std::size_t(k)]; e < an->upperStart[std::size_t(k) + 1]; ++e)
                yv[std::size_t(an->upperRow[std::size_t(e)])] += value[an->upperAt[std::size_t(e)]];
            for (int e = an->lowerStart[std::size_t(k)]; e < an->lowerStart[std::size_t(k) + 1]; ++e)
                zv[std::size_t(an->lowerCol[std::size_t(e)])] += value[an->lowerAt[std::size_t(e)]];
            double dk = yv[std::size_t(k)];
            yv[std::size_t(k)] = 0.0;
            for (int t = an->reachStart[std::size_t(k)]; t < an->reachStart[std::size_t(k) + 1]; ++t) {
                const int i = an->reach[std::size_t(t)];
                const double yi = yv[std::size_t(i)], zi = zv[std::size_t(i)];
                yv[std::size_t(i)] = 0.0;
                zv[std::size_t(i)] = 0.0;
                const int begin = an->colPtr[std::size_t(i)], end = begin + filled[std::size_t(i)];
                for (int p = begin; p < end; ++p) {
                    const int r = an->lowerRow[std::size_t(p)];
                    yv[std::size_t(r)] = yv[std::size_t(r)] - l[std::size_t(p)] * yi;
                    zv[std::size_t(r)] = zv[std::size_t(r)] - u[std::size_t(p)] * zi;
                }
                const double lki = zi / d[std::size_t(i)], uik = yi / d[std::size_t(i)];
                dk -= lki * yi;
                l[std::size_t(end)] = lki;
                u[std::size_t(end)] = uik;
                ++filled[std::size_t(i)];
            }
            d[std::size_t(k)] = dk;
        }
        std::vector<double> w(std::size_t(n), 0.0);
        for (int k = 0; k < n; ++k) w[std::size_t(k)] = b[an->perm[std::size_t(k)]];
        for (int j = 0; j < n; ++j) {
            if (w[std::size_t(j)] == 0.0) continue;
            for (int p = an->colPtr[std::size_t(j)]; p < an->colPtr[std::size_t(j) + 1]; ++p)
                w[std::size_t(an->lowerRow[std::size_t(p)])] -= l[std::size_t(p)] * w[std::size_t(j)];
        }
        for (int j = 0; j < n; ++j) w[std::size_t(j)] /= d[std::size_t(j)];
        for (int j = n - 1; j >= 0; --j) {
            double s = w[std::size_t(j)];
            for (int p = an->colPtr[std::size_t(j)]; p < an->colPtr[std::size_t(j) + 1]; ++p)
                s -= u[std::size_t(p)] * w[std::size_t(an->lowerRow[std::size_t(p)])];
            w[std::size_t(j)] = s;
        }
        Eigen::VectorXd reference(n);
        for (int k = 0; k < n; ++k) reference[an->perm[std::size_t(k)]] = w[std::size_t(k)];
        CHECK(std::memcmp(x.data(), reference.data(), sizeof(double) * std::size_t(n)) == 0);
    }
}

TEST_CASE("symmetric-pattern LU: with symmetric values it reads one entry of each mirrored pair, as readsSymmetric says") {
    // A body-space matrix M + J^T H J with symmetric values: 10 bodies in a chain, each pair coupled by a 3 x 3 block.
    const int bodies = 10, n = 3 * bodies;
    std::vector<Eigen::Triplet<double>> entries;
    for (int k = 0; k < n; ++k) entries.emplace_back(k, k, 4.0 + 0.1 * k);
    for (int b = 0; b + 1 < bodies; ++b) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                const double v = 0.3 * std::cos(1.3 * b + 0.7 * r + 0.4 * c);
                entries.emplace_back(3 * b + r, 3 * (b + 1) + c, v);
                entries.emplace_back(3 * (b + 1) + c, 3 * b + r, v);
            }
        }
    }
    Eigen::SparseMatrix<double> s(n, n);
    s.setFromTriplets(entries.begin(), entries.end());
    SymmetricPatternLu lu;
    lu.analyzePattern(s);
    // Exactly the diagonal and one entry of each off-diagonal pair are read.
    Eigen::SparseMatrix<double> garbled = s;
    int read = 0;
    for (int j = 0; j < n; ++j) {
        for (Eigen::SparseMatrix<double>::InnerIterator it(garbled, j); it; ++it) {
            const bool r = lu.readsSymmetric(int(it.row()), j);
            CHECK(r != (int(it.row()) != j && lu.readsSymmetric(j, int(it.row()))));
            if (r) {
                ++read;
            } else {
                it.valueRef() = 1e6;  // not read: any value gives the same factors
            }
        }
    }
    CHECK(read == (int(s.nonZeros()) + n) / 2);
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = std::sin(0.3 * i + 0.2);
    REQUIRE(lu.factorize(s, true));
    const Eigen::VectorXd x = lu.solve(b);
    CHECK((s * x - b).norm() <= 1e-14 * b.norm() * 10.0);
    REQUIRE(lu.factorize(garbled, true));
    const Eigen::VectorXd y = lu.solve(b);
    CHECK(std::memcmp(x.data(), y.data(), sizeof(double) * std::size_t(n)) == 0);
    // The unsymmetric variant reads every entry: the garbled matrix is another system there.
    REQUIRE(lu.factorize(garbled, false));
    CHECK((s * lu.solve(b) - b).norm() > 1e-3 * b.norm());
}

TEST_CASE("column assembly: short and long columns give setFromTriplets' matrix to the bit, and a refill its values") {
    // Entries in a scrambled order with many duplicates whose sums depend on their order (values of very different
    // sizes): few per column (the insertion sort) and dozens per column (bucketed by row first).
    for (const int perColumn : {3, 60}) {
        CAPTURE(perColumn);
        const int n = 50;
        std::uint64_t state = 0x9e3779b97f4a7c15ull;
        auto next = [&state]() {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return state >> 33;
        };
        std::vector<Eigen::Triplet<double>> entries;
        for (int t = 0; t < n * perColumn; ++t) {
            const int col = int(next() % std::uint64_t(n));
            const int row = int(next() % std::uint64_t(perColumn < 10 ? n : 12)) + (perColumn < 10 ? 0 : col % (n - 12));
            const double value = (next() % 2 ? 1.0 : -1.0) * std::ldexp(1.0 + double(next() % 1000) / 7.0,
                                                                         int(next() % 60) - 30);
            entries.emplace_back(row, col, value);
        }
        Eigen::SparseMatrix<double> expected(n, n);
        expected.setFromTriplets(entries.begin(), entries.end());
        expected.makeCompressed();
        auto same = [&](const Eigen::SparseMatrix<double>& got) {
            REQUIRE(got.nonZeros() == expected.nonZeros());
            CHECK(std::equal(got.outerIndexPtr(), got.outerIndexPtr() + n + 1, expected.outerIndexPtr()));
            CHECK(std::equal(got.innerIndexPtr(), got.innerIndexPtr() + got.nonZeros(), expected.innerIndexPtr()));
            CHECK(std::memcmp(got.valuePtr(), expected.valuePtr(), sizeof(double) * std::size_t(got.nonZeros())) == 0);
        };
        detail::ColumnAssembly ws;
        Eigen::SparseMatrix<double> plain, planned;
        detail::assembleColumns(n, entries, plain, ws);
        same(plain);
        detail::assembleColumns<true>(n, entries, planned, ws);
        same(planned);
        // A refill with the same sequence of positions writes the same sums.
        std::fill(planned.valuePtr(), planned.valuePtr() + planned.nonZeros(), 0.0);
        REQUIRE(detail::refillColumns(n, entries, planned, ws));
        same(planned);
        // The bucketed columns really were long, the short ones short (both branches ran).
        CHECK((entries.size() >= detail::kBucketRowsPerColumn * std::size_t(n)) == (perColumn >= 32));
    }
}

}  // TEST_SUITE
