// tests/test_active_set3.cpp — the 3D active-set path (core/active_set3_impl.h): its answers certified independently
// on the assembled Stewart–Trinkle LCP of four directions, agreement with Lemke's velocities, bits repeated, what it
// declines, and a 3D world whose landing islands it answers.
#include "test_support.h"

#include "make_scenes3d.h"
#include "resolver3d.h"
#include "scene_json3d.h"
#include "symmetric_pattern_lu.h"
#include "world3d.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace unison;

namespace {

// Unit cubes (mass 1) in columns x columns x layers, each resting on the one below (or on the ground, body 0) and
// touching its side neighbours, all falling at g dt: four corner points on every bottom face and on every face
// between neighbours. More contact rows than degrees of freedom (singular J M^-1 J^T).
struct Stack3 {
    std::vector<Body3> bodies;
    std::vector<Contact3> contacts;
};

Stack3 restingStack(int columns, int layers, double mu) {
    Stack3 s;
    s.bodies.push_back(Body3{});  // ground: infinite mass
    const double dt = 1.0 / 60.0, g = 10.0;
    auto at = [&](int i, int j, int l) { return 1 + (l * columns + j) * columns + i; };
    for (int l = 0; l < layers; ++l) {
        for (int j = 0; j < columns; ++j) {
            for (int i = 0; i < columns; ++i) {
                Body3 b;
                b.invMass = 1.0;
                b.invInertia = Mat3::Identity() * 6.0;  // 1 / (m (1 + 1) / 12)
                b.position = Vec3(double(i), double(j), 0.5 + double(l));
                b.velocity = Vec3(0.0, 0.0, -g * dt);
                s.bodies.push_back(b);
            }
        }
    }
    for (int l = 0; l < layers; ++l) {
        for (int j = 0; j < columns; ++j) {
            for (int i = 0; i < columns; ++i) {
                const int below = l == 0 ? 0 : at(i, j, l - 1);
                for (int corner = 0; corner < 4; ++corner) {
                    const double dx = (corner & 1) ? 0.5 : -0.5, dy = (corner & 2) ? 0.5 : -0.5;
                    s.contacts.push_back(makeContact<Dim3>(at(i, j, l), below, Vec3(i + dx, j + dy, double(l)),
                                                           Vec3(0, 0, 1), 0.0, mu));
                }
                for (int corner = 0; corner < 4; ++corner) {
                    const double da = (corner & 1) ? 0.5 : -0.5, dz = (corner & 2) ? 1.0 : 0.0;
                    if (i + 1 < columns)
                        s.contacts.push_back(makeContact<Dim3>(at(i + 1, j, l), at(i, j, l),
                                                               Vec3(i + 0.5, j + da, l + dz), Vec3(1, 0, 0), 0.0, mu));
                    if (j + 1 < columns)
                        s.contacts.push_back(makeContact<Dim3>(at(i, j + 1, l), at(i, j, l),
                                                               Vec3(i + da, j + 0.5, l + dz), Vec3(0, 1, 0), 0.0, mu));
                }
            }
        }
    }
    return s;
}

// The Stewart–Trinkle LCP's (four directions) scaled complementarity residual of an answer, on the dense assembled
// matrix: z = (p_n, the positive and negative parts of the friction impulse along t1 and t2, lambda). lambda is the
// LCP's own unknown, free for each contact; as in the path's certificate it is the smallest slack that makes every
// direction's row non-negative (the sliding speed) or 0, whichever leaves the smaller residual on the contact's rows.
double assembledResidual(const std::vector<Body3>& before, const std::vector<Contact3>& contacts, const Resolution& r,
                         const ResolverOptions& options) {
    FrictionLayout layout;
    const Lcp lcp = assembleFrictionLcp(before, contacts, options, &layout);
    const int n = lcp.n, nc = layout.contacts;
    REQUIRE(layout.directions == 4);
    std::vector<double> z(std::size_t(n), 0.0);
    for (int c = 0; c < nc; ++c) {
        z[std::size_t(c)] = r.impulses[std::size_t(c)];
        const std::vector<Vec3> dirs = frictionDirections(contacts[std::size_t(c)], 4);
        const Vec3 t(r.tangentImpulses[std::size_t(3 * c)], r.tangentImpulses[std::size_t(3 * c + 1)],
                     r.tangentImpulses[std::size_t(3 * c + 2)]);
        const double f1 = t.dot(dirs[0]), f2 = t.dot(dirs[1]);
        const int t0 = layout.tangentOffset() + 4 * c;
        z[std::size_t(t0)] = std::max(f1, 0.0);
        z[std::size_t(t0 + 1)] = std::max(f2, 0.0);
        z[std::size_t(t0 + 2)] = std::max(-f1, 0.0);
        z[std::size_t(t0 + 3)] = std::max(-f2, 0.0);
    }
    auto product = [&](int i) {
        double s = lcp.b[std::size_t(i)];
        for (int j = 0; j < n; ++j) s += lcp.A[std::size_t(i) * std::size_t(n) + std::size_t(j)] * z[std::size_t(j)];
        return s;
    };
    double res = 0.0, scale = 0.0;
    for (int i = 0; i < n; ++i) {
        if (i < layout.tangentOffset()) res = std::max(res, std::fabs(std::min(z[std::size_t(i)], product(i))));
        scale = std::max(scale, std::fabs(lcp.b[std::size_t(i)]));
        for (int j = 0; j < n; ++j) scale = std::max(scale, std::fabs(lcp.A[std::size_t(i) * std::size_t(n) + std::size_t(j)]));
    }
    for (int c = 0; c < nc; ++c) {
        const int t0 = layout.tangentOffset() + 4 * c, sc = layout.slackOffset() + c;
        auto contactResidual = [&](double lambda) {  // the contact's direction rows and its slack row
            z[std::size_t(sc)] = lambda;
            double r = std::fabs(std::min(lambda, product(sc)));
            for (int m = 0; m < 4; ++m) r = std::max(r, std::fabs(std::min(z[std::size_t(t0 + m)], product(t0 + m))));
            return r;
        };
        double sliding = 0.0;
        for (int m = 0; m < 4; ++m) sliding = std::max(sliding, -product(t0 + m));  // with lambda = 0
        res = std::max(res, std::min(contactResidual(sliding), contactResidual(0.0)));
    }
    return res / scale;
}

// A unit cube on the ground on its four bottom corners, coming in at (vx, 0.3 vx, -1) m/s and spinning at
// (0.2, wy, 0.1) rad/s.
Stack3 landingCube(double vx, double wy, double mu) {
    Stack3 s;
    s.bodies.resize(2);
    s.bodies[0].invMass = 1.0;
    s.bodies[0].invInertia = Mat3::Identity() * 6.0;
    s.bodies[0].position = Vec3(0, 0, 0.5);
    s.bodies[0].velocity = Vec3(vx, 0.3 * vx, -1.0);
    s.bodies[0].angularVelocity = Vec3(0.2, wy, 0.1);
    for (int i = 0; i < 4; ++i)
        s.contacts.push_back(makeContact<Dim3>(0, 1, Vec3((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, 0.0),
                                               Vec3(0, 0, 1), 0.0, mu));
    return s;
}

}  // namespace

TEST_SUITE("active_set") {

TEST_CASE("3D active-set path: a resting stack of cubes from a cold start is certified on the assembled LCP") {
    const Stack3 stack = restingStack(3, 3, 0.6);
    REQUIRE(stack.contacts.size() == 252);
    ResolverOptions options;  // four directions, as the 3D world
    const std::vector<double> cold(stack.contacts.size() * 4, 0.0);
    std::vector<Body3> bodies = stack.bodies;
    const Resolution r = resolveActiveSet(bodies, stack.contacts, cold, options, ActiveSetOptions{});
    REQUIRE(r.status == LcpStatus::solved);
    CHECK(r.activeSet);
    CHECK(r.pivots == 0);
    CHECK(r.scaledResidual <= options.lcp.residualTolerance);
    const double assembled = assembledResidual(stack.bodies, stack.contacts, r, options);
    MESSAGE("3D active-set residual " << r.scaledResidual << ", on the assembled LCP " << assembled);
    CHECK(assembled <= options.lcp.residualTolerance + 1e-13);
    // The stack comes to rest and the ground carries its weight (27 cubes of 1 kg at 10 m/s^2 over 1/60 s: 4.5 N s).
    double ground = 0.0;
    for (std::size_t c = 0; c < stack.contacts.size(); ++c)
        if (stack.contacts[c].b == 0) ground += r.impulses[c];
    CHECK(ground == doctest::Approx(4.5).epsilon(1e-7));  // velocities are zero to ~1e-8
    for (std::size_t k = 1; k < bodies.size(); ++k) {
        CHECK(bodies[k].velocity.norm() <= 1e-8);
        CHECK(bodies[k].angularVelocity.norm() <= 1e-8);
    }
    // Same bits on a second call, with and without a pattern cache.
    SymmetricPatternCache cache;
    ActiveSetOptions cached;
    cached.patternCache = &cache;
    const ActiveSetOptions* runs[] = {nullptr, &cached, &cached};
    for (const ActiveSetOptions* o : runs) {
        std::vector<Body3> again = stack.bodies;
        const Resolution r2 = resolveActiveSet(again, stack.contacts, cold, options, o ? *o : ActiveSetOptions{});
        REQUIRE(r2.impulses.size() == r.impulses.size());
        CHECK(std::memcmp(r2.impulses.data(), r.impulses.data(), r.impulses.size() * sizeof(double)) == 0);
        CHECK(std::memcmp(r2.tangentImpulses.data(), r.tangentImpulses.data(),
                          r.tangentImpulses.size() * sizeof(double)) == 0);
        CHECK(r2.work == r.work);
    }
}

TEST_CASE("3D active-set path: a scratch keeps island systems across calls; the answers and work stay the same") {
    const Stack3 big = restingStack(3, 3, 0.6), small = restingStack(2, 2, 0.6);
    ResolverOptions options;
    ActiveSetOptions plain;
    plain.coldInteriorPoint = false;  // the primal-dual iteration from zero impulses: the island's system is factored
    ActiveSetScratch scratch;
    ActiveSetOptions kept = plain;
    kept.scratch = &scratch;
    auto solve = [&](const Stack3& s, const ActiveSetOptions& o) {
        std::vector<Body3> bodies = s.bodies;
        return resolveActiveSet(bodies, s.contacts, std::vector<double>(s.contacts.size() * 4, 0.0), options, o);
    };
    const Resolution refBig = solve(big, plain), refSmall = solve(small, plain);
    REQUIRE(refBig.status == LcpStatus::solved);
    REQUIRE(refSmall.status == LcpStatus::solved);
    REQUIRE(refBig.patternAnalyses == 1);
    REQUIRE(refSmall.patternAnalyses == 1);
    // Two islands in turn: each system is assembled and analysed when first met, and found in the scratch after.
    const Stack3* order[] = {&big, &small, &big, &small, &big};
    for (int i = 0; i < 5; ++i) {
        const Resolution& ref = order[i] == &big ? refBig : refSmall;
        const Resolution r = solve(*order[i], kept);
        REQUIRE(r.impulses.size() == ref.impulses.size());
        CHECK(std::memcmp(r.impulses.data(), ref.impulses.data(), r.impulses.size() * sizeof(double)) == 0);
        CHECK(std::memcmp(r.tangentImpulses.data(), ref.tangentImpulses.data(),
                          r.tangentImpulses.size() * sizeof(double)) == 0);
        CHECK(r.work == ref.work);  // work units do not depend on what the scratch holds
        CHECK(r.patternAnalyses == (i < 2 ? 1 : 0));
    }
    CHECK(scratch.boxSystems.size() == 2);
    // More islands than the scratch keeps: the least recently used ones make room, the answers stay the same.
    for (int columns = 1; columns <= int(ActiveSetScratch::kBoxSystems) + 1; ++columns) {
        const Stack3 s = restingStack(columns, 2, 0.6);
        const Resolution ref = solve(s, plain);
        const Resolution r = solve(s, kept);
        REQUIRE(r.status == ref.status);
        CHECK(std::memcmp(r.impulses.data(), ref.impulses.data(), r.impulses.size() * sizeof(double)) == 0);
    }
    CHECK(scratch.boxSystems.size() == ActiveSetScratch::kBoxSystems);
    const Resolution again = solve(big, kept);  // evicted by the nine islands above: assembled again
    CHECK(again.patternAnalyses == 1);
    CHECK(std::memcmp(again.impulses.data(), refBig.impulses.data(), refBig.impulses.size() * sizeof(double)) == 0);
}

TEST_CASE("3D active-set path: agrees with Lemke on a landing cube that slides, turns or sticks") {
    // (vx, wy, mu): sliding along a diagonal, sliding while turning, stopped by friction.
    const double cases[][3] = {{1.0, 0.0, 0.5}, {0.1, 0.0, 0.5}, {2.0, 1.5, 0.3}, {0.5, -2.0, 0.8}, {3.0, 0.0, 0.1}};
    for (const auto& k : cases) {
        CAPTURE(k[0]);
        CAPTURE(k[1]);
        CAPTURE(k[2]);
        const Stack3 cube = landingCube(k[0], k[1], k[2]);
        ResolverOptions options;
        LemkeSolver solver;
        std::vector<Body3> lemke = cube.bodies, path = cube.bodies;
        const Resolution rl = resolveWithFriction(lemke, cube.contacts, options, solver);
        REQUIRE(rl.status == LcpStatus::solved);
        // Cold, and warm from impulses off the answer.
        for (int warmStart = 0; warmStart < 2; ++warmStart) {
            std::vector<double> warm(cube.contacts.size() * 4, 0.0);
            if (warmStart)
                for (std::size_t c = 0; c < cube.contacts.size(); ++c) warm[4 * c] = 0.1 * double(c + 1);
            path = cube.bodies;
            const Resolution rp = resolveActiveSet(path, cube.contacts, warm, options, ActiveSetOptions{});
            REQUIRE(rp.status == LcpStatus::solved);
            CHECK(assembledResidual(cube.bodies, cube.contacts, rp, options) <= options.lcp.residualTolerance + 1e-13);
            CHECK((path[0].velocity - lemke[0].velocity).norm() <= 1e-8);
            CHECK((path[0].angularVelocity - lemke[0].angularVelocity).norm() <= 1e-8);
        }
    }
}

TEST_CASE("3D active-set path: the interior-point restart answers a sliding landing as it stands") {
    // A cube landing while it slides (the relaxation alone lets its contacts separate at mu times their sliding
    // speed): the restart follows de Saxce's shift inside its iteration, so its answer is the LCP's without any
    // iteration of the path (phase 1 and the face refinements get none here).
    const double cases[][3] = {{1.0, 0.0, 0.5}, {2.0, 1.5, 0.3}, {3.0, 0.0, 0.1}};
    for (const auto& k : cases) {
        CAPTURE(k[0]);
        const Stack3 cube = landingCube(k[0], k[1], k[2]);
        ResolverOptions options;
        LemkeSolver solver;
        std::vector<Body3> lemke = cube.bodies, path = cube.bodies;
        REQUIRE(resolveWithFriction(lemke, cube.contacts, options, solver).status == LcpStatus::solved);
        ActiveSetOptions restartOnly;
        restartOnly.maxIterations = 0;
        const Resolution r =
            resolveActiveSet(path, cube.contacts, std::vector<double>(cube.contacts.size() * 4, 0.0), options,
                             restartOnly);
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(r.interiorPoint);
        CHECK(assembledResidual(cube.bodies, cube.contacts, r, options) <= options.lcp.residualTolerance + 1e-13);
        CHECK((path[0].velocity - lemke[0].velocity).norm() <= 1e-8);
        CHECK(path[0].velocity.head<2>().norm() > 0.05);  // it still slides: friction did not stop it
    }
}

TEST_CASE("3D active-set path: declines a pyramid of six directions and bad input, leaving the bodies untouched") {
    const Stack3 cube = landingCube(1.0, 0.0, 0.5);
    ResolverOptions options;
    options.frictionDirections = 6;
    std::vector<Body3> bodies = cube.bodies;
    Resolution r = resolveActiveSet(bodies, cube.contacts, std::vector<double>(16, 0.0), options, ActiveSetOptions{});
    CHECK(r.status == LcpStatus::pivot_limit);
    CHECK(!r.activeSet);
    CHECK(bodies[0].velocity == cube.bodies[0].velocity);
    options.frictionDirections = 4;
    r = resolveActiveSet(bodies, cube.contacts, std::vector<double>(3, 0.0), options, ActiveSetOptions{});
    CHECK(r.status == LcpStatus::pivot_limit);
    std::vector<Contact3> bad = cube.contacts;
    bad[0].b = 7;
    r = resolveActiveSet(bodies, bad, std::vector<double>(16, 0.0), options, ActiveSetOptions{});
    CHECK(r.status == LcpStatus::invalid_input);
    CHECK(bodies[0].velocity == cube.bodies[0].velocity);
    CHECK(bodies[0].angularVelocity == cube.bodies[0].angularVelocity);
}

TEST_CASE("3D active-set path: incomingVelocity predicts the next step's impulses of a settled stack") {
    // A 3 x 3 x 2 stack whose cubes come in falling at 1e-6 m/s (a settled pile's velocity error) before this step's
    // gravity. The answer stops them: the ground carries 18 cubes x (g dt + 1e-6) N s. The prediction is the load
    // alone (18 g dt): the next step's problem (bodies at rest, then gravity) is certified by it as it stands, while
    // the answer itself, carried, meets that problem 1e-6 m/s off and needs a factorisation.
    const double dt = 1.0 / 60.0, g = 10.0, slow = 1e-6;
    Stack3 stack = restingStack(3, 2, 0.6);
    for (std::size_t k = 1; k < stack.bodies.size(); ++k) stack.bodies[k].velocity.z() = -slow - g * dt;
    std::vector<double> incoming(6 * stack.bodies.size(), 0.0);
    for (std::size_t k = 1; k < stack.bodies.size(); ++k) incoming[6 * k + 2] = -slow;
    ResolverOptions options;
    const std::vector<double> cold(stack.contacts.size() * 4, 0.0);
    // The prediction needs the factors of the path's last iteration: the primal-dual iteration from zero impulses.
    ActiveSetOptions predict, noPrediction;
    predict.incomingVelocity = &incoming;
    predict.interiorPoint = noPrediction.interiorPoint = false;
    predict.maxIterations = noPrediction.maxIterations = 30;
    std::vector<Body3> bodies = stack.bodies, plainBodies = stack.bodies;
    const Resolution r = resolveActiveSet(bodies, stack.contacts, cold, options, predict);
    const Resolution plain = resolveActiveSet(plainBodies, stack.contacts, cold, options, noPrediction);
    REQUIRE(r.status == LcpStatus::solved);
    REQUIRE(plain.status == LcpStatus::solved);
    CHECK(plain.predictedImpulses.empty());
    // The prediction changes nothing of the answer.
    REQUIRE(r.impulses.size() == plain.impulses.size());
    CHECK(std::memcmp(r.impulses.data(), plain.impulses.data(), r.impulses.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(r.tangentImpulses.data(), plain.tangentImpulses.data(),
                      r.tangentImpulses.size() * sizeof(double)) == 0);
    REQUIRE(r.predictedImpulses.size() == 4 * stack.contacts.size());
    double ground = 0.0, groundRest = 0.0;
    for (std::size_t c = 0; c < stack.contacts.size(); ++c) {
        if (stack.contacts[c].b != 0) continue;
        ground += r.impulses[c];
        groundRest += r.predictedImpulses[4 * c];
    }
    CHECK(ground == doctest::Approx(18.0 * (g * dt + slow)).epsilon(1e-7));
    CHECK(groundRest == doctest::Approx(18.0 * g * dt).epsilon(1e-7));
    // The next step: the bodies left at rest (to the tolerance), then gravity.
    std::vector<Body3> next = stack.bodies;
    for (std::size_t k = 1; k < next.size(); ++k) {
        next[k].velocity = bodies[k].velocity - Vec3(0.0, 0.0, g * dt);
        next[k].angularVelocity = bodies[k].angularVelocity;
    }
    std::vector<double> carried;
    for (std::size_t c = 0; c < stack.contacts.size(); ++c) {
        carried.push_back(r.impulses[c]);
        for (int d = 0; d < 3; ++d) carried.push_back(r.tangentImpulses[3 * c + std::size_t(d)]);
    }
    std::vector<Body3> a = next, b = next;
    const Resolution fromPrediction = resolveActiveSet(a, stack.contacts, r.predictedImpulses, options, ActiveSetOptions{});
    const Resolution fromAnswer = resolveActiveSet(b, stack.contacts, carried, options, ActiveSetOptions{});
    REQUIRE(fromPrediction.status == LcpStatus::solved);
    REQUIRE(fromAnswer.status == LcpStatus::solved);
    MESSAGE("next step from the prediction: " << fromPrediction.patternAnalyses << " analyses, work "
                                              << fromPrediction.work << "; from the answer: "
                                              << fromAnswer.patternAnalyses << " analyses, work " << fromAnswer.work);
    CHECK(fromPrediction.warmFace);
    CHECK(fromPrediction.patternAnalyses == 0);  // certified as it stands: no system factored
    CHECK(fromAnswer.patternAnalyses >= 1);
    CHECK(fromPrediction.work < fromAnswer.work);
}

TEST_CASE("the toppling 3D heap's landing islands are answered on the active-set path, none failed") {
    // bench_world3d's heap: 100 cubes landing on edges and toppling, sleeping off; islands of about 100 contacts.
    auto loaded = scenes::loadScene3(scenes::boxPile3Scene(100, true, false), "heap");
    World3& w = *loaded.world;
    int pathIslands = 0, restarts = 0, failed = 0;
    double worst = 0.0;
    for (int step = 0; step < 120; ++step) {
        w.step();
        pathIslands += w.stats().activeSetIslands;
        restarts += w.stats().interiorPointRestarts;
        failed += w.stats().failedIslands;
        worst = std::max(worst, w.stats().maxResidual);
    }
    MESSAGE("path islands " << pathIslands << ", interior-point restarts " << restarts << ", worst residual "
                            << worst);
    CHECK(pathIslands >= 300);
    CHECK(restarts > 0);
    // Most landing islands certify from their warm start (its face, then a trial of phase 1 unless the face leaves it
    // more than kTrialGate tolerances off): 153 of the 425 take the restart; when every warm start far off went to
    // the restart at once, 342 of 430 did.
    CHECK(restarts <= 200);
    CHECK(failed == 0);
    CHECK(worst <= 1e-6);  // m/s, bench_world3d's target (near misses of the path only within kPathAccept3)
}

}  // TEST_SUITE
