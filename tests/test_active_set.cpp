// tests/test_active_set.cpp — the active-set fast path of the friction LCP (resolveActiveSet, core/active_set_impl.h):
// its certificate checked independently on the assembled Stewart–Trinkle LCP, agreement with Lemke's answer, bits
// repeated, and what it declines (the worlds that use it: tests/test_active_set_worlds.cpp).
#include "test_support.h"

#include "make_scenes2d.h"
#include "resolver2d.h"
#include "resolver3d.h"
#include "scene_json.h"
#include "world2d.h"
#include "step_support.h"
#include "body_space_solve.h"
#include "symmetric_pattern_lu.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace unison;

namespace {

// A wall of unit boxes (mass 1) in `columns` x `rows`, each resting on the one below (or on the ground) and touching
// its side neighbours, all falling at g dt (the first step of a resting pile): two points on every bottom face and
// on every face between neighbours. A pile with more contact rows than degrees of freedom (singular J M^-1 J^T).
struct Wall {
    std::vector<Body2> bodies;
    std::vector<Contact2> contacts;
};

Wall restingWall(int columns, int rows, double mu) {
    Wall w;
    w.bodies.push_back(Body2{});  // ground: infinite mass
    const double dt = 1.0 / 60.0, g = 10.0;
    auto at = [&](int c, int r) { return 1 + r * columns + c; };
    for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < columns; ++c) {
            Body2 b;
            b.invMass = 1.0;
            b.invInertia = 6.0;  // 1 / (m (1 + 1) / 12)
            b.position = {double(c), 0.5 + double(r)};
            b.velocity = {0.0, -g * dt};
            w.bodies.push_back(b);
        }
    }
    for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < columns; ++c) {
            const int below = r == 0 ? 0 : at(c, r - 1);
            for (double dx : {-0.5, 0.5}) {
                Contact2 k = makeContact<Dim2>(at(c, r), below, {double(c) + dx, double(r)}, {0.0, 1.0}, 0.0, mu);
                w.contacts.push_back(k);
            }
            if (c + 1 < columns) {
                for (double dy : {0.0, 1.0}) {
                    Contact2 k = makeContact<Dim2>(at(c + 1, r), at(c, r), {double(c) + 0.5, double(r) + dy},
                                                   {1.0, 0.0}, 0.0, mu);
                    w.contacts.push_back(k);
                }
            }
        }
    }
    return w;
}

// The Stewart–Trinkle LCP's scaled complementarity residual of an answer (normal impulses and world-frame friction
// impulses), evaluated on the assembled matrix: z = (p_n, max(p_t, 0), max(-p_t, 0), lambda), lambda the smallest
// slack that makes both tangent rows non-negative.
double assembledResidual(const std::vector<Body2>& before, const std::vector<Contact2>& contacts,
                         const Resolution& r, const ResolverOptions& options) {
    FrictionLayout layout;
    const Lcp lcp = assembleFrictionLcp(before, contacts, options, &layout);
    const int n = lcp.n, nc = layout.contacts;
    std::vector<double> z(std::size_t(n), 0.0);
    for (int c = 0; c < nc; ++c) {
        z[std::size_t(c)] = r.impulses[std::size_t(c)];
        const std::vector<Vec2> dirs = frictionDirections(contacts[std::size_t(c)], 2);
        const Vec2 t{r.tangentImpulses[std::size_t(2 * c)], r.tangentImpulses[std::size_t(2 * c + 1)]};
        const double pt = dot(t, dirs[0]);
        z[std::size_t(layout.tangentOffset() + 2 * c)] = std::max(pt, 0.0);
        z[std::size_t(layout.tangentOffset() + 2 * c + 1)] = std::max(-pt, 0.0);
    }
    auto product = [&](int i) {
        double s = lcp.b[std::size_t(i)];
        for (int j = 0; j < n; ++j) s += lcp.A[std::size_t(i) * std::size_t(n) + std::size_t(j)] * z[std::size_t(j)];
        return s;
    };
    for (int c = 0; c < nc; ++c) {
        const double wp = product(layout.tangentOffset() + 2 * c), wm = product(layout.tangentOffset() + 2 * c + 1);
        z[std::size_t(layout.slackOffset() + c)] = std::max({0.0, -wp, -wm});
    }
    double res = 0.0, scale = 0.0;
    for (int i = 0; i < n; ++i) {
        res = std::max(res, std::fabs(std::min(z[std::size_t(i)], product(i))));
        scale = std::max(scale, std::fabs(lcp.b[std::size_t(i)]));
        for (int j = 0; j < n; ++j) scale = std::max(scale, std::fabs(lcp.A[std::size_t(i) * std::size_t(n) + std::size_t(j)]));
    }
    return res / scale;
}

// Warm impulses that belong to another problem: every contact pushing at three times a box's weight (1 kg, 10 m/s^2,
// 1/60 s), its friction on the cone's rim.
std::vector<double> farWarmStart(const Wall& wall) {
    std::vector<double> wrong;
    for (const Contact2& c : wall.contacts) {
        const double pn = 3.0 / 60.0 * 10.0;
        const std::vector<Vec2> dirs = frictionDirections(c, 2);
        wrong.push_back(pn);
        wrong.push_back(c.friction * pn * dirs[0].x);
        wrong.push_back(c.friction * pn * dirs[0].y);
    }
    return wrong;
}

}  // namespace

TEST_SUITE("active_set") {

TEST_CASE("active-set path: a resting wall of boxes from a cold start is certified on the assembled LCP") {
    const Wall wall = restingWall(6, 6, 0.6);
    REQUIRE(wall.contacts.size() == 132);
    ResolverOptions options;
    options.frictionDirections = 2;
    const std::vector<double> cold(wall.contacts.size() * 3, 0.0);
    std::vector<Body2> bodies = wall.bodies;
    const Resolution r = resolveActiveSet(bodies, wall.contacts, cold, options, ActiveSetOptions{});
    REQUIRE(r.status == LcpStatus::solved);
    CHECK(r.activeSet);
    CHECK(r.pivots == 0);
    CHECK(r.work > 0);
    CHECK(r.scaledResidual <= options.lcp.residualTolerance);
    // The certificate, evaluated independently on the dense assembled LCP (rounding differs from the matrix-free
    // evaluation only at ~1e-16 of the scale).
    const double assembled = assembledResidual(wall.bodies, wall.contacts, r, options);
    MESSAGE("active-set residual " << r.scaledResidual << ", on the assembled LCP " << assembled);
    CHECK(assembled <= options.lcp.residualTolerance + 1e-13);
    // The wall comes to rest: every box's velocity is zero to the tolerance, and the ground carries the weight
    // (36 boxes of 1 kg at 10 m/s^2 over 1/60 s: 6 N s).
    double ground = 0.0;
    for (std::size_t c = 0; c < wall.contacts.size(); ++c)
        if (wall.contacts[c].b == 0) ground += r.impulses[c];
    CHECK(ground == doctest::Approx(6.0).epsilon(1e-9));
    for (std::size_t k = 1; k < bodies.size(); ++k) {
        CHECK(std::fabs(bodies[k].velocity.x) <= 1e-8);
        CHECK(std::fabs(bodies[k].velocity.y) <= 1e-8);
        CHECK(std::fabs(bodies[k].angularVelocity) <= 1e-8);
    }
    // Same bits on a second call.
    std::vector<Body2> again = wall.bodies;
    const Resolution r2 = resolveActiveSet(again, wall.contacts, cold, options, ActiveSetOptions{});
    REQUIRE(r2.impulses.size() == r.impulses.size());
    CHECK(std::memcmp(r2.impulses.data(), r.impulses.data(), r.impulses.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(r2.tangentImpulses.data(), r.tangentImpulses.data(), r.tangentImpulses.size() * sizeof(double)) == 0);
    CHECK(r2.work == r.work);
    // With a pattern cache: the same bits. The interior-point answer (the cold start's) analyses its body-space system
    // with the cache's workspace but does not keep it (a landing's contact graph does not come back); the path's own
    // systems (the primal-dual iteration without the interior point) are kept, and the second call finds them there.
    for (const bool interiorPoint : {true, false}) {
        SymmetricPatternCache cache;
        ActiveSetOptions plain, cached;
        plain.interiorPoint = cached.interiorPoint = interiorPoint;
        cached.patternCache = &cache;
        std::vector<Body2> without = wall.bodies;
        const Resolution r0 = resolveActiveSet(without, wall.contacts, cold, options, plain);
        for (int call = 0; call < 2; ++call) {
            std::vector<Body2> withCache = wall.bodies;
            const Resolution rc = resolveActiveSet(withCache, wall.contacts, cold, options, cached);
            REQUIRE(rc.impulses.size() == r0.impulses.size());
            CHECK(std::memcmp(rc.impulses.data(), r0.impulses.data(), r0.impulses.size() * sizeof(double)) == 0);
            CHECK(std::memcmp(rc.tangentImpulses.data(), r0.tangentImpulses.data(),
                              r0.tangentImpulses.size() * sizeof(double)) == 0);
            CHECK(rc.work == r0.work);
        }
        if (interiorPoint) {
            CHECK(cache.size() == 0);
        } else {
            CHECK(cache.size() > 0);
            CHECK(cache.hits() >= cache.size());  // every pattern of the second call was met in the first
        }
    }
}

TEST_CASE("active-set path: a cold start begins with the interior-point answer") {
    // A 10 x 10 wall from zero impulses: with the interior-point start (the default) the answer of the convex
    // relaxation is certified as it stands, with no system of the path factored; without it the primal-dual
    // iteration factors the whole system from the zero impulses. Both answers are certified on the assembled LCP and
    // stop the wall. (On this small wall one such factorisation is enough and costs less; docs/solver.md has
    // where the interior-point start pays.)
    const Wall wall = restingWall(10, 10, 0.6);
    ResolverOptions options;
    options.frictionDirections = 2;
    const std::vector<double> cold(wall.contacts.size() * 3, 0.0);
    ActiveSetOptions primalDual;
    primalDual.interiorPoint = false;
    std::vector<Body2> ipBodies = wall.bodies, pdBodies = wall.bodies;
    const Resolution ip = resolveActiveSet(ipBodies, wall.contacts, cold, options, ActiveSetOptions{});
    const Resolution pd = resolveActiveSet(pdBodies, wall.contacts, cold, options, primalDual);
    REQUIRE(ip.status == LcpStatus::solved);
    REQUIRE(pd.status == LcpStatus::solved);
    CHECK(ip.interiorPoint);
    CHECK_FALSE(pd.interiorPoint);
    MESSAGE("cold 10 x 10 wall: work " << ip.work << " from the interior-point answer, " << pd.work
                                       << " by the primal-dual iteration; analyses " << ip.patternAnalyses << " and "
                                       << pd.patternAnalyses);
    CHECK(ip.patternAnalyses == 0);  // no system of the path was factored
    CHECK(pd.patternAnalyses > 0);
    CHECK(assembledResidual(wall.bodies, wall.contacts, ip, options) <= options.lcp.residualTolerance + 1e-13);
    CHECK(assembledResidual(wall.bodies, wall.contacts, pd, options) <= options.lcp.residualTolerance + 1e-13);
    double ground = 0.0;
    for (std::size_t c = 0; c < wall.contacts.size(); ++c)
        if (wall.contacts[c].b == 0) ground += ip.impulses[c];
    CHECK(ground == doctest::Approx(100.0 / 6.0).epsilon(1e-9));  // 100 boxes of 1 kg, 10 m/s^2, 1/60 s
    for (std::size_t k = 1; k < ipBodies.size(); ++k) {
        CHECK(std::fabs(ipBodies[k].velocity.x) <= 1e-8);
        CHECK(std::fabs(ipBodies[k].velocity.y) <= 1e-8);
        CHECK(std::fabs(ipBodies[k].angularVelocity) <= 1e-8);
    }
}

TEST_CASE("active-set path: incomingVelocity predicts the next step's impulses of a settled wall") {
    // A 4 x 4 wall whose boxes come in falling at 1e-6 m/s (a settled pile's velocity error) before this step's
    // gravity. The answer stops them: the ground carries 16 boxes x (g dt + 1e-6) N s. The prediction is the load
    // alone (16 g dt): the next step's problem (bodies at rest, then gravity) is certified by it as it stands, while
    // the answer itself, carried, meets that problem 1e-6 m/s off and needs a factorisation.
    const double dt = 1.0 / 60.0, g = 10.0, slow = 1e-6;
    Wall wall = restingWall(4, 4, 0.6);
    for (std::size_t k = 1; k < wall.bodies.size(); ++k) wall.bodies[k].velocity.y = -slow - g * dt;
    std::vector<double> incoming(3 * wall.bodies.size(), 0.0);
    for (std::size_t k = 1; k < wall.bodies.size(); ++k) incoming[3 * k + 1] = -slow;
    ResolverOptions options;
    options.frictionDirections = 2;
    const std::vector<double> cold(wall.contacts.size() * 3, 0.0);
    // The prediction needs the factors of the path's last iteration: this cold start takes the primal-dual
    // iteration (with the interior-point start, the interior-point answer is certified as it stands and there are none).
    ActiveSetOptions predict, noPrediction;
    predict.incomingVelocity = &incoming;
    predict.interiorPoint = noPrediction.interiorPoint = false;
    std::vector<Body2> bodies = wall.bodies, plainBodies = wall.bodies;
    const Resolution r = resolveActiveSet(bodies, wall.contacts, cold, options, predict);
    const Resolution plain = resolveActiveSet(plainBodies, wall.contacts, cold, options, noPrediction);
    REQUIRE(r.status == LcpStatus::solved);
    REQUIRE(plain.status == LcpStatus::solved);
    CHECK(plain.predictedImpulses.empty());
    // The prediction changes nothing of the answer.
    REQUIRE(r.impulses.size() == plain.impulses.size());
    CHECK(std::memcmp(r.impulses.data(), plain.impulses.data(), r.impulses.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(r.tangentImpulses.data(), plain.tangentImpulses.data(),
                      r.tangentImpulses.size() * sizeof(double)) == 0);
    REQUIRE(r.predictedImpulses.size() == 3 * wall.contacts.size());
    double ground = 0.0, groundRest = 0.0;
    for (std::size_t c = 0; c < wall.contacts.size(); ++c) {
        if (wall.contacts[c].b != 0) continue;
        ground += r.impulses[c];
        groundRest += r.predictedImpulses[3 * c];
    }
    CHECK(ground == doctest::Approx(16.0 * (g * dt + slow)).epsilon(1e-10));
    CHECK(groundRest == doctest::Approx(16.0 * g * dt).epsilon(1e-10));
    // The next step: the bodies left at rest (to the tolerance), then gravity.
    std::vector<Body2> next = wall.bodies;
    for (std::size_t k = 1; k < next.size(); ++k) {
        next[k].velocity = {bodies[k].velocity.x, bodies[k].velocity.y - g * dt};
        next[k].angularVelocity = bodies[k].angularVelocity;
    }
    std::vector<double> carried;
    for (std::size_t c = 0; c < wall.contacts.size(); ++c) {
        carried.push_back(r.impulses[c]);
        carried.push_back(r.tangentImpulses[2 * c]);
        carried.push_back(r.tangentImpulses[2 * c + 1]);
    }
    std::vector<Body2> a = next, b = next;
    const Resolution fromPrediction = resolveActiveSet(a, wall.contacts, r.predictedImpulses, options, ActiveSetOptions{});
    const Resolution fromAnswer = resolveActiveSet(b, wall.contacts, carried, options, ActiveSetOptions{});
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

TEST_CASE("active-set path: a scratch kept across solves gives the bits of solves without one") {
    // A sequence as a world's worker meets it: a big wall solved cold, then warm from its own answer, then from a
    // far warm start (the interior-point restart), a different wall in between, and the big wall again. With one
    // scratch for all of them, systems with the last one's entries are refilled in place (no sort, no analysis);
    // every answer must be the bits, and the work, of the same solve with no scratch.
    const Wall big = restingWall(12, 10, 0.6), other = restingWall(7, 5, 0.4);
    ResolverOptions options;
    options.frictionDirections = 2;
    auto answerAsWarm = [](const Resolution& r) {
        std::vector<double> w;
        for (std::size_t c = 0; c < r.impulses.size(); ++c) {
            w.push_back(r.impulses[c]);
            w.push_back(r.tangentImpulses[2 * c]);
            w.push_back(r.tangentImpulses[2 * c + 1]);
        }
        return w;
    };
    ActiveSetScratch scratch;
    ActiveSetOptions kept;
    kept.scratch = &scratch;
    std::vector<double> bigWarm(big.contacts.size() * 3, 0.0), otherWarm(other.contacts.size() * 3, 0.0);
    int interiorPoints = 0;
    for (int call = 0; call < 9; ++call) {
        CAPTURE(call);
        const bool useOther = call == 3 || call == 4;
        const Wall& wall = useOther ? other : big;
        std::vector<double>& warm = useOther ? otherWarm : bigWarm;
        const std::vector<double> start = call == 2 || call == 6 || call == 7 ? farWarmStart(wall) : warm;
        std::vector<Body2> plain = wall.bodies, withScratch = wall.bodies;
        // Cold starts take the primal-dual iteration, whose systems the scratch keeps; the others may restart from
        // the interior-point answer, whose system it keeps too.
        const bool cold = std::all_of(start.begin(), start.end(), [](double v) { return v == 0.0; });
        ActiveSetOptions none;
        none.interiorPoint = kept.interiorPoint = !cold;
        const Resolution a = resolveActiveSet(plain, wall.contacts, start, options, none);
        const Resolution b = resolveActiveSet(withScratch, wall.contacts, start, options, kept);
        REQUIRE(a.status == b.status);
        REQUIRE(a.impulses.size() == b.impulses.size());
        CHECK(std::memcmp(a.impulses.data(), b.impulses.data(), a.impulses.size() * sizeof(double)) == 0);
        CHECK(std::memcmp(a.tangentImpulses.data(), b.tangentImpulses.data(),
                          a.tangentImpulses.size() * sizeof(double)) == 0);
        CHECK(a.work == b.work);
        CHECK(a.interiorPoint == b.interiorPoint);
        for (std::size_t k = 0; k < plain.size(); ++k) {
            CHECK(std::memcmp(&plain[k].velocity, &withScratch[k].velocity, sizeof(Vec2)) == 0);
            CHECK(std::memcmp(&plain[k].angularVelocity, &withScratch[k].angularVelocity, sizeof(double)) == 0);
        }
        interiorPoints += b.interiorPoint ? 1 : 0;
        if (b.status == LcpStatus::solved) warm = answerAsWarm(b);
    }
    // The sequence went through the interior-point restart and both kinds of refill.
    CHECK(interiorPoints >= 3);
    CHECK(scratch.refills > 0);
    CHECK(scratch.interiorPoint.refills > 0);
    MESSAGE("refilled systems: " << scratch.refills << " of the path, " << scratch.interiorPoint.refills
                                 << " of the interior-point restart");
}

TEST_CASE("active-set path: agrees with Lemke on the velocities of a sliding, bouncing island") {
    // The wall thrown sideways at 2 m/s with e = 0.5 on the ground rows: slipping contacts (mu 0.3) and a bounce.
    Wall wall = restingWall(4, 3, 0.3);
    for (auto& b : wall.bodies)
        if (b.invMass > 0.0) b.velocity = {2.0, -3.0};
    for (auto& c : wall.contacts)
        if (c.b == 0) c.restitution = 0.5;
    ResolverOptions options;
    options.frictionDirections = 2;
    options.restitutionThreshold = 1.0;
    std::vector<Body2> fast = wall.bodies, lemke = wall.bodies;
    const std::vector<double> cold(wall.contacts.size() * 3, 0.0);
    const Resolution a = resolveActiveSet(fast, wall.contacts, cold, options, ActiveSetOptions{});
    LemkeSolver solver;
    const Resolution b = resolveWithFriction(lemke, wall.contacts, options, solver);
    REQUIRE(a.status == LcpStatus::solved);
    REQUIRE(b.status == LcpStatus::solved);
    CHECK(assembledResidual(wall.bodies, wall.contacts, a, options) <= 1e-9 + 1e-13);
    // A rigid wall's post-impulse velocities are unique even where its impulses are not.
    for (std::size_t k = 1; k < fast.size(); ++k) {
        CHECK(fast[k].velocity.x == doctest::Approx(lemke[k].velocity.x).epsilon(1e-7));
        CHECK(fast[k].velocity.y == doctest::Approx(lemke[k].velocity.y).epsilon(1e-7));
        CHECK(fast[k].angularVelocity == doctest::Approx(lemke[k].angularVelocity).epsilon(1e-7));
    }
    // Bounced at e u on the ground (u = -3 m/s) and sliding with friction 0.3 of the normal impulse.
    CHECK(fast[1].velocity.y == doctest::Approx(1.5).epsilon(1e-7));
}

TEST_CASE("active-set path: a warm start far from the answer restarts from the interior-point answer") {
    // Warm impulses that belong to another problem (every contact pushing at three times a box's weight, friction on
    // its cone's rim): the face of that start does not hold, and its best iterate is far from an answer, so the path
    // restarts from the interior-point answer of the convex relaxation. The wall at rest, and the wall thrown
    // sideways (mu 0.3), where contacts slide and the relaxation's own answer is not the Stewart–Trinkle one (it
    // lets a sliding contact separate at mu |u_t|): both end certified on the assembled LCP.
    for (const bool thrown : {false, true}) {
        CAPTURE(thrown);
        Wall wall = restingWall(6, 6, thrown ? 0.3 : 0.6);
        if (thrown) {
            for (auto& b : wall.bodies)
                if (b.invMass > 0.0) b.velocity = {2.0, -3.0};
        }
        ResolverOptions options;
        options.frictionDirections = 2;
        const std::vector<double> wrong = farWarmStart(wall);
        std::vector<Body2> bodies = wall.bodies;
        const Resolution r = resolveActiveSet(bodies, wall.contacts, wrong, options, ActiveSetOptions{});
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(r.interiorPoint);
        CHECK(assembledResidual(wall.bodies, wall.contacts, r, options) <= options.lcp.residualTolerance + 1e-13);
        // At rest, Lemke's answer has the same velocities (every box stops; the impulses are not unique). Sliding, a
        // friction LCP can have more than one answer, and both are checked on the assembled LCP instead.
        std::vector<Body2> lemke = wall.bodies;
        LemkeSolver solver;
        const Resolution b = resolveWithFriction(lemke, wall.contacts, options, solver);
        REQUIRE(b.status == LcpStatus::solved);
        CHECK(assembledResidual(wall.bodies, wall.contacts, b, options) <= options.lcp.residualTolerance + 1e-13);
        for (std::size_t k = 1; k < bodies.size() && !thrown; ++k) {
            CHECK(bodies[k].velocity.x == doctest::Approx(lemke[k].velocity.x).epsilon(1e-7));
            CHECK(bodies[k].velocity.y == doctest::Approx(lemke[k].velocity.y).epsilon(1e-7));
            CHECK(bodies[k].angularVelocity == doctest::Approx(lemke[k].angularVelocity).epsilon(1e-7));
        }
        // Without the restart the same start is not certified (it goes to Lemke), and the answer repeats its bits.
        ActiveSetOptions without;
        without.interiorPoint = false;
        std::vector<Body2> plain = wall.bodies;
        const Resolution p = resolveActiveSet(plain, wall.contacts, wrong, options, without);
        CHECK(!p.interiorPoint);
        CHECK(p.status != LcpStatus::solved);
        MESSAGE("without the restart: " << std::string(statusName(p.status)) << ", scaled residual " << p.scaledResidual);
        std::vector<Body2> again = wall.bodies;
        const Resolution r2 = resolveActiveSet(again, wall.contacts, wrong, options, ActiveSetOptions{});
        REQUIRE(r2.impulses.size() == r.impulses.size());
        CHECK(std::memcmp(r2.impulses.data(), r.impulses.data(), r.impulses.size() * sizeof(double)) == 0);
        CHECK(r2.work == r.work);
    }
}

TEST_CASE("active-set path: with stickWrongWaySlip a rim contact sliding along its friction sticks on the warm face") {
    // A two-row wall sliding slowly sideways (0.05 m/s, mu 0.6: the ground's friction stops it within the step),
    // warm-started from the resting answer with every ground contact's friction on its cone's rim along the slide, as
    // if friction pushed the wall on. On that face those contacts slide the way their friction pushes, which the LCP
    // forbids. With stickWrongWaySlip (the world sets it on islands of kPathFirstContacts+ contacts) they stick, and
    // the answer is certified on the warm start's face (phase 0) with the wall at rest; without it that face is left
    // uncertified and phase 1 finds the answer, at more work. The interior-point restart is off, so that phase 0
    // sees this start.
    Wall wall = restingWall(6, 2, 0.6);
    for (auto& b : wall.bodies)
        if (b.invMass > 0.0) b.velocity.x = 0.05;
    ResolverOptions options;
    options.frictionDirections = 2;
    std::vector<double> warm;
    for (const Contact2& c : wall.contacts) {
        const bool ground = c.b == 0;
        const double pn = ground ? 2.0 / 60.0 * 10.0 / 2.0 : 0.0;  // each column's weight on its two points
        warm.push_back(pn);
        warm.push_back(ground ? c.friction * pn : 0.0);  // along +x, the slide
        warm.push_back(0.0);
    }
    ActiveSetOptions fix;
    fix.interiorPoint = false;
    fix.stickWrongWaySlip = true;
    std::vector<Body2> bodies = wall.bodies;
    const Resolution r = resolveActiveSet(bodies, wall.contacts, warm, options, fix);
    REQUIRE(r.status == LcpStatus::solved);
    CHECK(r.warmFace);
    CHECK(assembledResidual(wall.bodies, wall.contacts, r, options) <= options.lcp.residualTolerance + 1e-13);
    for (std::size_t k = 1; k < bodies.size(); ++k) {
        CHECK(std::fabs(bodies[k].velocity.x) <= 1e-8);
        CHECK(std::fabs(bodies[k].velocity.y) <= 1e-8);
    }
    // The ground's friction takes the wall's momentum (12 boxes of 1 kg at 0.05 m/s), against the slide.
    double friction = 0.0;
    for (std::size_t c = 0; c < wall.contacts.size(); ++c)
        if (wall.contacts[c].b == 0) friction += r.tangentImpulses[2 * c];
    CHECK(friction == doctest::Approx(-0.6).epsilon(1e-9));
    ActiveSetOptions plain;
    plain.interiorPoint = false;
    std::vector<Body2> other = wall.bodies;
    const Resolution p = resolveActiveSet(other, wall.contacts, warm, options, plain);
    MESSAGE("work with the rule " << r.work << ", without " << p.work);
    CHECK(p.status == LcpStatus::solved);
    CHECK(!p.warmFace);
    CHECK(p.work > 2 * r.work);
}

TEST_CASE("active-set path: with reuseSupersetPattern a kept face that releases contacts keeps its analysed pattern") {
    // A resting 8 x 4 wall whose top right box slides away from its left neighbour at 0.01 m/s (its ground
    // friction stops it within the step), warm-started from the resting answer with a small push (1e-3 N s) on
    // the two points between those two boxes. On the warm start's face that pair would have to pull: the face's step
    // releases it, and the next face is a subset of the first. With reuseSupersetPattern that face is factored on
    // the first one's analysed pattern (the released unknowns stored as zeros); the answer is the same up to rounding.
    constexpr int columns = 8, rows = 4;
    Wall wall = restingWall(columns, rows, 0.6);
    const int slider = 1 + (rows - 1) * columns + columns - 1;
    wall.bodies[std::size_t(slider)].velocity.x = 0.01;
    ResolverOptions options;
    options.frictionDirections = 2;
    std::vector<double> warm;
    for (const Contact2& c : wall.contacts) {
        const int row = (c.a - 1) / columns;                                // the upper (or right) body's row
        const double weight = double(rows - row) * (10.0 / 60.0) / 2.0;     // of its column, on each bottom point
        const double pn = c.normal.y > 0.5 ? weight : c.a == slider ? 1e-3 : 0.0;
        warm.push_back(pn);
        warm.push_back(0.0);
        warm.push_back(0.0);
    }
    ActiveSetOptions reuse;
    reuse.interiorPoint = false;
    reuse.reuseSupersetPattern = true;
    ActiveSetOptions exact;
    exact.interiorPoint = false;
    std::vector<Body2> a = wall.bodies, b = wall.bodies;
    const Resolution r = resolveActiveSet(a, wall.contacts, warm, options, reuse);
    const Resolution e = resolveActiveSet(b, wall.contacts, warm, options, exact);
    MESSAGE("with reuse: " << r.patternAnalyses << " analyses, " << r.supersetFactorizations
                           << " factorisations on a larger pattern; without: " << e.patternAnalyses << " analyses");
    REQUIRE(r.status == LcpStatus::solved);
    REQUIRE(e.status == LcpStatus::solved);
    CHECK(r.warmFace);
    CHECK(e.warmFace);
    CHECK(r.supersetFactorizations >= 1);
    CHECK(e.supersetFactorizations == 0);
    CHECK(r.patternAnalyses < e.patternAnalyses);
    CHECK(assembledResidual(wall.bodies, wall.contacts, r, options) <= options.lcp.residualTolerance + 1e-13);
    for (std::size_t c = 0; c < wall.contacts.size(); ++c) {
        CHECK(r.impulses[c] == doctest::Approx(e.impulses[c]).epsilon(1e-9).scale(1.0));
        if (wall.contacts[c].a == slider && wall.contacts[c].normal.x > 0.5) CHECK(r.impulses[c] == 0.0);  // released
    }
    for (std::size_t k = 1; k < a.size(); ++k) {
        CHECK(a[k].velocity.x == doctest::Approx(b[k].velocity.x).epsilon(1e-9).scale(1.0));
        CHECK(a[k].velocity.y == doctest::Approx(b[k].velocity.y).epsilon(1e-9).scale(1.0));
        CHECK(std::fabs(a[k].velocity.x) <= 1e-8);  // the slider stopped by its ground friction
        CHECK(std::fabs(a[k].velocity.y) <= 1e-8);  // the wall at rest
    }
}

TEST_CASE("active-set path: with floorExit a warm face that ends just above the tolerance is a near miss there") {
    // A 16 x 16 resting wall warm-started from its own answer, certified against a tolerance at the floor of
    // rounding (3e-16 scaled): the warm start's face ends a little above it. With floorExit (the world sets it on
    // islands of kPathFirstContacts+ contacts, where every iteration is a large factorisation) the answer is that
    // face's best iterate, applied as a near miss; without it phases 1 and 2 run and end no better.
    const Wall wall = restingWall(16, 16, 0.6);
    ResolverOptions options;
    options.frictionDirections = 2;
    options.acceptResidual = 1e-6;
    std::vector<Body2> first = wall.bodies;
    const Resolution cold = resolveActiveSet(first, wall.contacts, std::vector<double>(wall.contacts.size() * 3, 0.0),
                                             options, ActiveSetOptions{});
    REQUIRE(cold.status == LcpStatus::solved);
    std::vector<double> warm;
    for (std::size_t c = 0; c < wall.contacts.size(); ++c) {
        warm.push_back(cold.impulses[c]);
        warm.push_back(cold.tangentImpulses[2 * c]);
        warm.push_back(cold.tangentImpulses[2 * c + 1]);
    }
    options.lcp.residualTolerance = 3e-16;
    ActiveSetOptions floor;
    floor.floorExit = 10.0;
    std::vector<Body2> withExit = wall.bodies, without = wall.bodies;
    const Resolution e = resolveActiveSet(withExit, wall.contacts, warm, options, floor);
    const Resolution f = resolveActiveSet(without, wall.contacts, warm, options, ActiveSetOptions{});
    MESSAGE("floorExit: " << e.scaledResidual / options.lcp.residualTolerance << " tolerances, work " << e.work
                          << "; without: " << f.scaledResidual / options.lcp.residualTolerance << ", work " << f.work);
    CHECK(e.status == LcpStatus::numerical_failure);
    CHECK(e.approximate);
    CHECK(e.activeSet);
    CHECK(e.scaledResidual > options.lcp.residualTolerance);
    CHECK(e.scaledResidual <= 10.0 * options.lcp.residualTolerance);
    CHECK(f.approximate);
    CHECK(e.work < f.work);
    for (std::size_t k = 1; k < withExit.size(); ++k) {  // applied: the wall at rest
        CHECK(std::fabs(withExit[k].velocity.x) <= 1e-12);
        CHECK(std::fabs(withExit[k].velocity.y) <= 1e-12);
    }
    // Where the warm face certifies, floorExit changes nothing.
    options.lcp.residualTolerance = 1e-9;
    std::vector<Body2> a = wall.bodies, b = wall.bodies;
    const Resolution ea = resolveActiveSet(a, wall.contacts, warm, options, floor);
    const Resolution fb = resolveActiveSet(b, wall.contacts, warm, options, ActiveSetOptions{});
    REQUIRE(ea.status == LcpStatus::solved);
    CHECK(ea.warmFace);
    CHECK(ea.work == fb.work);
    CHECK(std::memcmp(ea.impulses.data(), fb.impulses.data(), ea.impulses.size() * sizeof(double)) == 0);
}

TEST_CASE("active-set path: declines what it cannot take, leaving the bodies untouched") {
    const Wall wall = restingWall(2, 2, 0.5);
    ResolverOptions options;
    std::vector<Body2> bodies = wall.bodies;
    // Warm impulses of the wrong size.
    Resolution r = resolveActiveSet(bodies, wall.contacts, std::vector<double>(3, 0.0), options, ActiveSetOptions{});
    CHECK(r.status == LcpStatus::pivot_limit);
    CHECK(std::memcmp(&bodies[1], &wall.bodies[1], sizeof(Body2)) == 0);
    // A work limit spent before the first iteration and a cold start that is not an answer: nothing applied.
    ActiveSetOptions none;
    none.maxWork = 1;
    r = resolveActiveSet(bodies, wall.contacts, std::vector<double>(wall.contacts.size() * 3, 0.0), options, none);
    CHECK(r.status != LcpStatus::solved);
    CHECK(std::memcmp(&bodies[1], &wall.bodies[1], sizeof(Body2)) == 0);
    // Bad input is reported as such.
    std::vector<Contact2> bad = wall.contacts;
    bad[0].a = 99;
    r = resolveActiveSet(bodies, bad, std::vector<double>(bad.size() * 3, 0.0), options, ActiveSetOptions{});
    CHECK(r.status == LcpStatus::invalid_input);
    // 3D declines pyramids of more than four directions (tests/test_active_set3.cpp).
    std::vector<Body3> bodies3(2);
    bodies3[1].invMass = 1.0;
    bodies3[1].invInertia = Mat3::Identity();
    const std::vector<Contact3> contacts3 = {makeContact<Dim3>(1, 0, Vec3(0, 0, 0), Vec3(0, 0, 1), 0.0, 0.5)};
    ResolverOptions six = options;
    six.frictionDirections = 6;
    r = resolveActiveSet(bodies3, contacts3, std::vector<double>(4, 0.0), six, ActiveSetOptions{});
    CHECK(r.status == LcpStatus::pivot_limit);
}

}  // TEST_SUITE
