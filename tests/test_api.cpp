// tests/test_api.cpp — the public C++ API (unison/world2d.h, world3d.h, replay.h) and the C API (unison/unison.h)
// from C++: the same scene built through the public worlds, the C API and the engine's worlds gives the same state
// hash every step; bad arguments fail and change nothing (the hash and the snapshot bytes stay the same); snapshots
// and rollback states round-trip; queries and events come through; an unfit floating-point environment is refused;
// recordings verify. (tests/capi_test.c calls every C function from a C99 program.)
#include "test_support.h"

#include <unison/replay.h>
#include <unison/unison.h>
#include <unison/world2d.h>
#include <unison/world3d.h>

#include "scene_dir.h"
#include "scene_json.h"
#include "world2d.h"
#include "world3d.h"

#include <cmath>
#include <fstream>
#include <sstream>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

using namespace unison;

namespace {

const double kNan = std::nan("");

// A pile in 2D through the public API: ground segment, a box, a circle, a triangle, a rotated box.
World2D pile2(std::vector<BodyId>* ids = nullptr) {
    World2D w;
    BodyDef2D ground;
    ground.type = BodyType::staticBody;
    const BodyId g = w.createBody(ground, {ShapeDef2D::segment({-10, 0}, {10, 0}), ShapeDef2D::box(0.5, 2.0, {-6, 2})});
    REQUIRE(!g.isNull());
    const std::vector<ShapeDef2D> shapes{ShapeDef2D::box(0.5, 0.5), ShapeDef2D::circle({0.1, 0}, 0.4),
                                         ShapeDef2D::polygon({{-0.5, 0}, {0.5, 0}, {0, 0.7}}),
                                         ShapeDef2D::box(0.6, 0.3, {0, 0}, 0.3)};
    for (int i = 0; i < 4; ++i) {
        BodyDef2D d;
        d.position = {0.2 * i, 0.6 + 1.1 * i};
        d.angle = 0.1 * i;
        std::string error;
        const BodyId id = w.createBody(d, {shapes[std::size_t(i)]}, &error);
        REQUIRE_MESSAGE(!id.isNull(), error);
        if (ids) ids->push_back(id);
    }
    return w;
}

// The same pile through the engine's World2.
World2 enginePile2() {
    World2 w;
    auto shape = [](const ShapeDef2D& s) {
        Shape2 out;
        if (s.kind == ShapeKind2D::circle) {
            REQUIRE(makeCircle({s.center.x, s.center.y}, s.radius, &out.circle).empty());
            out.type = ShapeType::circle;
        } else if (s.kind == ShapeKind2D::box) {
            REQUIRE(makeBox(s.halfExtents.x, s.halfExtents.y, {s.center.x, s.center.y}, s.angle, &out.polygon).empty());
            out.type = ShapeType::polygon;
        } else if (s.kind == ShapeKind2D::polygon) {
            std::vector<Vec2> pts;
            for (Vec2D p : s.points) pts.push_back({p.x, p.y});
            REQUIRE(makePolygon(pts, &out.polygon).empty());
            out.type = ShapeType::polygon;
        } else {
            REQUIRE(makeSegment({s.points[0].x, s.points[0].y}, {s.points[1].x, s.points[1].y}, &out.segment).empty());
            out.type = ShapeType::segment;
        }
        return out;
    };
    BodyDef2 ground;
    ground.type = BodyType::staticBody;
    w.createBody(ground, {shape(ShapeDef2D::segment({-10, 0}, {10, 0})), shape(ShapeDef2D::box(0.5, 2.0, {-6, 2}))});
    const std::vector<ShapeDef2D> shapes{ShapeDef2D::box(0.5, 0.5), ShapeDef2D::circle({0.1, 0}, 0.4),
                                         ShapeDef2D::polygon({{-0.5, 0}, {0.5, 0}, {0, 0.7}}),
                                         ShapeDef2D::box(0.6, 0.3, {0, 0}, 0.3)};
    for (int i = 0; i < 4; ++i) {
        BodyDef2 d;
        d.position = {0.2 * i, 0.6 + 1.1 * i};
        d.angle = 0.1 * i;
        REQUIRE(!w.createBody(d, {shape(shapes[std::size_t(i)])}).isNull());
    }
    return w;
}

// The cube [-h, h]^3 as a closed mesh.
ShapeDef3D cubeMesh(double h) {
    std::vector<Vec3D> v;
    for (int i = 0; i < 8; ++i) v.push_back({(i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h});
    return ShapeDef3D::mesh(v, {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}});
}

World3D pile3(std::vector<BodyId>* ids = nullptr) {
    World3D w;
    BodyDef3D ground;
    ground.type = BodyType::staticBody;
    REQUIRE(!w.createBody(ground, {ShapeDef3D::plane({0, 1, 0}, 0.0)}).isNull());
    const std::vector<ShapeDef3D> shapes{
        ShapeDef3D::box({0.5, 0.5, 0.5}), ShapeDef3D::sphere({0, 0, 0}, 0.4),
        ShapeDef3D::hull({{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0, 0, 0.5}, {0, 0.8, 0}}), cubeMesh(0.3)};
    for (int i = 0; i < 4; ++i) {
        BodyDef3D d;
        d.position = {0.1 * i, 0.6 + 1.1 * i, -0.05 * i};
        d.orientation = {std::cos(0.05 * i), std::sin(0.05 * i), 0, 0};
        std::string error;
        const BodyId id = w.createBody(d, {shapes[std::size_t(i)]}, &error);
        REQUIRE_MESSAGE(!id.isNull(), error);
        if (ids) ids->push_back(id);
    }
    return w;
}

template <class World>
void checkUnchanged(const World& w, std::uint64_t hash, const std::vector<std::uint8_t>& snap) {
    CHECK(w.stateHash() == hash);
    CHECK(w.snapshot() == snap);
}

std::string readText(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

TEST_SUITE("api") {

TEST_CASE("2D: the public world steps the engine's world bit for bit; the C API too") {
    World2D pub = pile2();
    World2 engine = enginePile2();
    // The same through the C API.
    unisonWorldDef2 def = unisonDefaultWorldDef2();
    unisonWorldId cw;
    REQUIRE(unisonCreateWorld2(&def, &cw) == UNISON_OK);
    unisonBodyDef2 ground = unisonDefaultBodyDef2();
    ground.type = UNISON_BODY_STATIC;
    unisonShapeDef2 groundShapes[2] = {unisonMakeSegment2({-10, 0}, {10, 0}), unisonMakeBox2(0.5, 2.0)};
    groundShapes[1].center = {-6, 2};
    unisonBodyId cid;
    REQUIRE(unisonCreateBody2(cw, &ground, groundShapes, 2, &cid) == UNISON_OK);
    const unisonVec2 tri[3] = {{-0.5, 0}, {0.5, 0}, {0, 0.7}};
    unisonShapeDef2 shapes[4] = {unisonMakeBox2(0.5, 0.5), unisonMakeCircle2({0.1, 0}, 0.4), unisonMakePolygon2(tri, 3),
                                 unisonMakeBox2(0.6, 0.3)};
    shapes[3].angle = 0.3;
    for (int i = 0; i < 4; ++i) {
        unisonBodyDef2 d = unisonDefaultBodyDef2();
        d.position = {0.2 * i, 0.6 + 1.1 * i};
        d.angle = 0.1 * i;
        REQUIRE(unisonCreateBody2(cw, &d, &shapes[i], 1, &cid) == UNISON_OK);
    }
    for (int step = 0; step <= 120; ++step) {
        std::uint64_t ch = 0;
        REQUIRE(unisonGetStateHash(cw, &ch) == UNISON_OK);
        REQUIRE(pub.stateHash() == engine.stateHash());
        REQUIRE(ch == engine.stateHash());
        pub.step();
        engine.step();
        REQUIRE(unisonStep(cw) == UNISON_OK);
    }
    CHECK(pub.stepInfo().contacts == engine.stats().contacts);
    CHECK(pub.contacts().size() == engine.contacts().size());
    CHECK(unisonDestroyWorld(cw) == UNISON_OK);
}

TEST_CASE("3D: the public world, the C API and the engine agree; every shape kind") {
    World3D pub = pile3();
    unisonWorldDef3 def = unisonDefaultWorldDef3();
    unisonWorldId cw;
    REQUIRE(unisonCreateWorld3(&def, &cw) == UNISON_OK);
    unisonBodyDef3 ground = unisonDefaultBodyDef3();
    ground.type = UNISON_BODY_STATIC;
    const unisonShapeDef3 plane = unisonMakePlane3({0, 1, 0}, 0.0);
    unisonBodyId cid;
    REQUIRE(unisonCreateBody3(cw, &ground, &plane, 1, &cid) == UNISON_OK);
    const unisonVec3 hullPts[4] = {{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0, 0, 0.5}, {0, 0.8, 0}};
    unisonVec3 cube[8];
    for (int i = 0; i < 8; ++i) cube[i] = {(i & 1) ? 0.3 : -0.3, (i & 2) ? 0.3 : -0.3, (i & 4) ? 0.3 : -0.3};
    const int tris[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                          2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    const unisonShapeDef3 shapes[4] = {unisonMakeBox3({0.5, 0.5, 0.5}), unisonMakeSphere3({0, 0, 0}, 0.4),
                                       unisonMakeHull3(hullPts, 4), unisonMakeMesh3(cube, 8, tris, 12)};
    for (int i = 0; i < 4; ++i) {
        unisonBodyDef3 d = unisonDefaultBodyDef3();
        d.position = {0.1 * i, 0.6 + 1.1 * i, -0.05 * i};
        d.orientation = {std::cos(0.05 * i), std::sin(0.05 * i), 0, 0};
        REQUIRE(unisonCreateBody3(cw, &d, &shapes[i], 1, &cid) == UNISON_OK);
    }
    for (int step = 0; step <= 90; ++step) {
        std::uint64_t ch = 0;
        REQUIRE(unisonGetStateHash(cw, &ch) == UNISON_OK);
        REQUIRE(ch == pub.stateHash());
        pub.step();
        REQUIRE(unisonStep(cw) == UNISON_OK);
    }
    // The box rests on the plane: its centre at 0.5 m.
    BodyState3D s;
    REQUIRE(pub.getState(pub.bodyIds()[1], &s));
    CHECK(s.position.y == doctest::Approx(0.5).epsilon(0.01));
    CHECK(s.mass == doctest::Approx(1.0));
    CHECK(unisonDestroyWorld(cw) == UNISON_OK);
}

TEST_CASE("defaults of the public definitions are the engine's") {
    const WorldDef2D d2;
    const WorldDef2 e2;
    CHECK(d2.gravity.x == e2.gravity.x);
    CHECK(d2.gravity.y == e2.gravity.y);
    CHECK(d2.hz == e2.hz);
    CHECK(d2.enableSleep == e2.enableSleep);
    const WorldDef3D d3;
    const WorldDef3 e3;
    CHECK(d3.gravity.y == e3.gravity.y());
    CHECK(d3.hz == e3.hz);
    CHECK(d3.enableSleep == e3.enableSleep);
    const ShapeDef2D s2;
    const Shape2 es2;
    CHECK(s2.density == es2.density);
    CHECK(s2.friction == es2.friction);
    CHECK(s2.restitution == es2.restitution);
    const ShapeDef3D s3;
    const Shape3 es3;
    CHECK(s3.density == es3.density);
    CHECK(s3.friction == es3.friction);
    CHECK(s3.restitution == es3.restitution);
}

TEST_CASE("bad arguments fail with a message and change nothing") {
    std::vector<BodyId> ids;
    World2D w = pile2(&ids);
    for (int i = 0; i < 10; ++i) w.step();
    const std::uint64_t hash = w.stateHash();
    const std::vector<std::uint8_t> snap = w.snapshot();
    std::string error;
    BodyDef2D bad;
    bad.position = {kNan, 0};
    CHECK(w.createBody(bad, {ShapeDef2D::circle({}, 1)}, &error).isNull());
    CHECK(error.find("finite") != std::string::npos);
    error.clear();
    CHECK(w.createBody(BodyDef2D{}, {ShapeDef2D::circle({}, -1)}, &error).isNull());
    CHECK(error.find("shape 0") != std::string::npos);
    CHECK(w.createBody(BodyDef2D{}, {ShapeDef2D::polygon({{0, 0}, {1, 0}})}, &error).isNull());
    ShapeDef2D threePointSegment = ShapeDef2D::segment({0, 0}, {1, 0});
    threePointSegment.points.push_back({2, 0});
    CHECK(w.createBody(BodyDef2D{}, {threePointSegment}, &error).isNull());
    ShapeDef2D nanFriction = ShapeDef2D::circle({}, 1);
    nanFriction.friction = kNan;
    CHECK(w.createBody(BodyDef2D{}, {nanFriction}, &error).isNull());
    CHECK(w.createBody(BodyDef2D{}, {ShapeDef2D::segment({0, 0}, {1, 0})}, &error).isNull());  // no mass
    CHECK_FALSE(w.setVelocity(ids[0], {kNan, 0}, 0));
    CHECK_FALSE(w.applyImpulse(ids[0], {1, 0}, {0, kNan}));
    CHECK_FALSE(w.setGravity({0, kNan}));
    const BodyId stale = ids[1];
    REQUIRE(w.destroyBody(stale));
    const std::uint64_t afterDestroy = w.stateHash();
    const std::vector<std::uint8_t> snapAfter = w.snapshot();
    CHECK_FALSE(w.destroyBody(stale));
    CHECK_FALSE(w.setVelocity(stale, {1, 0}, 0));
    CHECK_FALSE(w.isValid(stale));
    BodyState2D s;
    s.mass = -1.0;
    CHECK_FALSE(w.getState(stale, &s));
    CHECK(s.mass == -1.0);
    std::vector<std::uint8_t> garbage = snap;
    garbage[garbage.size() / 2] ^= 0x10;
    CHECK_FALSE(w.restore(garbage.data(), garbage.size(), &error));
    CHECK_FALSE(w.restore(nullptr, 10, &error));
    CHECK_FALSE(w.restoreCompact(garbage.data(), 3, &error));
    CHECK(w.overlapShape(ShapeDef2D::circle({}, 0), {0, 0}, 0, &error).empty());
    CHECK(w.overlapShape(ShapeDef2D::circle({}, 1), {kNan, 0}, 0, &error).empty());
    CHECK(w.overlapAabb({1, 1}, {0, 0}).empty());
    checkUnchanged(w, afterDestroy, snapAfter);
    CHECK(afterDestroy != hash);
    auto def2 = [](Vec2D g, double hz) {
        WorldDef2D d;
        d.gravity = g;
        d.hz = hz;
        return d;
    };
    CHECK_THROWS_AS(World2D(def2({0, -10}, 0.0)), Error);
    CHECK_THROWS_AS(World2D(def2({0, -10}, 1e-300)), Error);  // dt beyond the input policy
    CHECK_THROWS_AS(World2D(def2({2e4, -10}, 60.0)), Error);
    WorldDef3D def3;
    def3.gravity = {0, kNan, 0};
    CHECK_THROWS_AS((World3D(def3)), Error);
    WorldDef2D badTasks;
    badTasks.tasks.workerCount = 0;
    CHECK_THROWS_AS((World2D(badTasks)), Error);

    World3D w3 = pile3();
    const std::uint64_t h3 = w3.stateHash();
    const std::vector<std::uint8_t> s3 = w3.snapshot();
    BodyDef3D dyn;
    CHECK(w3.createBody(dyn, {ShapeDef3D::plane({0, 1, 0}, 0)}, &error).isNull());  // planes are static only
    CHECK(w3.createBody(dyn, {ShapeDef3D::hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}})}, &error).isNull());
    ShapeDef3D open = cubeMesh(1.0);
    open.triangles.pop_back();
    CHECK(w3.createBody(dyn, {open}, &error).isNull());
    dyn.orientation = {0, 0, 0, 0};
    CHECK(w3.createBody(dyn, {ShapeDef3D::sphere({}, 1)}, &error).isNull());
    CHECK(w3.overlapShape(ShapeDef3D::plane({0, 1, 0}, 0), {}, {}, &error).empty());
    CHECK(error.find("sphere, box or hull") != std::string::npos);
    CHECK(w3.overlapShape(ShapeDef3D::sphere({}, 1), {}, {0, 0, 0, 0}, &error).empty());
    CHECK_FALSE(w3.rayCastClosest({0, 0, 0}, {0, 0, 0}, nullptr));
    checkUnchanged(w3, h3, s3);
}

namespace {

// A job system of the embedding server, as the C API sees it: runs every task at once on the calling thread, in
// ranges of minRange items, counting the tasks.
struct CountingJobs {
    int tasks = 0;
    static void* enqueue(unisonTaskCallback* task, int itemCount, int minRange, void* taskContext, void* user) {
        ++static_cast<CountingJobs*>(user)->tasks;
        const int range = minRange < 1 ? 1 : minRange;
        for (int begin = 0; begin < itemCount; begin += range)
            task(begin, std::min(itemCount, begin + range), 0, taskContext);
        return nullptr;
    }
    static void finish(void*, void*) {}
};

// A 12-row pyramid of boxes on a segment, through the C API (78 boxes in one island).
unisonWorldId cPyramid(const unisonWorldDef2& def) {
    unisonWorldId w;
    REQUIRE(unisonCreateWorld2(&def, &w) == UNISON_OK);
    unisonBodyDef2 ground = unisonDefaultBodyDef2();
    ground.type = UNISON_BODY_STATIC;
    const unisonShapeDef2 segment = unisonMakeSegment2({-20, 0}, {20, 0});
    unisonBodyId id;
    REQUIRE(unisonCreateBody2(w, &ground, &segment, 1, &id) == UNISON_OK);
    const unisonShapeDef2 box = unisonMakeBox2(0.5, 0.5);
    for (int row = 0; row < 12; ++row) {
        for (int i = 0; i < 12 - row; ++i) {
            unisonBodyDef2 d = unisonDefaultBodyDef2();
            d.position = {-0.5 * (11 - row) + 1.0 * i, 0.5 + 1.0 * row};
            REQUIRE(unisonCreateBody2(w, &d, &box, 1, &id) == UNISON_OK);
        }
    }
    return w;
}

std::uint64_t cHash(unisonWorldId w) {
    std::uint64_t h = 0;
    REQUIRE(unisonGetStateHash(w, &h) == UNISON_OK);
    return h;
}

}  // namespace

TEST_CASE("budgets and threads through the C++ and C APIs: the same bits for any thread count or job system") {
    // A tight budget: most islands get the bounded approximation, the same on every world below.
    const std::uint64_t budget = workUnitsFromMilliseconds(0.05);
    CHECK(budget == unisonWorkUnitsFromMilliseconds(0.05));
    CHECK(workUnitsFromMilliseconds(-1.0) == 0);
    unisonWorldDef2 def = unisonDefaultWorldDef2();
    CHECK(def.stepBudget == 0);
    CHECK(def.tasks.workerCount == 1);
    def.stepBudget = budget;
    const unisonWorldId one = cPyramid(def);
    def.tasks.workerCount = 2;  // the built-in pool
    const unisonWorldId pool = cPyramid(def);
    CountingJobs jobs;
    def.tasks = {3, &CountingJobs::enqueue, &CountingJobs::finish, &jobs};
    const unisonWorldId embedded = cPyramid(def);
    def = unisonDefaultWorldDef2();  // unbudgeted, stepped with a per-call budget instead
    const unisonWorldId perCall = cPyramid(def);

    int approximate = 0;
    for (int step = 0; step < 60; ++step) {
        REQUIRE(unisonStep(one) == UNISON_OK);
        REQUIRE(unisonStep(pool) == UNISON_OK);
        REQUIRE(unisonStep(embedded) == UNISON_OK);
        REQUIRE(unisonStepWithBudget(perCall, budget) == UNISON_OK);
        const std::uint64_t h = cHash(one);
        REQUIRE(cHash(pool) == h);
        REQUIRE(cHash(embedded) == h);
        unisonStepInfo info;
        REQUIRE(unisonGetStepInfo(one, &info) == UNISON_OK);
        CHECK(info.budget == budget);
        CHECK(info.work <= std::max(info.budget, info.minimumWork) + info.overrun);
        approximate += info.approximateIslands;
        unisonStepInfo perCallInfo;
        REQUIRE(unisonGetStepInfo(perCall, &perCallInfo) == UNISON_OK);
        CHECK(perCallInfo.work == info.work);
        CHECK(perCallInfo.approximateIslands == info.approximateIslands);
    }
    CHECK(approximate > 0);
    CHECK(jobs.tasks > 0);
    // The per-call budget is not state: the world's own budget is part of the hash, so perCall differs from one.
    std::uint64_t stored = 1;
    REQUIRE(unisonGetStepBudget(perCall, &stored) == UNISON_OK);
    CHECK(stored == 0);
    CHECK(cHash(perCall) != cHash(one));
    REQUIRE(unisonSetStepBudget(perCall, budget) == UNISON_OK);
    CHECK(cHash(perCall) == cHash(one));

    // Bad thread settings are refused and change nothing.
    const std::uint64_t before = cHash(one);
    unisonTaskSystem bad = {0, nullptr, nullptr, nullptr};
    CHECK(unisonSetTaskSystem(one, &bad) == UNISON_ERROR_INVALID_ARGUMENT);
    bad = {2, &CountingJobs::enqueue, nullptr, &jobs};
    CHECK(unisonSetTaskSystem(one, &bad) == UNISON_ERROR_INVALID_ARGUMENT);
    CHECK(unisonSetTaskSystem(one, nullptr) == UNISON_ERROR_NULL_POINTER);
    unisonWorldDef2 badDef = unisonDefaultWorldDef2();
    badDef.tasks.workerCount = -1;
    unisonWorldId none;
    CHECK(unisonCreateWorld2(&badDef, &none) == UNISON_ERROR_INVALID_ARGUMENT);
    CHECK(cHash(one) == before);
    const unisonTaskSystem four = {4, nullptr, nullptr, nullptr};
    REQUIRE(unisonSetTaskSystem(one, &four) == UNISON_OK);
    REQUIRE(unisonStep(one) == UNISON_OK);
    REQUIRE(unisonStep(pool) == UNISON_OK);
    CHECK(cHash(one) == cHash(pool));
    size_t size = 0;
    REQUIRE(unisonGetWorldFault(one, nullptr, 0, &size) == UNISON_OK);
    CHECK(size == 1);  // "" and its NUL: no fault
    for (unisonWorldId w : {one, pool, embedded, perCall}) CHECK(unisonDestroyWorld(w) == UNISON_OK);

    // The C++ API: the same settings, the same answers as the engine's world.
    std::vector<BodyId> ids;
    World2D pub = pile2(&ids);
    World2 engine = enginePile2();
    pub.setStepBudget(budget);
    engine.setStepBudget(budget);
    REQUIRE(pub.setTaskSystem(TaskSystem{2}));
    CHECK_FALSE(pub.setTaskSystem(TaskSystem{0}));
    CHECK(pub.stepBudget() == budget);
    for (int step = 0; step < 30; ++step) {
        pub.step();
        engine.step();
        REQUIRE(pub.stateHash() == engine.stateHash());
    }
    CHECK(pub.stepInfo().budget == budget);
    CHECK(pub.stepInfo().exactIslands + pub.stepInfo().approximateIslands >= 1);
    CHECK(pub.fault().empty());
}

TEST_CASE("snapshots and rollback states continue bit-identically") {
    World2D w = pile2();
    for (int i = 0; i < 30; ++i) w.step();
    const std::vector<std::uint8_t> snap = w.snapshot();
    std::vector<std::uint8_t> compact;
    w.saveCompact(compact);
    CHECK(compact.size() < snap.size());
    std::vector<std::uint64_t> straight;
    for (int i = 0; i < 30; ++i) {
        w.step();
        straight.push_back(w.stateHash());
    }
    REQUIRE(w.restoreCompact(compact.data(), compact.size()));
    for (int i = 0; i < 30; ++i) {
        w.step();
        CHECK(w.stateHash() == straight[std::size_t(i)]);
    }
    World2D other;
    REQUIRE(other.restore(snap.data(), snap.size()));
    CHECK(other.stepCount() == 30);
    for (int i = 0; i < 30; ++i) other.step();
    CHECK(other.stateHash() == straight.back());
    // A 3D snapshot does not fit a 2D world.
    std::string error;
    const std::vector<std::uint8_t> snap3 = pile3().snapshot();
    CHECK_FALSE(other.restore(snap3.data(), snap3.size(), &error));
    CHECK_FALSE(error.empty());
}

TEST_CASE("events, contacts, state and queries come through") {
    std::vector<BodyId> ids;
    World2D w = pile2(&ids);
    bool began = false;
    for (int i = 0; i < 60; ++i) {
        w.step();
        for (const TouchEvent& e : w.beginTouchEvents()) began = began || e.a == ids[0] || e.b == ids[0];
    }
    CHECK(began);
    CHECK_FALSE(w.contacts().empty());
    CHECK(w.stepInfo().contacts == int(w.contacts().size()));
    BodyState2D s;
    REQUIRE(w.getState(ids[0], &s));
    CHECK(s.position.y == doctest::Approx(0.5).epsilon(0.01));  // the box rests on the ground segment
    CHECK(s.mass == doctest::Approx(1.0));
    RayHit2D hit;
    REQUIRE(w.rayCastClosest({s.position.x, 10}, {0, -20}, &hit));  // the pile's top: the box or what rests on it
    CHECK(hit.point.y >= s.position.y + 0.5 - 1e-6);
    CHECK(hit.normal.y > 0.0);
    CHECK(w.rayCastAll({-20, 0.25}, {40, 0}).size() >= 2);
    CHECK_FALSE(w.overlapAabb({-1, 0}, {1, 1}).empty());
    CHECK_FALSE(w.overlapShape(ShapeDef2D::circle({}, 0.2), {s.position.x, s.position.y}, 0).empty());
    CHECK(w.setGravity({0, -5}));
    CHECK(w.gravity().y == -5);
    CHECK(w.setVelocity(ids[0], {1, 0}, 0));
    CHECK(w.applyImpulse(ids[0], {0, 1}, {s.position.x, s.position.y}));
    REQUIRE(w.getState(ids[0], &s));
    CHECK(s.linearVelocity.y == doctest::Approx(1.0));
    CHECK(s.awake);
}

TEST_CASE("a world refuses an unfit floating-point environment") {
#if defined(__SSE2__)
    const unsigned int saved = _mm_getcsr();
    _mm_setcsr(saved | 0x8040u);  // flush-to-zero and denormals-are-zero
    std::string message;
    try {
        World2D w;
    } catch (const Error& e) {
        message = e.what();
    }
    unisonWorldDef3 def = unisonDefaultWorldDef3();
    unisonWorldId id{};
    const unisonError code = unisonCreateWorld3(&def, &id);
    _mm_setcsr(saved);
    CHECK(message.find("floating-point") != std::string::npos);
    CHECK(code == UNISON_ERROR_FLOATING_POINT);
    CHECK(std::string(unisonLastErrorMessage()).find("flushed to zero") != std::string::npos);
    CHECK_FALSE(unisonWorldIsValid(id));
#endif
    CHECK_NOTHROW(World2D{});
}

TEST_CASE("recordings: record, verify, hashes, and bad bytes") {
    const std::string scene = readText(scenes::sceneDir() + "/cradle.json");
    const std::string inputs = R"({"inputs": [{"tick": 3, "type": "apply_impulse", "body": 1, "impulse": [0.5, 0]}]})";
    std::string error;
    const std::vector<std::uint8_t> rec = recordMatch(scene, inputs, 40, 10, &error);
    REQUIRE_MESSAGE(!rec.empty(), error);
    VerifyResult result;
    REQUIRE(verifyRecording(rec.data(), rec.size(), &result, &error));
    CHECK(result.match);
    CHECK(result.ticks == 40);
    CHECK(result.summary == "all 40 ticks match");
    std::vector<std::uint64_t> hashes;
    REQUIRE(recordingHashes(rec.data(), rec.size(), &hashes));
    CHECK(hashes.size() == 41);
    // The recording's hashes are those of the scene stepped by the engine with the same input.
    const auto loaded = scenes::loadScene2(nlohmann::json::parse(scene), "cradle");
    CHECK(loaded.world->stateHash() == hashes[0]);
    std::vector<std::uint8_t> bad = rec;
    bad[bad.size() / 2] ^= 1;
    CHECK_FALSE(verifyRecording(bad.data(), bad.size(), &result, &error));
    CHECK_FALSE(error.empty());
    CHECK(recordMatch("{", "", 10, 5, &error).empty());
    CHECK(recordMatch(scene, "", 10, 0, &error).empty());
    CHECK(recordMatch(scene, R"({"inputs": [{"tick": 1, "type": "nope"}]})", 10, 5, &error).empty());
}

TEST_CASE("a big resting pile reports its active-set answers through both APIs") {
    // Box2D v3's large-pyramid layout through the public API: 1 m boxes touching side by side and stacked with no
    // gap, base 20 (210 boxes, about 1100 contacts in one island from the first step, no warm start).
    World2D w;
    BodyDef2D ground;
    ground.type = BodyType::staticBody;
    REQUIRE(!w.createBody(ground, {ShapeDef2D::box(40.0, 1.0, {0.0, -1.0})}).isNull());
    for (int row = 0; row < 20; ++row) {
        for (int i = 0; i < 20 - row; ++i) {
            BodyDef2D d;
            d.position = {-9.5 + 0.5 * row + i, 0.5 + row};
            REQUIRE(!w.createBody(d, {ShapeDef2D::box(0.5, 0.5)}).isNull());
        }
    }
    w.step();
    const StepInfo info = w.stepInfo();
    CHECK(info.contacts >= 512);
    CHECK(info.exactIslands == 1);
    CHECK(info.activeSetIslands == 1);
    CHECK(info.pivots == 0);
    CHECK(info.failedIslands == 0);
}

}  // TEST_SUITE
