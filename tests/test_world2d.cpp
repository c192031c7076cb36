// tests/test_world2d.cpp — the 2D world step: free fall, resting contact, the cradle fingerprint inside the world,
// sleeping, bad input, determinism of whole runs.
#include "test_support.h"

#include "make_scenes2d.h"
#include "scene_dir.h"
#include "scene_json.h"
#include "step_budget.h"
#include "world2d.h"

#include <algorithm>
#include <cmath>
#include <vector>

using namespace unison;

namespace {

Shape2 boxShape(double hx, double hy, double density = 1.0, double friction = 0.6) {
    Shape2 s;
    s.type = ShapeType::polygon;
    REQUIRE(makeBox(hx, hy, {}, 0.0, &s.polygon).empty());
    s.density = density;
    s.friction = friction;
    return s;
}

Shape2 groundShape() {
    Shape2 s;
    s.type = ShapeType::segment;
    REQUIRE(makeSegment({-40.0, 0.0}, {40.0, 0.0}, &s.segment).empty());
    return s;
}

// Adds the ground and a 1 m box (density 1) at (0, y) with restitution e; returns the box.
BodyId addGroundAndBox(World2& world, double y, double e = 0.0) {
    BodyDef2 g;
    g.type = BodyType::staticBody;
    world.createBody(g, {groundShape()});
    BodyDef2 def;
    def.position = {0.0, y};
    Shape2 box = boxShape(0.5, 0.5);
    box.restitution = e;
    return world.createBody(def, {box});
}

}  // namespace

TEST_SUITE("world2d") {

TEST_CASE("free fall follows semi-implicit Euler exactly") {
    World2 world;
    BodyDef2 def;
    def.position = {0.0, 10.0};
    const BodyId id = world.createBody(def, {boxShape(0.5, 0.5)});
    REQUIRE_FALSE(id.isNull());
    const double dt = 1.0 / 60.0;
    double v = 0.0, y = 10.0;
    for (int i = 0; i < 30; ++i) {
        world.step();
        v += dt * -10.0;
        y += dt * v;
    }
    CHECK(world.state(id)->velocity.y == doctest::Approx(v).epsilon(1e-14));
    CHECK(world.state(id)->position.y == doctest::Approx(y).epsilon(1e-14));
}

TEST_CASE("a box dropped on the ground comes to rest on it, and sleeps") {
    World2 world;
    const BodyId box = addGroundAndBox(world, 2.0);
    for (int i = 0; i < 240; ++i) world.step();
    const BodyState2* s = world.state(box);
    CHECK(s->position.y == doctest::Approx(0.5).epsilon(0.02));
    CHECK(std::fabs(s->velocity.y) < 1e-6);
    CHECK(world.stats().failedIslands == 0);
    CHECK_FALSE(world.info(box)->awake);
}

TEST_CASE("a box landing on a sleeping box wakes it, and both come to rest stacked") {
    World2 world;
    const BodyId below = addGroundAndBox(world, 0.5);
    for (int i = 0; i < 240; ++i) world.step();
    REQUIRE_FALSE(world.info(below)->awake);
    BodyDef2 def;
    def.position = {0.2, 3.0};
    const BodyId above = world.createBody(def, {boxShape(0.5, 0.5)});
    bool woke = false;
    for (int i = 0; i < 60 && !woke; ++i) {
        world.step();
        woke = world.info(below)->awake;
    }
    CHECK(woke);  // the contact joined the sleeping box's island, and the island woke
    for (int i = 0; i < 300; ++i) world.step();
    CHECK(world.state(below)->position.y == doctest::Approx(0.5).epsilon(0.02));
    CHECK(world.state(above)->position.y == doctest::Approx(1.5).epsilon(0.02));
    CHECK(world.stats().failedIslands == 0);
}

TEST_CASE("a failed 2D friction solve falls back to the frictionless LCP, and the step counts both solves' pivots") {
    // With every LCP capped at 4 pivots a box landing while sliding cannot finish its friction LCP (normals, both
    // tangent directions and slacks enter), and the frictionless LCP of its two normals can.
    WorldDef2 capped;
    capped.enableSleep = false;
    capped.lcp.maxPivots = 4;
    World2 w(capped);
    const BodyId box = addGroundAndBox(w, 0.51);
    REQUIRE(w.setVelocity(box, {2.0, -1.0}, 0.0));
    int failedSteps = 0;
    for (int i = 0; i < 3; ++i) {
        const double vx = w.state(box)->velocity.x;
        w.step();
        const StepStats2& c = w.stats();
        if (c.failedIslands == 0) continue;
        ++failedSteps;
        CHECK(c.unsolvedIslands == 0);
        CHECK(c.approximateIslands == 0);
        CHECK(c.pivots > capped.lcp.maxPivots);  // the failed friction solve's pivots and the fallback's
        CHECK(c.maxIslandPivots == c.pivots);
        CHECK(w.state(box)->velocity.x == doctest::Approx(vx).epsilon(1e-12));  // no friction in the answer
    }
    CHECK(failedSteps > 0);
}

TEST_CASE("the contact list holds every contact of the step once: sleeping, awake, budgeted, on any thread count") {
    // A box asleep on the ground and a second one landing far from it: the step writes each island's contacts as
    // it finishes the island (a sleeping one as found), so every entry must name the step's own bodies, and a
    // resting awake box's normal impulses must carry its weight for the step (1 kg, 10 m/s^2, 1/60 s).
    for (const std::uint64_t budget : {std::uint64_t(0), work::fromMilliseconds(0.002)}) {
        std::vector<std::vector<ContactPoint2>> lists[2];
        for (int threads : {1, 2}) {
            CAPTURE(budget);
            CAPTURE(threads);
            World2 world;
            REQUIRE(world.setTaskSystem(TaskSystem{threads}));
            world.setStepBudget(budget);
            const BodyId asleep = addGroundAndBox(world, 0.5);
            for (int i = 0; i < 240; ++i) world.step();
            REQUIRE_FALSE(world.info(asleep)->awake);
            BodyDef2 def;
            def.position = {10.0, 2.0};
            const BodyId lands = world.createBody(def, {boxShape(0.5, 0.5)});
            int sleepingListed = 0, restingChecked = 0;
            for (int i = 0; i < 90; ++i) {
                world.step();
                const auto& list = world.contacts();
                CHECK(int(list.size()) == world.stats().contacts);
                double carried = 0.0;
                for (const ContactPoint2& cp : list) {
                    CHECK(world.valid(cp.a));
                    CHECK(world.valid(cp.b));
                    CHECK(cp.a != cp.b);
                    CHECK(std::fabs(std::hypot(cp.normal.x, cp.normal.y) - 1.0) < 1e-12);
                    if (cp.a == asleep || cp.b == asleep) {
                        ++sleepingListed;
                        CHECK(cp.normalImpulse == 0.0);  // not solved while it sleeps
                    }
                    if (cp.a == lands || cp.b == lands) carried += cp.normalImpulse;
                }
                if (budget == 0 && i >= 50 && world.info(lands)->awake) {
                    CHECK(carried == doctest::Approx(1.0 / 6.0).epsilon(1e-6));
                    ++restingChecked;
                }
                lists[threads - 1].push_back(list);
            }
            CHECK_FALSE(world.info(asleep)->awake);
            CHECK(sleepingListed >= 2 * 90);  // both corners of the sleeping box, every step
            if (budget == 0) CHECK(restingChecked >= 10);
        }
        REQUIRE(lists[0].size() == lists[1].size());
        for (std::size_t t = 0; t < lists[0].size(); ++t) {
            REQUIRE(lists[0][t].size() == lists[1][t].size());
            for (std::size_t k = 0; k < lists[0][t].size(); ++k) {
                const ContactPoint2& p = lists[0][t][k];
                const ContactPoint2& q = lists[1][t][k];
                CHECK((p.a == q.a && p.b == q.b && p.point.x == q.point.x && p.point.y == q.point.y &&
                       p.normalImpulse == q.normalImpulse && p.tangentImpulse == q.tangentImpulse &&
                       p.featureId == q.featureId));
            }
        }
    }
}

TEST_CASE("Newton's cradle inside the world keeps the simultaneous closed form") {
    const auto scene = scenes::readSceneFile(scenes::sceneDir() + "/cradle.json");
    auto loaded = scenes::loadScene2(scene, "cradle.json");
    loaded.world->step();
    const double v = 2.0, e = 1.0, n = 5.0;
    CHECK(loaded.world->state(loaded.bodies[0])->velocity.x == doctest::Approx(v * (1.0 - (1.0 + e) * (n - 1.0) / n)).epsilon(1e-9));
    for (int k = 1; k < 5; ++k)
        CHECK(loaded.world->state(loaded.bodies[std::size_t(k)])->velocity.x == doctest::Approx(v * (1.0 + e) / n).epsilon(1e-9));
}

TEST_CASE("restitution row: rebound apex is e^2 h within 3 %") {
    // Balls of radius 0.5 dropped from y = 5 (fall height h = 4.5) with e = k/6. The world bounces a contact at its
    // time of impact inside the step (WorldStep::solveIsland, core/world_step.h), so what remains is the
    // semi-implicit Euler discretisation of the two flights: measured +0.6 % at e = 1 to +2.2 % at e = 1/6 (Box2D 2.4.1: +0.5 % to
    // +1.2 %; tests/test_box2d_validation.cpp). Before that fix the apex was up to (1 + e) v dt high (+64 % at
    // e = 1/6). e = 0 must not bounce at all.
    const auto scene = scenes::readSceneFile(scenes::sceneDir() + "/restitution_row.json");
    auto loaded = scenes::loadScene2(scene, "restitution_row.json");
    World2& world = *loaded.world;
    const double h = 4.5;
    std::vector<double> apex(8, -1.0), prevVy(8, -1.0);
    std::vector<int> bounces(8, 0);
    for (int step = 0; step < 400; ++step) {
        world.step();
        for (int k = 1; k < 8; ++k) {
            const BodyState2* s = world.state(loaded.bodies[std::size_t(k)]);
            const double vy = s->velocity.y;
            if (prevVy[std::size_t(k)] < 0.0 && vy > 0.0) ++bounces[std::size_t(k)];
            if (bounces[std::size_t(k)] == 1 && prevVy[std::size_t(k)] > 0.0 && vy <= 0.0 && apex[std::size_t(k)] < 0.0)
                apex[std::size_t(k)] = s->position.y;
            prevVy[std::size_t(k)] = vy;
        }
    }
    CHECK(bounces[1] == 0);
    for (int k = 2; k < 8; ++k) {
        const double e = (k - 1) / 6.0;
        CAPTURE(e);
        const double rise = apex[std::size_t(k)] - 0.5;
        CHECK(std::fabs(rise - e * e * h) <= 0.03 * e * e * h);
    }
}

TEST_CASE("a box with e = 1 landing flat keeps its energy from bounce to bounce") {
    // A 1 m box (mass 1) dropped flat from y = 5 with e = 1 onto the ground: both corners bounce together. Its
    // energy at every apex (5 in 10 s) must stay within 1 % of the 50 J it started with (the 1 % covers the semi-implicit
    // Euler energy of a step-end sample, about m g^2 dt^2 n / 2). Before bounces were placed at the time of
    // impact, every bounce added about 3 % (51.6, 53.2, ... 61.7 J over 7 bounces).
    World2 world;
    const BodyId id = addGroundAndBox(world, 5.0, 1.0);
    int apexes = 0;
    double prevVy = 0.0;
    for (int i = 0; i < 600; ++i) {
        world.step();
        const BodyState2* s = world.state(id);
        if (prevVy > 0.0 && s->velocity.y <= 0.0) {
            const double energy = 0.5 * dot(s->velocity, s->velocity) + 0.5 * world.info(id)->inertia * s->angularVelocity *
                                  s->angularVelocity + 10.0 * s->center.y;
            CAPTURE(apexes);
            CHECK(std::fabs(energy - 50.0) <= 0.5);
            ++apexes;
        }
        prevVy = s->velocity.y;
    }
    CHECK(apexes >= 5);  // one flight every 1.9 s
}

TEST_CASE("invalid bodies are rejected with a message and the world is unchanged") {
    World2 world;
    std::string error;
    BodyDef2 def;
    def.position = {NAN, 0.0};
    CHECK(world.createBody(def, {boxShape(0.5, 0.5)}, &error).isNull());
    CHECK(error.find("finite") != std::string::npos);
    def.position = {0.0, 0.0};
    CHECK(world.createBody(def, {}, &error).isNull());
    CHECK(error.find("mass") != std::string::npos);
    CHECK(world.bodyCount() == 0);
}

TEST_CASE("two runs of the same scene give the same hash every step") {
    const auto scene = scenes::readSceneFile(scenes::sceneDir() + "/stack10.json");
    auto a = scenes::loadScene2(scene, "a");
    auto b = scenes::loadScene2(scene, "b");
    for (int i = 0; i < 120; ++i) {
        a.world->step();
        b.world->step();
        REQUIRE(a.world->stateHash() == b.world->stateHash());
    }
}

TEST_CASE("the 20-row testbed pyramid lands with friction in every island and residuals <= 1e-6") {
    // The landing is where the friction LCPs are most degenerate (hundreds of resting contacts with b = 0 gain new
    // neighbours every step); it once cycled to the pivot cap and fell back to the frictionless LCP. 90 steps take
    // it through the first impacts, the merge into one island and the first settled steps.
    auto scene = scenes::loadScene2(scenes::pyramidScene(20, 0.5, false), "pyramid20");
    int failed = 0, maxPivots = 0;
    double maxScaled = 0.0;
    for (int i = 0; i < 90; ++i) {
        scene.world->step();
        failed += scene.world->stats().failedIslands;
        maxPivots = std::max(maxPivots, scene.world->stats().pivots);
        maxScaled = std::max(maxScaled, scene.world->stats().maxScaledResidual);
    }
    MESSAGE("pyramid20 landing: max pivots per step " << maxPivots << ", max scaled residual " << maxScaled);
    CHECK(failed == 0);
    CHECK(maxScaled <= 1e-6);
    CHECK(scene.world->stats().islands == 1);
    // Then it rests: the warm start holds for 25 s of simulation. With a 1e-8 tangential dead zone, rounding-level
    // creep crossed it after about 20 s and every step took thousands of pivots (WorldDef2::tangentDeadZone).
    long restingPivots = 0;
    for (int i = 90; i < 1500; ++i) {
        scene.world->step();
        failed += scene.world->stats().failedIslands;
        if (i >= 300) restingPivots += scene.world->stats().pivots;
    }
    MESSAGE("pyramid20 resting, steps 300-1500: " << restingPivots << " pivots");
    CHECK(failed == 0);
    // Known and open: a contact at the edge of its friction cone creeps. Its cone violation grows ~1.4x per 40
    // steps from 2e-11 (the check accepts it below the 1e-9 tolerance), and from ~11 s on the basis is re-solved
    // every 20-40 steps (about 130 pivots each): 8796 pivots in steps 300-1500 (it was 113 with the LU check, by
    // the luck of where the pile settled; the 18-row pyramid fails in both from ~11 s, see docs/solver-notes.md). The
    // failure this bound guards against is the dead-zone creep of thousands of pivots every step.
    CHECK(restingPivots <= 12000);
}

TEST_CASE("the 5-level card house (Box2D v3's sample) stands for 10 s with friction in every island") {
    // 40 cards 2 mm thick lean on each other at 25 degrees and stand by friction alone (0.7). The island's friction
    // LCP once failed on most steps of the landing: each card end carried two contact points 2 mm apart (nearly
    // parallel rows; 4542 pivots for the first LCP, n = 704), and the landing's Lemke paths (2-5n) ran past a cap of
    // 2n + 100. Every failure applied the frictionless answer, the cards slid, and the house was flat within 0.5 s.
    const nlohmann::json json = scenes::cardHouseScene(5, false);
    auto scene = scenes::loadScene2(json, "cardhouse");
    std::vector<double> startY;
    for (BodyId id : scene.bodies) startY.push_back(scene.world->state(id)->center.y);
    int failed = 0;
    long pivots = 0;
    for (int i = 0; i < 600; ++i) {
        scene.world->step();
        failed += scene.world->stats().failedIslands;
        pivots += scene.world->stats().pivots;
    }
    MESSAGE("card house, 600 steps: " << failed << " failed islands, " << pivots << " pivots");
    CHECK(failed == 0);
    CHECK(pivots <= 30000);  // 6236 when this was written; a house that keeps re-solving costs thousands per step
    // No card moved more than 3 cm down (they settle by 2-3 mm); the top pair stays above 1.6 m.
    double topY = 0.0;
    for (std::size_t b = 1; b < scene.bodies.size(); ++b) {
        const double y = scene.world->state(scene.bodies[b])->center.y;
        CHECK(y > startY[b] - 0.03);
        topY = std::max(topY, y);
    }
    CHECK(topY > 1.6);
}

TEST_CASE("a body replaced in the same tick regroups the islands a resting scene kept from step to step") {
    // Boxes p and q rest on the ground 4 m apart, r on p. A resting scene keeps its islands from the last step
    // while no body's flag and no contact's pair of bodies changed. Replacing r by a box on q keeps the body and
    // contact counts, but the pairs change ({p, r} becomes {q, r'}): the islands must follow, exactly as in a
    // world restored from a snapshot of that moment (which builds them from nothing).
    World2 a;
    BodyDef2 g;
    g.type = BodyType::staticBody;
    a.createBody(g, {groundShape()});
    auto boxAt = [&](World2& w, double x, double y) {
        BodyDef2 def;
        def.position = {x, y};
        return w.createBody(def, {boxShape(0.5, 0.5)});
    };
    boxAt(a, 0.0, 0.5);
    const BodyId q = boxAt(a, 4.0, 0.5);
    const BodyId r = boxAt(a, 0.0, 1.5);
    for (int t = 0; t < 30; ++t) a.step();
    const int contacts = a.stats().contacts;
    const int islands = a.stats().islands;
    REQUIRE(a.destroyBody(r));
    const BodyId moved = boxAt(a, 4.0, a.state(q)->position.y + 1.0);
    REQUIRE(moved.index1 != 0);
    const std::vector<std::uint8_t> snap = a.snapshot();
    World2 b;
    REQUIRE(b.restore(snap.data(), snap.size()));
    for (int t = 0; t < 30; ++t) {
        a.step();
        b.step();
        REQUIRE(a.stateHash() == b.stateHash());
    }
    CHECK(a.stats().contacts == contacts);
    CHECK(a.stats().islands == islands);
    CHECK(a.state(moved)->position.y == doctest::Approx(a.state(q)->position.y + 1.0).epsilon(1e-3));
    CHECK(std::fabs(a.state(moved)->velocity.y) < 1e-6);
}

TEST_CASE("bodies with other shape counts in the place of destroyed ones get their own broadphase boxes") {
    // The step keeps each body's first broadphase proxy from the shape counts it last saw. Destroying a one-shape
    // body moves the last body (three shapes) into its dense place and a two-shape body takes the next one, with
    // the body count unchanged: every box must be placed anew, exactly as in a world restored from a snapshot of
    // that moment (which lays out the proxies from nothing).
    World2 a;
    BodyDef2 g;
    g.type = BodyType::staticBody;
    a.createBody(g, {groundShape()});
    auto bodyAt = [&](double x, double y, int shapes) {
        BodyDef2 def;
        def.position = {x, y};
        std::vector<Shape2> parts;
        for (int k = 0; k < shapes; ++k) {
            Shape2 part;
            part.type = ShapeType::polygon;
            REQUIRE(makeBox(0.25, 0.25, {0.5 * k, 0.0}, 0.0, &part.polygon).empty());
            part.density = 1.0;
            part.friction = 0.6;
            parts.push_back(part);
        }
        return a.createBody(def, parts);
    };
    const BodyId single = bodyAt(0.0, 0.25, 1);
    bodyAt(3.0, 0.25, 2);
    const BodyId three = bodyAt(6.0, 0.25, 3);
    for (int t = 0; t < 30; ++t) a.step();
    REQUIRE(a.destroyBody(single));
    const BodyId two = bodyAt(-0.25, 1.5, 2);  // lands where the single box was
    const std::vector<std::uint8_t> snap = a.snapshot();
    World2 b;
    REQUIRE(b.restore(snap.data(), snap.size()));
    for (int t = 0; t < 60; ++t) {
        a.step();
        b.step();
        REQUIRE(a.stateHash() == b.stateHash());
    }
    CHECK(a.state(two)->position.y == doctest::Approx(0.25).epsilon(1e-2));  // it landed on the ground
    CHECK(a.state(three)->position.y == doctest::Approx(0.25).epsilon(1e-2));
}

TEST_CASE("a destroyed body's warm-start entries are not inherited by the next body in its slot") {
    World2 world;
    const BodyId box = addGroundAndBox(world, 0.5);
    for (int i = 0; i < 10; ++i) world.step();
    REQUIRE(world.stats().warmStartedIslands == 1);
    REQUIRE(world.destroyBody(box));
    BodyDef2 def;
    def.position = {0.0, 0.5};
    const BodyId again = world.createBody(def, {boxShape(0.5, 0.5)});
    REQUIRE(again.index1 == box.index1);  // LIFO reuse of the slot
    world.step();
    CHECK(world.stats().contacts > 0);
    CHECK(world.stats().warmStartedIslands == 0);
}

}  // TEST_SUITE
