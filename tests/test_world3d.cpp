// tests/test_world3d.cpp — the 3D world step against closed forms: free fall, a cube landing flat on 4 corners
// (v+ = e v, no spin), a tilted cube landing on one corner (single-point impulse), sphere restitution, boxes on a
// ramp (rest when mu > tan(theta), slide otherwise), a 3D Newton's cradle, stacking, bad input, determinism.
#include "test_support.h"

#include "make_scenes3d.h"
#include "resolver3d.h"
#include "scene_json3d.h"
#include "step_budget.h"
#include "world3d.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace unison;

namespace {

Shape3 boxShape(const Vec3& h, double friction = 0.6, double restitution = 0.0) {
    Shape3 s;
    REQUIRE(makeBox(h, Vec3::Zero(), &s).empty());
    s.friction = friction;
    s.restitution = restitution;
    return s;
}

Shape3 ballShape(double r, double friction = 0.6, double restitution = 0.0) {
    Shape3 s;
    REQUIRE(makeSphere(Vec3::Zero(), r, &s).empty());
    s.friction = friction;
    s.restitution = restitution;
    return s;
}

Shape3 groundPlane(double friction = 0.6, double restitution = 0.0) {
    Shape3 s;
    REQUIRE(makePlane(Vec3(0, 1, 0), 0.0, &s).empty());
    s.friction = friction;
    s.restitution = restitution;
    return s;
}

// A closed box mesh (12 triangles, counter-clockwise from outside) spanning [lo, hi].
Shape3 boxMesh(const Vec3& lo, const Vec3& hi) {
    std::vector<Vec3> v;
    for (int i = 0; i < 8; ++i) v.push_back(Vec3((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z()));
    const std::vector<std::array<int, 3>> t{{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                            {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    Shape3 s;
    REQUIRE(makeMesh(v, t, &s).empty());
    return s;
}

BodyId addStatic(World3& w, const Shape3& s, const Vec3& p = Vec3::Zero(), const Quat& q = Quat{}) {
    BodyDef3 d;
    d.type = BodyType::staticBody;
    d.position = p;
    d.orientation = q;
    return w.createBody(d, {s});
}

BodyId addDynamic(World3& w, const Shape3& s, const Vec3& p, const Vec3& v = Vec3::Zero(), const Quat& q = Quat{}) {
    BodyDef3 d;
    d.position = p;
    d.linearVelocity = v;
    d.orientation = q;
    const BodyId id = w.createBody(d, {s});
    REQUIRE_FALSE(id.isNull());
    return id;
}

}  // namespace

TEST_SUITE("world3d") {

TEST_CASE("free fall follows semi-implicit Euler exactly") {
    World3 world;
    const BodyId id = addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 10, 0));
    const double dt = 1.0 / 60.0;
    double v = 0.0, y = 10.0;
    for (int i = 0; i < 30; ++i) {
        world.step();
        v += dt * -10.0;
        y += dt * v;
    }
    CHECK(world.state(id)->velocity.y() == doctest::Approx(v).epsilon(1e-14));
    CHECK(world.state(id)->position.y() == doctest::Approx(y).epsilon(1e-14));
}

TEST_CASE("cube landing flat on 4 corners: v+ = e v and no spin (on a plane and on a static box)") {
    for (int ground = 0; ground < 2; ++ground) {
        CAPTURE(ground);
        WorldDef3 def;
        def.gravity = Vec3::Zero();
        World3 world(def);
        if (ground == 0) addStatic(world, groundPlane(0.6, 0.5));
        else addStatic(world, boxShape(Vec3(5, 1, 5), 0.6, 0.5), Vec3(0, -1, 0));
        // 1 cm above the ground at 3 m/s: the speculative contacts close within the step and bounce.
        const BodyId id = addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5), 0.6, 0.5), Vec3(0, 0.51, 0), Vec3(0, -3, 0));
        world.step();
        CHECK(world.stats().contacts == 4);
        CHECK(world.stats().failedIslands == 0);
        const BodyState3& s = *world.state(id);
        CHECK(s.velocity.y() == doctest::Approx(1.5).epsilon(1e-9));
        CHECK(std::fabs(s.velocity.x()) < 1e-9);
        CHECK(std::fabs(s.velocity.z()) < 1e-9);
        CHECK(s.angularVelocity.norm() < 1e-9);
    }
}

TEST_CASE("tilted cube landing on one corner: the single-point closed form") {
    WorldDef3 def;
    def.gravity = Vec3::Zero();
    World3 world(def);
    addStatic(world, groundPlane(0.0, 0.7));
    const Shape3 cube = boxShape(Vec3(0.5, 0.5, 0.5), 0.0, 0.7);
    const Quat q = multiply(axisAngle(Vec3(1, 0, 0), 0.3), axisAngle(Vec3(0, 0, 1), 0.4));
    const Mat3 r = toMatrix(q);
    Vec3 low = Vec3::Zero();
    double lowY = 1e9;
    for (const Vec3& v : cube.poly->vertices) {
        const Vec3 w = mul(r, v);
        if (w.y() < lowY) {
            lowY = w.y();
            low = w;
        }
    }
    const Vec3 c(0.0, -lowY + 0.005, 0.0);
    const Vec3 v0(0.4, -3.0, -0.2);
    const BodyId id = addDynamic(world, cube, c, v0, q);
    world.step();
    REQUIRE(world.stats().contacts == 1);
    // f = -(1 + e) v_rel / (1/m + (r x n) . I^-1 (r x n)), with r from the centre to the corner (frictionless).
    const double m = 1.0, e = 0.7;
    const Mat3 invI = r * (Mat3::Identity() * 6.0) * r.transpose();  // I = m a^2 / 6 = 1/6 for a unit cube
    const Vec3 n(0, 1, 0);
    const Vec3 rc = Dim3::sub(world.contacts()[0].point, c);
    const Vec3 rxn = rc.cross(n);
    const double f = -(1.0 + e) * v0.dot(n) / (1.0 / m + rxn.dot(invI * rxn));
    const BodyState3& s = *world.state(id);
    CHECK((s.velocity - (v0 + f / m * n)).norm() < 1e-9);
    CHECK((s.angularVelocity - invI * (rc.cross(f * n))).norm() < 1e-9);
    CHECK((world.contacts()[0].point - (c + low)).norm() < 0.01);
    CHECK(world.contacts()[0].normalImpulse == doctest::Approx(f).epsilon(1e-9));
}

TEST_CASE("sphere restitution: the rebound apex is e^2 h within 3 % (the 2D restitution row's tolerance)") {
    // Spheres of radius 0.5 dropped from y = 5 (fall height h = 4.5) onto a plane with e = k/6, as the 2D
    // restitution row. The world bounces a contact at its time of impact inside the step (core/world_step.h), so
    // what remains is the semi-implicit Euler discretisation of the two flights. Before 3D bounced at the time of
    // impact, the apex was up to (1 + e) v dt high (+3.7 % at e = 1, +53 % at e = 1/6). e = 0 must not bounce.
    const double h = 4.5, r = 0.5;
    for (int k = 0; k <= 6; ++k) {
        const double e = k / 6.0;
        CAPTURE(e);
        World3 world;
        addStatic(world, groundPlane(0.6, e));
        const BodyId id = addDynamic(world, ballShape(r, 0.6, e), Vec3(0, r + h, 0));
        double prevVy = 0.0, apex = -1.0;
        int bounces = 0;
        for (int i = 0; i < 300; ++i) {
            world.step();
            const BodyState3& s = *world.state(id);
            if (prevVy < 0.0 && s.velocity.y() > 0.0) ++bounces;
            if (bounces == 1 && prevVy > 0.0 && s.velocity.y() <= 0.0 && apex < 0.0) apex = s.position.y();
            prevVy = s.velocity.y();
            CHECK(s.angularVelocity.norm() < 1e-12);
        }
        if (k == 0) {
            CHECK(bounces == 0);
            CHECK(world.state(id)->position.y() == doctest::Approx(r).epsilon(0.01));
        } else {
            const double rise = apex - r;
            MESSAGE("e = " << e << ": apex " << rise << " m, e^2 h = " << e * e * h << " m ("
                           << 100.0 * (rise - e * e * h) / (e * e * h) << " %)");
            CHECK(std::fabs(rise - e * e * h) <= 0.03 * e * e * h);
        }
    }
}

// Energy (J) of a body of the world: kinetic (linear and angular) plus potential in g = 10 m/s^2 along -y.
double energy(const World3& world, BodyId id) {
    const BodyState3& s = *world.state(id);
    const BodyInfo3& info = *world.info(id);
    const Mat3 r = toMatrix(s.rotation);
    const Vec3 wb = r.transpose() * s.angularVelocity;  // body axes
    return 0.5 * info.mass * s.velocity.squaredNorm() + 0.5 * wb.dot(info.inertia * wb) +
           10.0 * info.mass * s.center.y();
}

TEST_CASE("e = 1: a cube landing flat and a sphere keep their energy from bounce to bounce") {
    // As the 2D test of a box with e = 1: a 1 m cube (mass 1) dropped flat from y = 5 onto a plane bounces on its 4
    // corners together, and a sphere of radius 0.5 (mass pi/6) from y = 5. The energy at every apex must stay
    // within 1 % of the energy they started with (the 1 % covers the semi-implicit Euler energy of a step-end
    // sample, about m g^2 dt^2 n / 2), so it does not grow from bounce to bounce.
    for (int shape = 0; shape < 2; ++shape) {
        CAPTURE(shape);
        World3 world;
        addStatic(world, groundPlane(0.6, 1.0));
        const BodyId id = shape == 0 ? addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5), 0.6, 1.0), Vec3(0, 5, 0))
                                     : addDynamic(world, ballShape(0.5, 0.6, 1.0), Vec3(0, 5, 0));
        const double e0 = energy(world, id);
        int apexes = 0;
        double prevVy = 0.0, worst = 0.0;
        for (int i = 0; i < 600; ++i) {
            world.step();
            const BodyState3& s = *world.state(id);
            if (prevVy > 0.0 && s.velocity.y() <= 0.0) {
                const double e = energy(world, id);
                CAPTURE(apexes);
                CHECK(std::fabs(e - e0) <= 0.01 * e0);
                worst = std::max(worst, std::fabs(e - e0) / e0);
                ++apexes;
            }
            prevVy = s.velocity.y();
        }
        const std::string name = shape == 0 ? "cube" : "sphere";
        MESSAGE(name << ": " << apexes << " apexes, largest energy change " << 100.0 * worst << " %");
        CHECK(apexes >= 5);  // one flight every 1.9 s
    }
}

TEST_CASE("box on a ramp: rests when mu > tan(theta), slides with g (sin - mu cos) otherwise") {
    const double theta = 0.35;  // rad; tan = 0.365
    const Quat q = axisAngle(Vec3(0, 0, 1), theta);
    const Mat3 r = toMatrix(q);
    const Vec3 up = mul(r, Vec3(0, 1, 0)), down = mul(r, Vec3(-1, 0, 0));
    for (double mu : {0.5, 0.15}) {
        CAPTURE(mu);
        WorldDef3 def;
        def.enableSleep = false;
        World3 world(def);
        addStatic(world, boxShape(Vec3(20, 0.5, 5), mu), Vec3::Zero(), q);
        const Vec3 start = Dim3::add(Dim3::scale(0.5 + 0.25 - 0.001, up), Dim3::scale(-8.0, down));
        const BodyId id = addDynamic(world, boxShape(Vec3(0.25, 0.25, 0.25), mu), start, Vec3::Zero(), q);
        const int steps = 90;
        for (int i = 0; i < 30; ++i) world.step();
        const Vec3 p30 = world.state(id)->center;
        const double v30 = world.state(id)->velocity.dot(down);
        for (int i = 30; i < steps; ++i) world.step();
        CHECK(world.stats().failedIslands == 0);
        const BodyState3& s = *world.state(id);
        const double slid = Dim3::sub(s.center, p30).dot(down);
        const double s_ = std::sin(theta), c_ = std::cos(theta);
        if (mu > std::tan(theta)) {
            CHECK(std::fabs(slid) < 1e-3);
            CHECK(s.velocity.norm() < 1e-3);
        } else {
            // The 4-direction pyramid is inscribed in the Coulomb cone: friction is mu f_n along a tangent axis and
            // mu f_n / sqrt 2 between two, so the acceleration lies between these bounds.
            // Semi-implicit Euler: N steps of constant a move v t + a dt^2 N (N + 1) / 2.
            const double nSteps = steps - 30, dt = 1.0 / 60.0, t = nSteps * dt;
            const double a = (slid - v30 * t) / (dt * dt * nSteps * (nSteps + 1.0) / 2.0);
            CHECK(a >= 10.0 * (s_ - mu * c_) * 0.99);
            CHECK(a <= 10.0 * (s_ - mu * c_ / std::sqrt(2.0)) * 1.01);
            CHECK(s.angularVelocity.norm() < 1e-6);
        }
        CHECK(Dim3::sub(s.center, start).dot(up) == doctest::Approx(0.0).scale(1.0).epsilon(0.01));
    }
}

TEST_CASE("3D Newton's cradle keeps the simultaneous closed form") {
    WorldDef3 def;
    def.gravity = Vec3::Zero();
    def.restitutionThreshold = 0.0;
    for (double e : {1.0, 0.5}) {
        CAPTURE(e);
        World3 world(def);
        const int n = 5;
        const double v = 2.0;
        std::vector<BodyId> ids;
        const Vec3 dir = Vec3(1, 2, 2).normalized();  // off-axis, so all three coordinates take part
        for (int i = 0; i < n; ++i)
            ids.push_back(addDynamic(world, ballShape(0.5, 0.0, e), Dim3::scale(double(i), dir), i == 0 ? Dim3::scale(v, dir) : Vec3::Zero()));
        world.step();
        const double first = v * (1.0 - (1.0 + e) * (n - 1.0) / n);
        CHECK((world.state(ids[0])->velocity - first * dir).norm() < 1e-9);
        for (int i = 1; i < n; ++i) CHECK((world.state(ids[std::size_t(i)])->velocity - v * (1.0 + e) / n * dir).norm() < 1e-9);
    }
}

TEST_CASE("a stack of 5 boxes settles, keeps its footprint and sleeps") {
    World3 world;
    addStatic(world, groundPlane());
    std::vector<BodyId> ids;
    for (int i = 0; i < 5; ++i) ids.push_back(addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0.5 + 1.0 * i + 0.001 * i, 0)));
    double maxResidual = 0.0;
    int failed = 0;
    for (int i = 0; i < 300; ++i) {
        world.step();
        maxResidual = std::max(maxResidual, world.stats().maxResidual);
        failed += world.stats().failedIslands;
    }
    CHECK(failed == 0);
    CHECK(maxResidual <= 1e-6);
    for (int i = 0; i < 5; ++i) {
        const BodyState3& s = *world.state(ids[std::size_t(i)]);
        CHECK(s.position.y() == doctest::Approx(0.5 + i).epsilon(0.01));
        CHECK(std::fabs(s.position.x()) < 1e-3);
        CHECK(std::fabs(s.position.z()) < 1e-3);
    }
    CHECK_FALSE(world.info(ids[4])->awake);
}

TEST_CASE("step statistics: how far the active set moved (basisChange) and stale guesses (discardedGuesses)") {
    // A cube resting on the ground: after settling, last step's basis is this step's answer (no change, no pivot).
    WorldDef3 def;
    def.enableSleep = false;
    World3 world(def);
    addStatic(world, groundPlane());
    const BodyId cube = addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0.5, 0));
    for (int i = 0; i < 60; ++i) world.step();
    for (int i = 0; i < 30; ++i) {
        world.step();
        CHECK(world.stats().warmStartedIslands == 1);
        CHECK(world.stats().basisChange == 0);
        CHECK(world.stats().discardedGuesses == 0);
        CHECK(world.stats().pivots == 0);
    }
    // Thrown sideways at 3 m/s: its 4 points go from sticking to sliding (the slacks and the tangent impulses
    // opposing the motion enter, the sticking ones leave), so the guess is wrong by several unknowns, and Lemke
    // needs at least half as many pivots as there are changes (one pivot moves at most two).
    REQUIRE(world.setVelocity(cube, Vec3(3, 0, 0), Vec3::Zero()));
    world.step();
    const StepStats3& st = world.stats();
    CHECK(st.basisChange >= 4);
    CHECK(st.discardedGuesses == 0);
    CHECK(2 * st.pivots >= st.basisChange);
    CHECK(world.state(cube)->velocity.x() < 3.0);

    // A friction solve that fails counts its pivots, and the island gets the bounded approximation instead (with
    // friction: a frictionless answer would leave the sliding speed as it is): with every LCP capped at 6 pivots, a
    // cube landing while sliding cannot finish its friction LCP (normals, tangents and slacks enter).
    {
        WorldDef3 capped;
        capped.enableSleep = false;
        capped.lcp.maxPivots = 6;
        World3 w(capped);
        addStatic(w, groundPlane());
        const BodyId cube = addDynamic(w, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0.51, 0), Vec3(2, -1, 0));
        int failedSteps = 0;
        for (int i = 0; i < 3; ++i) {
            const double vx = w.state(cube)->velocity.x();
            w.step();
            const StepStats3& c = w.stats();
            if (c.failedIslands == 0) continue;
            ++failedSteps;
            CHECK(c.approximateIslands == c.failedIslands);
            CHECK(c.unsolvedIslands == 0);
            CHECK(c.pivots > 0);
            CHECK(c.pivots <= capped.lcp.maxPivots);
            CHECK(c.maxResidual == 0.0);  // no exact answer was applied
            CHECK(c.maxApproximateResidual < 1e-3);
            CHECK(w.state(cube)->velocity.x() < vx - 1e-3);  // friction slowed the slide
            // and the ground held the fall to what closes the 1 cm gap within the step (free fall: -1.16 m/s)
            CHECK(w.state(cube)->velocity.y() > -0.61);
        }
        CHECK(failedSteps > 0);
    }

    // The residuals in the statistics are those of answers the step applied: with one pivot per LCP the friction
    // LCP of a cube landing on four corners cannot finish, and its failed solve's residual (1e17 and more on resting
    // piles) is not reported as if applied; the approximation's own residual is.
    {
        WorldDef3 capped;
        capped.enableSleep = false;
        capped.lcp.maxPivots = 1;
        World3 w(capped);
        addStatic(w, groundPlane());
        const BodyId cube = addDynamic(w, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0.49, 0), Vec3(0, -1, 0));
        w.step();
        const StepStats3& c = w.stats();
        CHECK(c.failedIslands == 1);
        CHECK(c.approximateIslands == 1);
        CHECK(c.unsolvedIslands == 0);
        CHECK(c.maxResidual == 0.0);
        CHECK(c.maxScaledResidual == 0.0);
        CHECK(c.maxApproximateResidual < 1.0);
        CHECK(w.state(cube)->velocity.y() > -0.1);
    }

    // A tumbling heap of 16 cubes: the bound holds on every step that kept its guess, and the heap's active set
    // does move.
    scenes::LoadedScene3 heap = scenes::loadScene3(scenes::boxPile3Scene(16, true, false), "heap");
    long change = 0;
    for (int i = 0; i < 120; ++i) {
        heap.world->step();
        const StepStats3& h = heap.world->stats();
        change += h.basisChange;
        if (h.discardedGuesses == 0) CHECK(2 * h.pivots >= h.basisChange);
    }
    CHECK(change > 0);
}

TEST_CASE("speculative band: resting neighbours 1.5 cm apart stay separate islands; fast approaches still close") {
    // Two stacks of two 0.5 m cubes, 1.5 cm apart: their facing sides are within speculativeDistance (2 cm) but
    // nothing moves them together, so the band keeps those points out of the LCP and the stacks are two islands.
    // Keeping every point (band = 1 m) joins them into one island without changing the answer: a speculative point
    // that stays open carries no impulse.
    auto run = [](double band, int* islands, std::vector<Vec3>* centres) {
        WorldDef3 def;
        def.enableSleep = false;
        def.speculativeBand = band;
        World3 world(def);
        addStatic(world, groundPlane());
        std::vector<BodyId> ids;
        for (int stack = 0; stack < 2; ++stack)
            for (int level = 0; level < 2; ++level)
                ids.push_back(addDynamic(world, boxShape(Vec3(0.25, 0.25, 0.25)), Vec3(0.515 * stack, 0.25 + 0.5 * level, 0)));
        for (int i = 0; i < 120; ++i) world.step();
        *islands = world.stats().islands;
        for (const BodyId id : ids) centres->push_back(world.state(id)->center);
        int across = 0;
        for (const ContactPoint3& c : world.contacts()) across += std::fabs(c.normal.x()) > 0.9 ? 1 : 0;
        return across;
    };
    int islandsBand = 0, islandsAll = 0;
    std::vector<Vec3> band, all;
    CHECK(run(0.01, &islandsBand, &band) == 0);
    CHECK(run(1.0, &islandsAll, &all) > 0);
    CHECK(islandsBand == 2);
    CHECK(islandsAll == 1);
    for (std::size_t i = 0; i < band.size(); ++i) CHECK((band[i] - all[i]).norm() < 1e-6);

    // A cube thrown at 10 m/s at a wall 10 cm away (reach 0.17 m per step): the gap closes within the step, so its
    // points are in the LCP from the start and it stops at the wall instead of sinking into it.
    World3 world;
    world.setGravity(Vec3::Zero());
    addStatic(world, boxShape(Vec3(0.1, 1.0, 1.0)), Vec3(0.6, 0, 0));  // face at x = 0.5
    const BodyId cube = addDynamic(world, boxShape(Vec3(0.25, 0.25, 0.25)), Vec3(0.15, 0, 0), Vec3(10, 0, 0));
    double deepest = 0.0;
    for (int i = 0; i < 30; ++i) {
        world.step();
        deepest = std::max(deepest, world.state(cube)->center.x() + 0.25 - 0.5);
    }
    CHECK(deepest <= world.def().linearSlop + 1e-9);
    CHECK(world.state(cube)->velocity.x() <= 1e-9);
}

TEST_CASE("tilted cubes dropped onto a heap: the corners they turn onto are in the LCP before they close") {
    // scenes::dropHeap3Scene: cubes turned 0.3 rad land on corners and edges of the layer below at 3-6 m/s and
    // turn onto their next corners within a step. Those corners must already be contact points: the narrowphase
    // adds a face's corners to an edge-edge point, keeps speculative corners where the touching points leave slots,
    // and reaches as far as the body's kinetic energy can carry a corner (WorldStep's speedBound). Without them
    // the deepest overlap was 41 mm (two layers, exact) and 94 mm (four layers, 2 ms budget).
    auto deepest = [](int cubes, double budgetMs) {
        WorldDef3 def;
        def.stepBudget = budgetMs > 0.0 ? workUnitsFromMilliseconds(budgetMs) : 0;
        scenes::LoadedScene3 heap = scenes::loadScene3(scenes::dropHeap3Scene(cubes, false), "drop heap", "", def);
        double pen = 0.0;
        for (int i = 0; i < 300; ++i) {
            heap.world->step();
            pen = std::max(pen, heap.world->stats().maxPenetration);
        }
        return pen;
    };
    CHECK(deepest(50, 0.0) <= 0.02);
    CHECK(deepest(100, 2.0) <= 0.02);
}

TEST_CASE("a 3D island whose friction solve fails gets the approximation, not the frictionless LCP") {
    // The 100-cube drop heap: from step 47 its one island of ~500 contacts slides as it lands, and neither the path
    // nor Lemke's capped run answers its friction LCP. A frictionless answer there let the heap spread (3.3 cm deep
    // overlaps, a failed island on most of 300 steps); the approximation keeps its friction (kFailedIslandSweeps3).
    scenes::LoadedScene3 heap = scenes::loadScene3(scenes::dropHeap3Scene(100, false), "drop heap");
    double pen = 0.0;
    int failed = 0;
    for (int i = 0; i < 56; ++i) {
        heap.world->step();
        const StepStats3& st = heap.world->stats();
        pen = std::max(pen, st.maxPenetration);
        failed += st.failedIslands;
        CHECK(st.approximateIslands == st.failedIslands);
        CHECK(st.unsolvedIslands == 0);
        if (st.failedIslands > 0) CHECK(st.maxApproximateResidual < 1.0);
    }
    CHECK(failed >= 5);
    CHECK(pen <= 0.02);
}

TEST_CASE("invalid bodies are rejected with a message and the world is unchanged") {
    World3 world;
    std::string error;
    BodyDef3 def;
    def.position = Vec3(NAN, 0, 0);
    CHECK(world.createBody(def, {boxShape(Vec3(0.5, 0.5, 0.5))}, &error).isNull());
    CHECK(error.find("finite") != std::string::npos);
    def.position = Vec3::Zero();
    CHECK(world.createBody(def, {}, &error).isNull());
    CHECK(error.find("mass") != std::string::npos);
    CHECK(world.createBody(def, {groundPlane()}, &error).isNull());
    CHECK(error.find("static") != std::string::npos);
    def.orientation = Quat{0, 0, 0, 0};
    CHECK(world.createBody(def, {boxShape(Vec3(0.5, 0.5, 0.5))}, &error).isNull());
    CHECK(world.bodyCount() == 0);
}

TEST_CASE("determinism: two runs give the same hash every step; the golden hash of a mixed pile") {
    auto build = [](World3& w) {
        addStatic(w, groundPlane(0.5, 0.2));
        for (int i = 0; i < 4; ++i) {
            const Quat q = axisAngle(Vec3(1, 1, double(i)), 0.3 * i);
            addDynamic(w, boxShape(Vec3(0.3, 0.2, 0.4), 0.5, 0.2), Vec3(0.2 * i, 0.5 + 0.8 * i, -0.1 * i), Vec3::Zero(), q);
            addDynamic(w, ballShape(0.25, 0.5, 0.3), Vec3(-0.5 + 0.3 * i, 1.0 + 0.7 * i, 0.4));
        }
    };
    World3 a, b;
    build(a);
    build(b);
    for (int i = 0; i < 240; ++i) {
        a.step();
        b.step();
        REQUIRE(a.stateHash() == b.stateHash());
    }
    CHECK(a.stats().failedIslands == 0);
    CHECK(a.stateHash() == 0x4f1d3e0080785947ull);  // gcc 12 -O2 x86-64 (state format of world3d_state.cpp); cross-build: the 3D golden scenes
}

TEST_CASE("sphere-tree meshes: a mesh cube lands like a box; the bunnies slide off both ramps and rest on the ground") {
    WorldDef3 def;
    def.gravity = Vec3::Zero();
    World3 world(def);
    addStatic(world, groundPlane(0.6, 0.5));
    Shape3 mesh = boxMesh(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
    mesh.restitution = 0.5;
    const BodyId id = addDynamic(world, mesh, Vec3(0, 0.51, 0), Vec3(0, -3, 0));
    world.step();
    CHECK(world.stats().contacts == 4);
    CHECK(world.state(id)->velocity.y() == doctest::Approx(1.5).epsilon(1e-9));
    CHECK(world.state(id)->angularVelocity.norm() < 1e-9);

    // The sample's scene: mixed friction sqrt(0.5 * 0.2) = 0.32 < tan(0.35) = 0.37, so the bunnies slide off.
    auto loaded = scenes::loadScene3(scenes::bunnies3Scene(std::string(UNISON_SOURCE_DIR) + "/scenes/bunny.obj", 0.05, 2), "bunnies");
    int failed = 0, maxContacts = 0;
    for (int i = 0; i < 600; ++i) {
        loaded.world->step();
        failed += loaded.world->stats().failedIslands;
        maxContacts = std::max(maxContacts, loaded.world->stats().contacts);
    }
    CHECK(failed == 0);
    CHECK(maxContacts <= 4 * 4);  // at most 4 points per touching pair (two bunnies, two ramps, ground, each other)
    for (std::size_t b = 3; b < 5; ++b) {
        const BodyState3& s = *loaded.world->state(loaded.bodies[b]);
        CHECK(s.center.y() < 0.3);  // on the ground (the bunny is about 0.48 m tall)
        CHECK(s.center.y() > 0.05);
        CHECK(s.velocity.norm() < 0.05);
    }
    CHECK(loaded.world->stateHash() == 0x9ce7c4fa03fd4f16ull);  // golden: the mesh path too (gcc 12 -O2; see above)
}

TEST_CASE("events: a bouncing ball begins touching the ground once and ends once; bad velocities are refused") {
    WorldDef3 def;
    def.restitutionThreshold = 0.0;
    World3 world(def);
    const BodyId ground = addStatic(world, groundPlane(0.6, 1.0));
    const BodyId ball = addDynamic(world, ballShape(0.5, 0.6, 1.0), Vec3(0, 0.49, 0), Vec3(0, -2, 0));
    world.step();
    REQUIRE(world.beginEvents().size() == 1);
    const ContactEvent3 ev = world.beginEvents()[0];
    CHECK(((ev.a == ground && ev.b == ball) || (ev.a == ball && ev.b == ground)));
    CHECK(world.endEvents().empty());
    int ends = 0;
    for (int i = 0; i < 20; ++i) {
        world.step();
        CHECK(world.beginEvents().empty());
        ends += int(world.endEvents().size());
    }
    CHECK(ends == 1);
    CHECK(world.state(ball)->position.y() > 0.5);  // still in the air after its first bounce
    const std::uint64_t before = world.stateHash();
    CHECK_FALSE(world.setVelocity(ball, Vec3(NAN, 0, 0), Vec3::Zero()));
    CHECK_FALSE(world.setVelocity(ground, Vec3(1, 0, 0), Vec3::Zero()));
    CHECK(world.stateHash() == before);
}

TEST_CASE("a destroyed body's warm-start entries are not inherited by the next body in its slot") {
    World3 world;
    addStatic(world, groundPlane());
    const BodyId box = addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0.5, 0));
    for (int i = 0; i < 10; ++i) world.step();
    REQUIRE(world.stats().warmStartedIslands == 1);
    REQUIRE(world.destroyBody(box));
    const BodyId again = addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0.5, 0));
    REQUIRE(again.index1 == box.index1);  // LIFO reuse of the slot
    world.step();
    CHECK(world.stats().contacts > 0);
    CHECK(world.stats().warmStartedIslands == 0);
}

TEST_CASE("static mesh ground of two big triangles per face: box corners and spheres meet its triangles") {
    // A closed slab mesh 20 x 1 x 20 m (12 triangles), top face at y = 0: no mesh vertex lies under the bodies.
    Shape3 slab = boxMesh(Vec3(-10, -1, -10), Vec3(10, 0, 10));
    slab.restitution = 0.5;
    {
        WorldDef3 def;
        def.gravity = Vec3::Zero();
        World3 world(def);
        addStatic(world, slab);
        const BodyId id = addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5), 0.6, 0.5), Vec3(0.3, 0.51, -0.2), Vec3(0, -3, 0));
        world.step();
        CHECK(world.stats().contacts == 4);
        CHECK(world.state(id)->velocity.y() == doctest::Approx(1.5).epsilon(1e-9));
        CHECK(world.state(id)->angularVelocity.norm() < 1e-9);
    }
    World3 world;
    addStatic(world, slab);
    const BodyId box = addDynamic(world, boxShape(Vec3(0.5, 0.5, 0.5)), Vec3(2, 1.0, 0));
    const BodyId ball = addDynamic(world, ballShape(0.4), Vec3(-2, 1.0, 1));
    for (int i = 0; i < 180; ++i) world.step();
    CHECK(world.stats().failedIslands == 0);
    CHECK(world.state(box)->position.y() == doctest::Approx(0.5).epsilon(0.01));
    CHECK(world.state(ball)->position.y() == doctest::Approx(0.4).epsilon(0.01));
    CHECK_FALSE(world.info(box)->awake);
}

}  // TEST_SUITE
