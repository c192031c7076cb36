// tests/test_lcp.cpp — the Lemke solver's contract (core/lcp.h): outcomes, residual checks, caps and budgets,
// warm starts and determinism, on small problems whose answers are known exactly.
#include "test_support.h"

#include <unison/lcp.h>

#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <string>

#include <zlib.h>

using namespace unison;

namespace {

Lcp makeLcp(int n, std::initializer_list<double> A, std::initializer_list<double> b) {
    Lcp p(n);
    p.A.assign(A);
    p.b.assign(b);
    return p;
}

// Deterministic symmetric positive definite A = L L^T + 0.1 I with a mixed-sign b.
Lcp randomPd(int n, std::uint64_t seed) {
    std::uint64_t s = seed;
    auto rnd = [&]() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return double(s >> 11) / double(1ULL << 53) - 0.5;
    };
    std::vector<double> L(std::size_t(n * n));
    for (auto& x : L) x = rnd();
    Lcp p(n);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            double sum = i == j ? 0.1 : 0.0;
            for (int k = 0; k < n; ++k) sum += L[std::size_t(i * n + k)] * L[std::size_t(j * n + k)];
            p.at(i, j) = sum;
        }
        p.b[std::size_t(i)] = rnd();
    }
    return p;
}

void checkSolution(const Lcp& p, const LcpResult& r) {
    REQUIRE(r.status == LcpStatus::solved);
    for (int i = 0; i < p.n; ++i) {
        double w = p.b[std::size_t(i)];
        for (int j = 0; j < p.n; ++j) w += p.at(i, j) * r.z[std::size_t(j)];
        CHECK(w == doctest::Approx(r.w[std::size_t(i)]).epsilon(1e-12).scale(1.0));
        CHECK(r.z[std::size_t(i)] >= -1e-12);
        CHECK(w >= -1e-12);
        CHECK(std::fabs(std::min(r.z[std::size_t(i)], w)) <= 1e-12);
    }
    CHECK(r.scaledResidual <= 1e-9);
}

}  // namespace

namespace {

// tests/data/pyramid40_fallback_lcp.bin.gz: the frictionless LCP (4760 contacts) of a 40-row pyramid laid out
// like Box2D v3's large-pyramid benchmark (scenes::largePyramidScene(40)) in its step 198, where its friction LCP
// had failed. Little-endian: int32 n, int32 nnz, int32 rowStart[n + 1], int32 cols[nnz], float64 vals[nnz],
// float64 b[n], float64 maxAbs.
SparseLcp loadPyramid40Fallback() {
    const std::string path = std::string(UNISON_SOURCE_DIR) + "/tests/data/pyramid40_fallback_lcp.bin.gz";
    gzFile f = gzopen(path.c_str(), "rb");
    REQUIRE(f != nullptr);
    auto readAll = [&](void* dst, std::size_t bytes) {
        REQUIRE(gzread(f, dst, unsigned(bytes)) == int(bytes));
    };
    SparseLcp p;
    int nnz = 0;
    readAll(&p.n, 4);
    readAll(&nnz, 4);
    p.rowStart.resize(std::size_t(p.n) + 1);
    p.cols.resize(std::size_t(nnz));
    p.vals.resize(std::size_t(nnz));
    p.b.resize(std::size_t(p.n));
    readAll(p.rowStart.data(), 4 * p.rowStart.size());
    readAll(p.cols.data(), 4 * p.cols.size());
    readAll(p.vals.data(), 8 * p.vals.size());
    readAll(p.b.data(), 8 * p.b.size());
    readAll(&p.maxAbs, 8);
    gzclose(f);
    return p;
}

}  // namespace

TEST_SUITE("lcp") {

TEST_CASE("b >= 0 is solved by z = 0 without pivoting") {
    LemkeSolver s;
    const LcpResult r = s.solve(makeLcp(2, {2, 1, 1, 2}, {1, 0}));
    CHECK(r.status == LcpStatus::solved);
    CHECK(r.pivots == 0);
    CHECK(r.z == std::vector<double>{0.0, 0.0});
}

TEST_CASE("a 2x2 problem with a known answer") {
    // A = [[2,1],[1,2]], b = [-5,-6]: both active, z = A^-1 (-b) = (4/3, 7/3).
    LemkeSolver s;
    const Lcp p = makeLcp(2, {2, 1, 1, 2}, {-5, -6});
    const LcpResult r = s.solve(p);
    checkSolution(p, r);
    CHECK(r.z[0] == doctest::Approx(4.0 / 3.0).epsilon(1e-15));
    CHECK(r.z[1] == doctest::Approx(7.0 / 3.0).epsilon(1e-15));
    CHECK(r.basis == std::vector<int>{0, 1});
    // b = [-1, 4]: only z_0 active, z_0 = 1/2, w_1 = 4.5.
    const Lcp q = makeLcp(2, {2, 1, 1, 2}, {-1, 4});
    const LcpResult rq = s.solve(q);
    checkSolution(q, rq);
    CHECK(rq.z[0] == doctest::Approx(0.5).epsilon(1e-15));
    CHECK(rq.z[1] == 0.0);
    CHECK(rq.w[1] == doctest::Approx(4.5).epsilon(1e-15));
}

TEST_CASE("random positive definite problems are solved; a warm start from the basis needs no pivot") {
    LemkeSolver s;
    for (int n : {1, 2, 5, 20, 60}) {
        CAPTURE(n);
        const Lcp p = randomPd(n, std::uint64_t(n) * 977u);
        const LcpResult cold = s.solve(p);
        checkSolution(p, cold);
        LcpOptions o;
        o.warmBasis = &cold.basis;
        const LcpResult warm = s.solve(p, o);
        checkSolution(p, warm);
        CHECK(warm.warmStarted == !cold.basis.empty());
        CHECK(warm.pivots == 0);
        for (int i = 0; i < n; ++i) CHECK(warm.z[std::size_t(i)] == doctest::Approx(cold.z[std::size_t(i)]).epsilon(1e-12).scale(1.0));
    }
}

TEST_CASE("a wrong warm basis still converges to the same unique solution") {
    LemkeSolver s;
    const Lcp p = randomPd(30, 4242);
    const LcpResult cold = s.solve(p);
    checkSolution(p, cold);
    for (const std::vector<int>& guess : {std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, std::vector<int>{29, 3, 3, 17},
                                          std::vector<int>{-1, 2}, std::vector<int>{100}}) {
        LcpOptions o;
        o.warmBasis = &guess;
        const LcpResult r = s.solve(p, o);
        checkSolution(p, r);
        for (int i = 0; i < p.n; ++i) CHECK(r.z[std::size_t(i)] == doctest::Approx(cold.z[std::size_t(i)]).epsilon(1e-10).scale(1.0));
    }
}

TEST_CASE("a warm basis that the perturbation makes feasible is continued from, not dropped for a cold start") {
    // A = [[1, 1], [1, 1]], b = (-1 - 1e-8, -1): the answer is z = (1 + 1e-8, 0). With the guess {1}, w_0 = -1e-8:
    // beyond the warm check's tolerance (1e-9 of the scale), and its block principal correction {0, 1} is singular,
    // so pivoting starts. Pivoting runs on b + 1e-7 max|b| p, which lifts w_0 above zero: the guess is already the
    // perturbed problem's answer and the start step has nothing to pivot on. The guess is taken as found and
    // continued with smaller perturbations to the exact answer: 3 pivots. It used to be thrown away for a cold
    // start (5 pivots here; a settled 3D box rocking at the tangent dead zone paid about 110 pivots every third
    // step for that).
    Lcp p(2);
    p.A = {1.0, 1.0, 1.0, 1.0};
    p.b = {-1.0 - 1e-8, -1.0};
    const std::vector<int> guess{1};
    LcpOptions o;
    o.warmBasis = &guess;
    LemkeSolver s;
    const LcpResult r = s.solve(p, o);
    checkSolution(p, r);
    CHECK(r.pivots <= 3);
    CHECK(r.restarts == 0);
    CHECK(r.z[0] == doctest::Approx(1.0 + 1e-8).epsilon(1e-15));
    CHECK(r.z[1] == 0.0);
    CHECK(r.basis == std::vector<int>{0});
}

TEST_CASE("invalid input: NaN, infinity and size mismatch are reported, never solved") {
    LemkeSolver s;
    Lcp p = makeLcp(2, {2, 1, 1, 2}, {-1, -1});
    p.A[1] = std::nan("");
    LcpResult r = s.solve(p);
    CHECK(r.status == LcpStatus::invalid_input);
    CHECK(r.message.find("A has a non-finite entry at (0, 1)") != std::string::npos);
    p = makeLcp(2, {2, 1, 1, 2}, {-1, INFINITY});
    r = s.solve(p);
    CHECK(r.status == LcpStatus::invalid_input);
    CHECK(r.message.find("b has a non-finite") != std::string::npos);
    p = makeLcp(2, {2, 1, 1, 2}, {-1, -1});
    p.b.pop_back();
    CHECK(s.solve(p).status == LcpStatus::invalid_input);
    CHECK(s.solve(-1, nullptr, nullptr).status == LcpStatus::invalid_input);
    CHECK(s.solve(Lcp(0)).status == LcpStatus::solved);
}

TEST_CASE("solver options out of range are invalid input, never a crash") {
    Lcp p(2);
    p.at(0, 0) = 2.0;
    p.at(1, 1) = 2.0;
    p.b = {-1.0, -1.0};
    LemkeSolver solver;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int k = 0; k < 7; ++k) {
        LcpOptions o;
        if (k == 0) o.pivotTolerance = 1.0;
        if (k == 1) o.pivotTolerance = -1e-9;
        if (k == 2) o.residualTolerance = nan;
        if (k == 3) o.degeneracyPerturbation = -1e-7;
        if (k == 4) o.maxPivots = -1;
        if (k == 5) o.blockPivotRounds = -1;
        if (k == 6) o.blockPivotRounds = 9;
        const LcpResult r = solver.solve(p, o);
        CHECK(r.status == LcpStatus::invalid_input);
        CHECK(r.message.find("options") != std::string::npos);
    }
    CHECK(solver.solve(p).status == LcpStatus::solved);
}

TEST_CASE("no solution: the secondary ray is reported as infeasible") {
    // w1 = z1 - z2 - 1, w2 = -z1 + z2 - 1: w1 + w2 = -2 < 0 for every z, so no solution exists.
    LemkeSolver s;
    const LcpResult r = s.solve(makeLcp(2, {1, -1, -1, 1}, {-1, -1}));
    CHECK(r.status == LcpStatus::infeasible);
    // A = 0 with b < 0 has no solution either.
    CHECK(s.solve(makeLcp(1, {0}, {-1})).status == LcpStatus::infeasible);
}

TEST_CASE("pivot cap and work budget end with pivot_limit, and the counts are deterministic") {
    LemkeSolver s;
    const Lcp p = randomPd(40, 99);
    const LcpResult full = s.solve(p);
    REQUIRE(full.status == LcpStatus::solved);
    REQUIRE(full.pivots > 5);
    LcpOptions capped;
    capped.maxPivots = full.pivots - 1;
    const LcpResult c = s.solve(p, capped);
    CHECK(c.status == LcpStatus::pivot_limit);
    CHECK(c.pivots == full.pivots - 1);
    LcpOptions budget;
    budget.maxWork = full.work - 1;
    const LcpResult b = s.solve(p, budget);
    CHECK(b.status == LcpStatus::pivot_limit);
    CHECK(b.work < full.work);
    budget.maxWork = full.work;  // exactly enough
    CHECK(s.solve(p, budget).status == LcpStatus::solved);
    CHECK(s.solve(p).work == full.work);
}

TEST_CASE("the same problem gives bit-identical z, whatever the solver solved before") {
    LemkeSolver fresh;
    LemkeSolver used;
    (void)used.solve(randomPd(70, 1));
    (void)used.solve(randomPd(3, 2));
    const Lcp p = randomPd(25, 5);
    const LcpResult a = fresh.solve(p);
    const LcpResult b = used.solve(p);
    REQUIRE(a.status == LcpStatus::solved);
    REQUIRE(a.z.size() == b.z.size());
    CHECK(std::memcmp(a.z.data(), b.z.data(), a.z.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(a.w.data(), b.w.data(), a.w.size() * sizeof(double)) == 0);
    CHECK(a.pivots == b.pivots);
}

TEST_CASE("the compressed-row entry point gives the same bits as the dense one, and checks its input") {
    LemkeSolver s;
    Lcp p = randomPd(30, 77);
    for (int i = 0; i < 30; ++i) {  // make it sparse: keep a band
        for (int j = 0; j < 30; ++j) {
            if (std::abs(i - j) > 3) p.at(i, j) = 0.0;
        }
        p.at(i, i) += 2.0;  // still positive definite (diagonally dominant enough)
    }
    const SparseLcp sp = toSparse(p);
    CHECK(sp.vals.size() < std::size_t(30 * 30));
    const LcpResult a = s.solve(p);
    const LcpResult b = s.solve(sp);
    checkSolution(p, a);
    REQUIRE(b.status == LcpStatus::solved);
    CHECK(std::memcmp(a.z.data(), b.z.data(), a.z.size() * sizeof(double)) == 0);
    CHECK(a.pivots == b.pivots);
    SparseLcp bad = sp;
    bad.cols[1] = bad.cols[0];  // not strictly increasing
    CHECK(s.solve(bad).status == LcpStatus::invalid_input);
    bad = sp;
    bad.cols[0] = 99;
    CHECK(s.solve(bad).message.find("out of range") != std::string::npos);
    bad = sp;
    bad.vals[3] = std::nan("");
    CHECK(s.solve(bad).message.find("non-finite") != std::string::npos);
    bad = sp;
    bad.rowStart.pop_back();
    CHECK(s.solve(bad).status == LcpStatus::invalid_input);
}

TEST_CASE("status names are stable") {
    CHECK(std::string(statusName(LcpStatus::solved)) == "solved");
    CHECK(std::string(statusName(LcpStatus::infeasible)) == "infeasible");
    CHECK(std::string(statusName(LcpStatus::pivot_limit)) == "pivot_limit");
    CHECK(std::string(statusName(LcpStatus::invalid_input)) == "invalid_input");
    CHECK(std::string(statusName(LcpStatus::numerical_failure)) == "numerical_failure");
}


TEST_CASE("a degenerate path whose tie-breaking coefficients overflow ends with an explicit outcome") {
    // The eps coefficients of the perturbed values grew to inf and NaN along this LCP's pivot path; the tie rule then
    // kept no candidate and Lemke read past an empty list (a crash in every build). Now the lexicographic rule
    // decides such ties, and the solve ends with an answer the world can judge.
    SparseLcp p = loadPyramid40Fallback();
    REQUIRE(p.n == 4760);
    LcpOptions o;
    o.maxPivots = 10 * p.n + 1000;  // the world's frictionless fallback cap
    o.warmCovering = LcpOptions::WarmCovering::violated;
    LemkeSolver solver;
    const LcpResult r = solver.solve(SparseLcp(p), o);
    CHECK(r.status != LcpStatus::invalid_input);
    CHECK(r.pivots > 0);
    if (r.status == LcpStatus::solved || r.status == LcpStatus::numerical_failure) {
        CHECK(r.scaledResidual <= 1e-6);  // what the worlds accept (WorldDef2::acceptResidual)
        double zMin = 0.0;
        for (double z : r.z) zMin = std::min(zMin, z);
        CHECK(zMin >= -r.residual);  // the residual covers negative impulses too: |min(z_i, w_i)|
    }
    // Deterministic: the same bits again.
    const LcpResult again = LemkeSolver().solve(std::move(p), o);
    CHECK(again.status == r.status);
    CHECK(again.pivots == r.pivots);
    CHECK(std::memcmp(again.z.data(), r.z.data(), r.z.size() * sizeof(double)) == 0);
}

}  // TEST_SUITE
