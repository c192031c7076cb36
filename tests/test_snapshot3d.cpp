// tests/test_snapshot3d.cpp — snapshots, restore, recordings and verify for the 3D world:
// bit-identical continuation after a restore (meshes with rebuilt sphere trees, shared geometry, warm starts),
// corrupt / truncated / foreign snapshots rejected with the live world untouched, 3D inputs applied with their
// closed-form effect, record + verify of a 3D scene and a tampered input reported at its tick.
#include "test_support.h"

#include "make_scenes3d.h"
#include "recording.h"
#include "scene_dir.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "snapshot_file.h"
#include "state_io.h"
#include "world2d.h"
#include "world3d.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

using namespace unison;
using namespace unison::replay;

namespace {

/// scenes/mixed3d.json: a plane, a box, a sphere, a hull and an obj mesh (every shape type).
scenes::LoadedScene3 mixed() {
    const std::string dir = scenes::sceneDir();
    return scenes::loadScene3(scenes::readSceneFile(dir + "/mixed3d.json"), "mixed3d", dir);
}

nlohmann::json mixedSceneInlined() {
    const std::string dir = scenes::sceneDir();
    return scenes::inlineMeshFiles3(scenes::readSceneFile(dir + "/mixed3d.json"), "mixed3d", dir);
}

/// Every 3D input type on mixed3d (bodies 1..4 are dynamic, 0 is the ground plane).
InputScript mixedInputs() {
    const char* text = R"({"inputs": [
        {"tick": 5, "type": "apply_impulse", "body": 2, "impulse": [0.5, 1, 0.2], "point": [0, 1, 0]},
        {"tick": 9, "type": "set_velocity", "body": 3, "linear_velocity": [0, 2, 0], "angular_velocity": [0, 1, 0]},
        {"tick": 12, "type": "create_body", "body_def": {"position": [0, 3, 0], "orientation": [1, 0, 0, 0],
                                                          "shapes": [{"type": "sphere", "radius": 0.2}]}},
        {"tick": 15, "type": "apply_force", "body": 1, "force": [0, 30, 0]},
        {"tick": 18, "type": "set_gravity", "gravity": [0.5, -9, 0]},
        {"tick": 20, "type": "destroy_body", "body": 4}
    ]})";
    return parseInputs(nlohmann::json::parse(text), "mixed inputs", 3);
}

}  // namespace

TEST_SUITE("snapshot3d") {

TEST_CASE("a 3D snapshot restores every shape type and continues bit-identically; fields name quaternion parts") {
    scenes::LoadedScene3 a = mixed();
    for (int t = 0; t < 45; ++t) a.world->step();
    const std::vector<std::uint8_t> snap = a.world->snapshot();
    World3 b;
    std::string error;
    REQUIRE_MESSAGE(b.restore(snap.data(), snap.size(), &error), error);
    CHECK(b.stateHash() == a.world->stateHash());
    CHECK(b.snapshot() == snap);
    CHECK(b.bodyIds().size() == a.bodies.size());
    for (int t = 0; t < 120; ++t) {
        a.world->step();
        b.step();
        REQUIRE(b.stateHash() == a.world->stateHash());
        REQUIRE(b.stats().pivots == a.world->stats().pivots);
    }
    // The mesh came back with the same geometry and a rebuilt sphere tree of the same shape.
    const Shape3* meshA = nullptr;
    const Shape3* meshB = nullptr;
    for (BodyId id : a.bodies) {
        for (const Shape3& s : a.world->info(id)->shapes)
            if (s.type == ShapeType3::mesh) meshA = &s;
        for (const Shape3& s : b.info(id)->shapes)
            if (s.type == ShapeType3::mesh) meshB = &s;
    }
    REQUIRE(meshA != nullptr);
    REQUIRE(meshB != nullptr);
    CHECK(meshA->mesh != meshB->mesh);  // rebuilt, not shared with the other world
    CHECK(meshB->mesh->vertexTree.nodes.size() == meshA->mesh->vertexTree.nodes.size());
    CHECK(meshB->mesh->triangleTree.order == meshA->mesh->triangleTree.order);
    // Named fields: quaternion components, the inertia tensor and mesh vertices are all reported by name.
    const std::vector<StateField> fields = b.stateFields();
    auto has = [&](const std::string& path) {
        return std::any_of(fields.begin(), fields.end(), [&](const StateField& f) { return f.path == path; });
    };
    CHECK(has("rotation.w"));
    CHECK(has("rotation.z"));
    CHECK(has("inertia.yz"));
    CHECK(has("def.frictionDirections"));
    CHECK(has("shapes[0].mesh.vertices[0].p.x"));
}

TEST_CASE("bodies sharing one mesh share it after a restore, and the snapshot holds it once") {
    const std::string dir = scenes::sceneDir();
    const nlohmann::json scene = scenes::bunnies3Scene(dir + "/bunny.obj", 0.05, 2, false);
    scenes::LoadedScene3 two = scenes::loadScene3(scene, "b2");
    // The loader reads the obj file once per shape, so make the two bunnies share one mesh the way a program would.
    std::vector<const TriangleMesh*> meshes;
    for (BodyId id : two.bodies)
        for (const Shape3& s : two.world->info(id)->shapes)
            if (s.type == ShapeType3::mesh) meshes.push_back(s.mesh.get());
    REQUIRE(meshes.size() == 2);
    CHECK(meshes[0] != meshes[1]);
    World3 shared;
    std::shared_ptr<const TriangleMesh> first;
    std::vector<BodyId> ids;
    for (BodyId id : two.bodies) {
        const BodyState3* s = two.world->state(id);
        BodyDef3 def;
        def.type = two.world->info(id)->type;
        def.position = s->position;
        def.orientation = s->rotation;
        std::vector<Shape3> shapes = two.world->info(id)->shapes;
        for (Shape3& sh : shapes) {
            if (sh.type != ShapeType3::mesh) continue;
            if (!first) first = sh.mesh;
            sh.mesh = first;
        }
        ids.push_back(shared.createBody(def, shapes));
        REQUIRE_FALSE(ids.back().isNull());
    }
    for (int t = 0; t < 20; ++t) shared.step();
    const std::vector<std::uint8_t> snap = shared.snapshot();
    World3 back;
    REQUIRE(back.restore(snap.data(), snap.size()));
    std::vector<const TriangleMesh*> restored;
    for (BodyId id : ids)
        for (const Shape3& s : back.info(id)->shapes)
            if (s.type == ShapeType3::mesh) restored.push_back(s.mesh.get());
    REQUIRE(restored.size() == 2);
    CHECK(restored[0] == restored[1]);
    CHECK(back.snapshot() == snap);
    // One mesh's vertices and triangles are 24 nv + 12 nt bytes; two copies would add that again.
    const std::size_t meshBytes = 24 * first->vertices.size() + 12 * first->triangles.size();
    CHECK(snap.size() < two.world->snapshot().size());
    CHECK(two.world->snapshot().size() - snap.size() >= meshBytes);
    for (int t = 0; t < 40; ++t) {
        shared.step();
        back.step();
        REQUIRE(back.stateHash() == shared.stateHash());
    }
}

TEST_CASE("the 3D state hash covers settings, velocities, sleep timers, shapes and the id pool") {
    scenes::LoadedScene3 base = mixed();
    for (int t = 0; t < 10; ++t) base.world->step();
    const std::vector<std::uint8_t> snap = base.world->snapshot();
    const std::uint64_t h0 = base.world->stateHash();
    auto fresh = [&] {
        World3 w;
        REQUIRE(w.restore(snap.data(), snap.size()));
        REQUIRE(w.stateHash() == h0);
        return w;
    };
    {
        World3 w = fresh();
        w.setGravity(Vec3(0.0, -10.0, 1e-12));
        CHECK(w.stateHash() != h0);
    }
    {
        // A body that has been slow for a while: setting its own velocities again only resets its sleep timer.
        World3 w = fresh();
        BodyId slow = BodyId::null();
        for (BodyId id : base.bodies)
            if (slow.isNull() && w.info(id)->sleepTime > 0.0) slow = id;
        REQUIRE_FALSE(slow.isNull());
        const BodyState3 s = *w.state(slow);
        REQUIRE(w.setVelocity(slow, s.velocity, s.angularVelocity));
        CHECK(w.info(slow)->sleepTime == 0.0);
        CHECK(w.stateHash() != h0);
    }
    {
        World3 w = fresh();
        REQUIRE(w.destroyBody(base.bodies[4]));
        const std::uint64_t gone = w.stateHash();
        CHECK(gone != h0);
        // Recreating it reuses the slot with the next generation: a different id pool, so a different hash.
        BodyDef3 def;
        def.position = base.world->state(base.bodies[4])->position;
        def.orientation = base.world->state(base.bodies[4])->rotation;
        const BodyId again = w.createBody(def, base.world->info(base.bodies[4])->shapes);
        CHECK(again.index1 == base.bodies[4].index1);
        CHECK(again.generation == base.bodies[4].generation + 1);
        CHECK(w.stateHash() != h0);
        CHECK(w.stateHash() != gone);
    }
    {
        // The same bodies with one sphere 1e-12 m larger: the shapes are part of the state.
        World3 w;
        for (BodyId id : base.bodies) {
            std::vector<Shape3> shapes = base.world->info(id)->shapes;
            for (Shape3& sh : shapes)
                if (sh.type == ShapeType3::sphere) sh.radius += 1e-12;
            BodyDef3 def;
            def.type = base.world->info(id)->type;
            REQUIRE_FALSE(w.createBody(def, shapes).isNull());
        }
        World3 same;
        for (BodyId id : base.bodies) {
            BodyDef3 def;
            def.type = base.world->info(id)->type;
            REQUIRE_FALSE(same.createBody(def, base.world->info(id)->shapes).isNull());
        }
        CHECK(w.stateHash() != same.stateHash());
    }
}

TEST_CASE("corrupt, truncated and foreign 3D snapshots are rejected and the live world is untouched") {
    scenes::LoadedScene3 live = mixed();
    scenes::LoadedScene3 twin = mixed();
    scenes::LoadedScene3 other = mixed();
    for (int t = 0; t < 15; ++t) {
        live.world->step();
        twin.world->step();
    }
    for (int t = 0; t < 30; ++t) other.world->step();
    const std::vector<std::uint8_t> good = other.world->snapshot();
    const std::uint64_t before = live.world->stateHash();
    auto rejected = [&](const std::vector<std::uint8_t>& bytes, const char* fragment) {
        std::string error;
        CHECK_FALSE(live.world->restore(bytes.data(), bytes.size(), &error));
        CHECK_MESSAGE(error.find(fragment) != std::string::npos, error);
        CHECK(live.world->stateHash() == before);
    };
    for (std::size_t len : {std::size_t(0), std::size_t(39), std::size_t(40), good.size() / 2, good.size() - 1})
        rejected(std::vector<std::uint8_t>(good.begin(), good.begin() + std::ptrdiff_t(len)), "truncated");
    for (std::size_t at : {std::size_t(50), good.size() / 3, good.size() - 9}) {
        std::vector<std::uint8_t> bad = good;
        bad[at] ^= 0x04;
        rejected(bad, "checksum");
    }
    const std::vector<std::uint8_t> payload(good.begin() + kSnapshotHeaderSize, good.end() - 8);
    const std::uint64_t n = std::uint64_t(other.world->bodyCount());
    rejected(frameSnapshot(SnapshotKind::world3, n + 1, payload), "bodies");
    rejected(frameSnapshot(SnapshotKind::world3, n, std::vector<std::uint8_t>(payload.begin(), payload.end() - 5)),
             "truncated");
    rejected(frameSnapshot(SnapshotKind::world3, n, std::vector<std::uint8_t>(payload.size(), 0xff)), "snapshot rejected");
    // A 2D snapshot into the 3D world and a 3D one into the 2D world: the world kind says no.
    const std::vector<std::uint8_t> flat = World2().snapshot();
    rejected(flat, "kind");
    World2 w2;
    std::string error;
    CHECK_FALSE(w2.restore(good.data(), good.size(), &error));
    CHECK(error.find("kind") != std::string::npos);
    // Settings the step cannot run with.
    WorldDef3 def;
    def.frictionDirections = 0;
    rejected(World3(def).snapshot(), "frictionDirections");
    def = WorldDef3{};
    def.lcp.pivotTolerance = 1.0;
    rejected(World3(def).snapshot(), "def.lcp");
    def = WorldDef3{};
    def.lcp.blockPivotRounds = 9;
    rejected(World3(def).snapshot(), "def.lcp");
    def = WorldDef3{};
    def.speculativeBand = std::numeric_limits<double>::quiet_NaN();
    rejected(World3(def).snapshot(), "speculativeBand");
    // Payload bits flipped behind a valid checksum (fixed positions): each is rejected (a count, an index, an enum,
    // a non-finite or out-of-range value, a mesh that makeMesh refuses) or read back exactly as written.
    std::uint64_t lcg = 777;
    int accepted = 0, refused = 0;
    for (int trial = 0; trial < 300; ++trial) {
        lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
        std::vector<std::uint8_t> bad = payload;
        const std::size_t at = std::size_t((lcg >> 33) % bad.size());
        bad[at] ^= std::uint8_t(1u << ((lcg >> 20) & 7u));
        const std::vector<std::uint8_t> bytes = frameSnapshot(SnapshotKind::world3, n, bad);
        World3 w;
        if (w.restore(bytes.data(), bytes.size(), &error)) {
            ++accepted;
            CHECK(w.snapshot() == bytes);
        } else {
            ++refused;
            CHECK(error.find("snapshot rejected") == 0);
            CHECK(w.bodyCount() == 0);
        }
    }
    MESSAGE("3D flipped payload bits: " << accepted << " accepted (a changed value), " << refused << " rejected");
    CHECK(refused > 0);
    // After all that the live world still steps exactly like its twin, and a good snapshot replaces it.
    for (int t = 0; t < 20; ++t) {
        live.world->step();
        twin.world->step();
        REQUIRE(live.world->stateHash() == twin.world->stateHash());
    }
    REQUIRE(live.world->restore(good.data(), good.size()));
    CHECK(live.world->stateHash() == other.world->stateHash());
}

TEST_CASE("World3::applyImpulse: dv = J / m and dw = I^-1 (r x J) for a sphere") {
    WorldDef3 zeroGravity;
    zeroGravity.gravity = Vec3::Zero();
    World3 w(zeroGravity);
    Shape3 ball;
    REQUIRE(makeSphere(Vec3::Zero(), 0.5, &ball).empty());
    ball.density = 2.0;
    BodyDef3 def;
    def.position = Vec3(1, 2, 3);
    const BodyId id = w.createBody(def, {ball});
    REQUIRE_FALSE(id.isNull());
    const double pi = 3.141592653589793;
    const double m = 2.0 * 4.0 / 3.0 * pi * 0.125;
    const double inertia = 0.4 * m * 0.25;
    CHECK(w.info(id)->mass == doctest::Approx(m).epsilon(1e-12));
    REQUIRE(w.applyImpulse(id, Vec3(0, 0, 3), Vec3(1, 2.5, 3)));  // r = (0, 0.5, 0), r x J = (1.5, 0, 0)
    CHECK(w.state(id)->velocity.z() == doctest::Approx(3.0 / m).epsilon(1e-12));
    CHECK(w.state(id)->velocity.x() == 0.0);
    CHECK(w.state(id)->angularVelocity.x() == doctest::Approx(1.5 / inertia).epsilon(1e-12));
    CHECK(w.state(id)->angularVelocity.y() == doctest::Approx(0.0).epsilon(1e-12));
    CHECK_FALSE(w.applyImpulse(id, Vec3(std::nan(""), 0, 0), Vec3::Zero()));
    Shape3 plane;
    REQUIRE(makePlane(Vec3::UnitY(), 0.0, &plane).empty());
    BodyDef3 ground;
    ground.type = BodyType::staticBody;
    CHECK_FALSE(w.applyImpulse(w.createBody(ground, {plane}), Vec3(1, 0, 0), Vec3::Zero()));
    CHECK_FALSE(w.applyImpulse(BodyId::null(), Vec3(1, 0, 0), Vec3::Zero()));
}

TEST_CASE("3D inputs: 3-vectors are required, and the JSON form reads back the same") {
    const InputScript script = mixedInputs();
    REQUIRE(script.actions.size() == 6);
    CHECK(script.actions[0].vector3 == Vec3(0.5, 1, 0.2));
    CHECK(script.actions[0].point3 == Vec3(0, 1, 0));
    CHECK(script.actions[1].angularVelocity3 == Vec3(0, 1, 0));
    const InputScript back = parseInputs(inputsToJson(script), "round trip", 3);
    CHECK(inputsToJson(back) == inputsToJson(script));
    CHECK_THROWS_AS(parseInputs(nlohmann::json::parse(R"({"inputs": [{"tick": 1, "type": "set_gravity", "gravity": [0, -9]}]})"),
                                "2-vector", 3),
                    ReplayError);
    CHECK_THROWS_AS(parseInputs(nlohmann::json::parse(R"({"inputs": [{"tick": 1, "type": "create_body", "body_def": {"shapes": [{"type": "circle", "radius": 1}]}}]})"),
                                "2D body", 3),
                    ReplayError);
    // 2D inputs for a 3D scene are refused by record().
    const InputScript flat = parseInputs(nlohmann::json::parse(R"({"inputs": [{"tick": 1, "type": "set_gravity", "gravity": [0, -9]}]})"), "2D");
    CHECK_THROWS_AS(record(mixedSceneInlined(), flat, 5, 5), ReplayError);
}

TEST_CASE("record + verify a 3D scene with every input type; a tampered input is reported at its tick") {
    const Recording rec = record(mixedSceneInlined(), mixedInputs(), 60, 1);
    REQUIRE(rec.hashes.size() == 61);
    // The inputs changed the run (the same scene without them ends elsewhere).
    CHECK(record(mixedSceneInlined(), InputScript{3, {}}, 60, 60).hashes.back() != rec.hashes.back());
    const std::vector<std::uint8_t> bytes = serializeRecording(rec);
    const Recording parsed = parseRecording(bytes, "rec3");
    CHECK(parsed.inputs.dimension == 3);
    CHECK(serializeRecording(parsed) == bytes);
    const VerifyReport ok = verify(parsed);
    CHECK(ok.match);
    CHECK(ok.ticks == 60);
    // The recorded snapshots restore into a 3D world with the recorded hash.
    for (const RecordedSnapshot& s : parsed.snapshots) {
        World3 w;
        restoreOrThrow(w, s.bytes, "snapshot");
        REQUIRE(w.stateHash() == parsed.hashes[std::size_t(s.tick)]);
    }

    Recording tampered = parsed;
    tampered.inputs.actions[1].angularVelocity3.y() += 0.001;  // the set_velocity of tick 9 on body number 3
    const VerifyReport bad = verify(tampered);
    CHECK_FALSE(bad.match);
    CHECK(bad.firstTick == 9);
    CHECK(bad.comparedTick == 9);
    REQUIRE_FALSE(bad.differences.empty());
    bool namedAngular = false;
    for (std::size_t i = 0; i < bad.differences.size(); ++i) {
        if (bad.differences[i].path == "angularVelocity.y") {
            namedAngular = true;
            CHECK(bad.bodyNumbers[i] == 3);
        }
    }
    CHECK(namedAngular);
    const nlohmann::json report = reportToJson(bad, 10);
    CHECK(report["first_desync_tick"] == 9);
    CHECK(reportSummary(bad).find("desync at tick 9") == 0);

    // A tampered impulse point (tick 5) is found at tick 5.
    Recording moved = parsed;
    moved.inputs.actions[0].point3.x() += 0.01;
    CHECK(verify(moved).firstTick == 5);
}

TEST_CASE("3D snapshot files: diff names the differing body fields") {
    scenes::LoadedScene3 a = mixed();
    for (int t = 0; t < 10; ++t) a.world->step();
    const std::vector<std::uint8_t> s10 = a.world->snapshot();
    a.world->step();
    const std::vector<std::uint8_t> s11 = a.world->snapshot();
    CHECK(diffSnapshots(s10, s10, "a", "a").empty());
    const std::vector<FieldDifference> d = diffSnapshots(s10, s11, "a", "b");
    REQUIRE_FALSE(d.empty());
    CHECK(d.front().path == "stepCount");
    CHECK(std::any_of(d.begin(), d.end(), [](const FieldDifference& f) { return f.path == "center.y" && !f.body.isNull(); }));
    // A 2D and a 3D snapshot cannot be compared.
    CHECK_THROWS_AS(diffSnapshots(s10, World2().snapshot(), "a", "b"), ReplayError);
}

}  // TEST_SUITE
