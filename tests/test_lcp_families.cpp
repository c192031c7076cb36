// tests/test_lcp_families.cpp — the hard LCP families of the solver contract, each with the status a correct
// Lemke must report, the scaled residual bound (1e-9) and, for contact scenes, the physics the impulses must
// produce: a settled stack hit by one step of gravity stops dead (e = 0), so every post-impulse velocity is zero.
#include "test_support.h"

#include "lcp_families.h"
#include "resolver2d.h"
#include "resolver3d.h"

#include <cmath>
#include <cstdint>
#include <cstring>

using namespace unison;
using namespace unison::scenes;

namespace {

LcpResult solveCase(const LcpCase& c, int maxPivots = 0) {
    LemkeSolver solver;
    LcpOptions options;
    options.maxPivots = maxPivots;
    return solver.solve(c.lcp, options);
}

void requireSolved(const LcpCase& c, const LcpResult& r) {
    CAPTURE(c.name);
    REQUIRE(r.status == LcpStatus::solved);
    CHECK(r.scaledResidual <= 1e-9);
    CHECK(scaledResidual(c.lcp, r.z) <= 1e-9);  // recomputed independently of the solver's own w
}

double maxSpeed(const std::vector<Body2>& bodies) {
    double v = 0.0;
    for (const auto& b : bodies) v = std::max({v, std::fabs(b.velocity.x), std::fabs(b.velocity.y), std::fabs(b.angularVelocity)});
    return v;
}

double maxSpeed3(const std::vector<Body3>& bodies) {
    double v = 0.0;
    for (const auto& b : bodies) v = std::max({v, b.velocity.cwiseAbs().maxCoeff(), b.angularVelocity.cwiseAbs().maxCoeff()});
    return v;
}

}  // namespace

TEST_SUITE("lcp_families") {

TEST_CASE("Murty's matrix: 2^n pivots (2^n - 1 after z0 enters), solved up to n = 16; the cap stops it") {
    for (int n = 1; n <= 16; ++n) {
        CAPTURE(n);
        const LcpCase c = murty(n);
        const LcpResult r = solveCase(c, 1 << 17);
        requireSolved(c, r);
        CHECK(r.pivots == c.expectedPivots);
        CHECK(r.pivots == (1 << n));
    }
    const LcpResult capped = solveCase(murty(12), 1000);
    CHECK(capped.status == LcpStatus::pivot_limit);
    CHECK(capped.pivots == 1000);
}

TEST_CASE("L L^T with L = I + 2 strict-lower is solved") {
    for (int n : {10, 50, 200}) {
        for (bool mixed : {false, true}) {
            const LcpCase c = lowerLLT(n, mixed);
            requireSolved(c, solveCase(c));
        }
    }
}

TEST_CASE("cube stacks with 4 coplanar corner contacts (singular A, degenerate b) up to n = 400") {
    for (int count : {1, 2, 10, 50, 100}) {
        CAPTURE(count);
        Scene3 scene = cubeStack3dScene(count);
        const LcpCase c = cubeStack3d(count);
        REQUIRE(c.lcp.n == 4 * count);
        const LcpResult r = solveCase(c);
        requireSolved(c, r);
        applyImpulses(scene.bodies, scene.contacts, r.z);
        CHECK(maxSpeed3(scene.bodies) < 1e-9);  // the whole stack stops: velocities are unique even if impulses are not
    }
}

TEST_CASE("settled 2D pyramids: frictionless n = 800 and friction LCPs up to n = 800 stop dead") {
    for (int rows : {5, 12, 20}) {
        CAPTURE(rows);
        Scene2 scene = pyramid2dScene(rows);
        const LcpCase c = pyramid2d(rows, false);
        REQUIRE(c.lcp.n == 2 * rows * rows);
        const LcpResult r = solveCase(c);
        requireSolved(c, r);
        applyImpulses(scene.bodies, scene.contacts, r.z);
        CHECK(maxSpeed(scene.bodies) < 1e-9);
        // Total normal impulse carries the weight of one step: sum f = m g dt over all boxes.
        double total = 0.0, mass = 0.0;
        for (std::size_t i = 0; i < scene.contacts.size(); ++i) {
            if (scene.contacts[i].b == 0) total += r.z[i];
        }
        for (const auto& b : scene.bodies) mass += b.invMass > 0.0 ? 1.0 / b.invMass : 0.0;
        CHECK(total == doctest::Approx(mass * kSettledFallSpeed).epsilon(1e-9));
    }
    for (int rows : {3, 7, 10}) {
        CAPTURE(rows);
        const LcpCase c = pyramid2d(rows, true);
        REQUIRE(c.lcp.n == 8 * rows * rows);
        Scene2 scene = pyramid2dScene(rows);
        LemkeSolver solver;
        const Resolution res = resolveWithFriction(scene.bodies, scene.contacts, ResolverOptions{}, solver);
        REQUIRE(res.status == LcpStatus::solved);
        CHECK(res.residual <= 1e-9);
        CHECK(maxSpeed(scene.bodies) < 1e-9);
        requireSolved(c, solveCase(c));
    }
}

TEST_CASE("friction LCP of a settled cube stack (4 directions, non-symmetric) is solved") {
    for (int count : {1, 5, 20}) {
        CAPTURE(count);
        const LcpCase c = cubeStack3d(count, true);
        REQUIRE(c.lcp.n == 24 * count);
        requireSolved(c, solveCase(c));
    }
}

TEST_CASE("cradle chains follow the closed form for long chains") {
    for (int balls : {10, 50}) {
        for (double e : {1.0, 0.5}) {
            CAPTURE(balls);
            Scene2 scene = cradleChainScene(balls, e);
            const LcpCase c = cradleChain(balls, e);
            const LcpResult r = solveCase(c);
            requireSolved(c, r);
            applyImpulses(scene.bodies, scene.contacts, r.z);
            const double N = balls;
            CHECK(scene.bodies.front().velocity.x == doctest::Approx(1.0 - (1.0 + e) * (N - 1.0) / N).epsilon(1e-10));
            CHECK(scene.bodies.back().velocity.x == doctest::Approx((1.0 + e) / N).epsilon(1e-10));
        }
    }
}

TEST_CASE("a particle jammed between two walls with e > 0 is infeasible, never a fake success") {
    for (const LcpCase& c : {jammedParticle(0.5), jammedParticle(1.0), squeezedParticle(0.5), squeezedParticle(0.0)}) {
        CAPTURE(c.name);
        CHECK(c.expected == "infeasible");
        const LcpResult r = solveCase(c);
        CHECK(r.status == LcpStatus::infeasible);
    }
}

TEST_CASE("warm start at n = 800 from the previous basis: a few pivots, same velocities") {
    const LcpCase c = pyramid2d(20, false);
    LemkeSolver solver;
    const LcpResult cold = solver.solve(c.lcp);
    requireSolved(c, cold);
    LcpOptions options;
    options.warmBasis = &cold.basis;
    const LcpResult warm = solver.solve(c.lcp, options);
    requireSolved(c, warm);
    CHECK(warm.warmStarted);
    CHECK(warm.pivots <= 5);
    Scene2 a = pyramid2dScene(20), b = pyramid2dScene(20);
    applyImpulses(a.bodies, a.contacts, cold.z);
    applyImpulses(b.bodies, b.contacts, warm.z);
    CHECK(maxSpeed(a.bodies) < 1e-9);
    CHECK(maxSpeed(b.bodies) < 1e-9);
}

TEST_CASE("every standard case ends with its expected status, bit-identically on a second run") {
    for (const LcpCase& c : standardCases(true)) {
        CAPTURE(c.name);
        const LcpResult a = solveCase(c, 1 << 17);
        const LcpResult b = solveCase(c, 1 << 17);
        CHECK(std::string(statusName(a.status)) == c.expected);
        if (a.status == LcpStatus::solved) CHECK(a.scaledResidual <= 1e-9);
        REQUIRE(a.z.size() == b.z.size());
        CHECK(std::memcmp(a.z.data(), b.z.data(), a.z.size() * sizeof(double)) == 0);
        CHECK(a.pivots == b.pivots);
    }
}

TEST_CASE("golden hash: the z's and pivot counts of the quick standard cases") {
    // FNV-1a over the raw bits of every z and every pivot count. The same value comes out of gcc -O0/-O2/-O3 and
    // clang -O2/-O3 builds (checked when this was written). A change that alters it changes answers on the wire:
    // say why in the commit.
    std::uint64_t h = 1469598103934665603ULL;
    auto mix = [&](const void* p, std::size_t n) {
        const unsigned char* c = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) {
            h ^= c[i];
            h *= 1099511628211ULL;
        }
    };
    LemkeSolver solver;
    LcpOptions options;
    options.maxPivots = 1 << 17;
    for (const LcpCase& c : standardCases(true)) {
        const LcpResult r = solver.solve(c.lcp, options);
        mix(r.z.data(), r.z.size() * sizeof(double));
        const std::int32_t pivots = r.pivots;
        mix(&pivots, sizeof pivots);
    }
    CHECK(h == 0xf37fee6818b2decdULL);
}

}  // TEST_SUITE
