// tests/test_replay.cpp — determinism, snapshots and replay verification of the 2D world: golden hashes
// of the golden scenes, snapshot -> restore -> continue bit-identically (warm starts and id reuse included),
// record -> verify, desync reports naming the tampered tick, and rejection of corrupt or truncated data with the live
// world untouched.
#include "test_support.h"

#include "golden.h"
#include "recording.h"
#include "scene_json3d.h"
#include "snapshot_file.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace unison;
using namespace unison::replay;

namespace {

// ==== GOLDEN HASHES ===============================================================================================
// The state hash after the last tick of each golden scene (replay/golden.cpp) and the chain hash of every tick's
// hash. They change whenever the step, the scenes or the state format change (the lead is changing the solver and
// the step, so expect that). To regenerate, build and run
//     build/replay/unison_golden --cpp
// (or set UNISON_PRINT_GOLDEN=1 when running this suite), paste its lines here, and say in the commit why the
// hashes changed. scripts/determinism.sh checks that every build (gcc/clang, -O0..-O3, aarch64) prints the same.
struct Golden {
    const char* name;
    int steps;
    std::uint64_t finalHash;
    std::uint64_t chainHash;
};
const Golden kGolden[] = {
    {"pyramid", 240, 0x1e213b323e891624ull, 0x34ae520ce885118aull},
    {"restitution_row", 240, 0xe75237c06f434b0dull, 0xa469a525b025814dull},
    {"mixed_pile", 300, 0x5e0fb21df4d238c2ull, 0xd30e0b5e98a0fcbdull},
    {"cradle", 120, 0x59d204f6a0c9eeeeull, 0x35f3da5d91b54a78ull},
    {"pyramid16", 120, 0xb203efdef1459a0cull, 0xe0875c06f0a36e39ull},
    {"large_pyramid24", 30, 0xcdbdc83655aef621ull, 0xf0a9172897ae1793ull},
    {"pyramid24_landing", 100, 0xb6cb9f6ccb9ac2fbull, 0xab0d791e935cd615ull},
    {"box_heap3d", 180, 0xb7c77e83c4a1aadbull, 0xbd4a1d7c999ba77cull},
    {"spheres3d", 180, 0xc02e72087abe9203ull, 0xb7246fb08473fdd4ull},
    {"bunnies3d", 240, 0x8e2b01043affc298ull, 0xf8ed5214d76f3ddcull},
    {"box_heap3d_path", 90, 0x6c19806223cdbeb5ull, 0x0abde1c20a57be89ull},
    {"pyramid16_budget", 120, 0x061037aae206169eull, 0x67dd81cbdd9cb81full},
    {"box_heap3d_budget", 180, 0x401d4869a41820a7ull, 0xd0402e6066746b8bull},
};
// ==================================================================================================================

const GoldenScene& golden(const std::string& name) {
    static const std::vector<GoldenScene> scenes = goldenScenes();
    for (const GoldenScene& g : scenes) {
        if (g.name == name) return g;
    }
    FAIL("no golden scene " << name);
    return scenes.front();
}

/// Inputs that exercise every input type on the mixed pile (bodies 1..30 are dynamic, 0 is the static box).
InputScript pileInputs() {
    const char* text = R"({"inputs": [
        {"tick": 5, "type": "apply_impulse", "body": 3, "impulse": [2, 5]},
        {"tick": 12, "type": "set_velocity", "body": 5, "linear_velocity": [0, 8], "angular_velocity": 1},
        {"tick": 20, "type": "destroy_body", "body": 7},
        {"tick": 20, "type": "destroy_body", "body": 9},
        {"tick": 24, "type": "create_body", "body_def": {"position": [0, 8], "shapes": [{"type": "circle", "radius": 0.3}]}},
        {"tick": 30, "type": "set_gravity", "gravity": [1, -9]},
        {"tick": 33, "type": "apply_force", "body": 31, "force": [0, 100], "point": [0.1, 8]},
        {"tick": 40, "type": "create_body", "body_def": {"position": [1, 8], "shapes": [{"type": "box", "half_extents": [0.2, 0.2]}]}}
    ]})";
    return parseInputs(nlohmann::json::parse(text), "pile inputs");
}

/// Steps `original` to steps/3, restores its snapshot into a fresh world and steps both to the end, requiring the
/// same hash, pivot count and warm starts every tick. Returns the restored world's warm-started islands.
template <class World>
int restoreAndContinue(World& original, int steps) {
    const int k = steps / 3;
    for (int t = 0; t < k; ++t) original.step();
    const std::vector<std::uint8_t> snap = original.snapshot();
    World fresh;
    std::string error;
    REQUIRE_MESSAGE(fresh.restore(snap.data(), snap.size(), &error), error);
    CHECK(fresh.stateHash() == original.stateHash());
    CHECK(fresh.snapshot() == snap);  // the restored state serialises to the same bytes
    int warmIslands = 0;
    for (int t = k; t < steps; ++t) {
        original.step();
        fresh.step();
        REQUIRE(fresh.stateHash() == original.stateHash());
        // Same warm starts, so the same number of pivots (a lost warm-start cache would show here first).
        REQUIRE(fresh.stats().pivots == original.stats().pivots);
        REQUIRE(fresh.stats().warmStartedIslands == original.stats().warmStartedIslands);
        warmIslands += fresh.stats().warmStartedIslands;
    }
    return warmIslands;
}

std::string tempFile(const std::string& name) {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir ? dir : "/tmp") + "/unison_test_replay_" + std::to_string(::getpid()) + "_" + name;
}

}  // namespace

TEST_SUITE("replay") {

TEST_CASE("golden scenes: the hash after every tick matches the golden table") {
    const bool print = std::getenv("UNISON_PRINT_GOLDEN") != nullptr;
    for (const Golden& g : kGolden) {
        CAPTURE(std::string(g.name));
        const GoldenScene& scene = golden(g.name);
        REQUIRE(scene.steps == g.steps);
        const std::vector<std::uint64_t> hashes = goldenHashes(scene);
        REQUIRE(hashes.size() == std::size_t(g.steps) + 1);
        const std::uint64_t chain = chainHash(hashes);
        if (print || hashes.back() != g.finalHash || chain != g.chainHash) {
            std::cout << "    {\"" << g.name << "\", " << g.steps << ", 0x" << hexHash(hashes.back()) << "ull, 0x"
                      << hexHash(chain) << "ull},   // regenerate: build/replay/unison_golden --cpp\n";
        }
        CHECK(hexHash(hashes.back()) == hexHash(g.finalHash));
        CHECK(hexHash(chain) == hexHash(g.chainHash));
        // A second world steps to the same bits.
        CHECK(goldenHashes(scene) == hashes);
        CHECK(firstRestoreMismatch(scene, hashes) == -1);  // what unison_golden checks in every build
        std::vector<std::uint64_t> tampered = hashes;
        tampered[std::size_t(g.steps) - 1] ^= 1u;
        CHECK(firstRestoreMismatch(scene, tampered) == g.steps - 1);
    }
}

TEST_CASE("the state hash covers settings, velocities, sleep state and the id pool") {
    scenes::LoadedScene2 loaded = scenes::loadScene2(golden("mixed_pile").scene, "pile");
    World2& w = *loaded.world;
    for (int i = 0; i < 10; ++i) w.step();
    const std::uint64_t h0 = w.stateHash();
    const std::vector<std::uint8_t> snap = w.snapshot();
    auto restored = [&] {
        auto copy = std::make_unique<World2>();
        REQUIRE(copy->restore(snap.data(), snap.size()));
        REQUIRE(copy->stateHash() == h0);
        return copy;
    };
    {
        auto c = restored();
        c->setGravity({0.0, -9.0});
        CHECK(c->stateHash() != h0);
    }
    {
        // Destroying and re-creating an identical body gives the same dense layout but a newer generation.
        auto c = restored();
        const BodyId last = loaded.bodies.back();
        const BodyState2 s = *c->state(last);
        BodyDef2 def;
        def.position = s.position;
        def.angle = c->angle(last);
        def.linearVelocity = s.velocity;
        def.angularVelocity = s.angularVelocity;
        const std::vector<Shape2> shapes = c->info(last)->shapes;
        REQUIRE(c->destroyBody(last));
        const BodyId again = c->createBody(def, shapes);
        CHECK(again.index1 == last.index1);
        CHECK(again.generation == last.generation + 1);
        CHECK(c->stateHash() != h0);
    }
    {
        // The sleep timer alone: step until some awake body is slow enough to be counting towards sleep, then set
        // its velocity to what it already is (that resets only the timer).
        auto c = restored();
        BodyId counting;
        for (int t = 0; t < 200 && counting.isNull(); ++t) {
            c->step();
            for (BodyId id : loaded.bodies) {
                const BodyInfo2* info = c->info(id);
                if (info->type == BodyType::dynamicBody && info->awake && info->sleepTime > 0.0) counting = id;
            }
        }
        REQUIRE_FALSE(counting.isNull());
        const std::uint64_t before = c->stateHash();
        const BodyState2 s = *c->state(counting);
        REQUIRE(c->setVelocity(counting, s.velocity, s.angularVelocity));
        CHECK(c->info(counting)->sleepTime == 0.0);
        CHECK(c->stateHash() != before);
    }
    // The named field list is the hash's serialisation: same world, same fields; every body has its sleep timer.
    const std::vector<StateField> fields = w.stateFields();
    CHECK(diffFields(fields, restored()->stateFields()).empty());
    int timers = 0;
    for (const StateField& f : fields) timers += f.path == "sleepTime" ? 1 : 0;
    CHECK(timers == w.bodyCount());
}

TEST_CASE("snapshot at tick k, restore into a fresh world, continue: every tick's hash and pivot count match") {
    for (const Golden& g : kGolden) {
        CAPTURE(std::string(g.name));
        const GoldenScene& scene = golden(g.name);
        const int warmIslands = scene.is3d() ? restoreAndContinue(*scenes::loadScene3(scene.scene, g.name).world, scene.steps)
                                             : restoreAndContinue(*scenes::loadScene2(scene.scene, g.name).world, scene.steps);
        if (g.name == std::string("pyramid") || g.name == std::string("mixed_pile") || scene.is3d())
            CHECK(warmIslands > 0);
    }
}

TEST_CASE("after a restore, freed ids are reused in the same order (LIFO free list)") {
    Session2 session(golden("mixed_pile").scene, "pile");
    const InputScript inputs = pileInputs();
    for (int t = 1; t <= 21; ++t) session.tick(t, inputs);  // bodies 7 and 9 destroyed at tick 20
    const std::vector<std::uint8_t> snap = session.world().snapshot();
    World2 fresh;
    REQUIRE(fresh.restore(snap.data(), snap.size()));
    scenes::BodySpec2 spec = scenes::readBody2(
        nlohmann::json::parse(R"({"position": [0, 8], "shapes": [{"type": "circle", "radius": 0.3}]})"), "body");
    for (int i = 0; i < 3; ++i) {
        const BodyId a = session.world().createBody(spec.def, spec.shapes);
        const BodyId b = fresh.createBody(spec.def, spec.shapes);
        CHECK(a == b);
        CHECK(a.generation == (i < 2 ? 2u : 1u));  // two reused slots (generation 2), then a new one
        session.world().step();
        fresh.step();
        CHECK(session.world().stateHash() == fresh.stateHash());
    }
}

TEST_CASE("record then verify: every tick matches, also after a save and load of the file") {
    const Recording rec = record(golden("mixed_pile").scene, pileInputs(), 60, 7);
    CHECK(rec.hashes.size() == 61);
    std::vector<int> ticks;
    for (const RecordedSnapshot& s : rec.snapshots) ticks.push_back(s.tick);
    CHECK(ticks == std::vector<int>{0, 7, 14, 21, 28, 35, 42, 49, 56, 60});
    const VerifyReport direct = verify(rec);
    CHECK(direct.match);
    CHECK(direct.ticks == 60);
    const std::string path = tempFile("match.urec");
    writeFileAtomic(path, serializeRecording(rec));
    const Recording loaded = parseRecording(readBinaryFile(path), path);
    CHECK(loaded.hashes == rec.hashes);
    CHECK(inputsToJson(loaded.inputs) == inputsToJson(rec.inputs));
    CHECK(verify(loaded).match);
    // A recorded snapshot restores to the recorded hash of its tick.
    World2 w;
    REQUIRE(w.restore(loaded.snapshots[3].bytes.data(), loaded.snapshots[3].bytes.size()));
    CHECK(w.stateHash() == loaded.hashes[21]);
    std::remove(path.c_str());
}

TEST_CASE("a tampered input: the desync report names its tick, the body and the field with both values") {
    Recording rec = record(golden("mixed_pile").scene, pileInputs(), 40, 1);
    REQUIRE(rec.inputs.actions[0].tick == 5);
    rec.inputs.actions[0].vector.y += 0.001;  // the impulse of tick 5 on body number 3
    const VerifyReport report = verify(rec);
    CHECK_FALSE(report.match);
    CHECK(report.firstTick == 5);
    CHECK(report.comparedTick == 5);  // snapshots every tick: the field report is for the same tick
    REQUIRE_FALSE(report.differences.empty());
    bool velocityOfBody3 = false;
    for (std::size_t i = 0; i < report.differences.size(); ++i) {
        const FieldDifference& d = report.differences[i];
        CHECK(d.a != d.b);
        if (report.bodyNumbers[i] == 3 && d.path == "velocity.y") velocityOfBody3 = true;
    }
    CHECK(velocityOfBody3);
    const nlohmann::json js = reportToJson(report, 5);
    CHECK(js["status"] == "desync");
    CHECK(js["first_desync_tick"] == 5);
    CHECK(js["differences"].size() <= 5);
    CHECK(reportSummary(report).find("desync at tick 5") == 0);

    // With snapshots every 10 ticks the tick is still exact; verify stops there (no snapshot at tick 12, so no
    // fields), and when asked to keep going the fields come from the next snapshot (tick 20).
    Recording sparse = record(golden("mixed_pile").scene, pileInputs(), 40, 10);
    sparse.inputs.actions[1].angularVelocity = 2.0;  // the set_velocity of tick 12
    const VerifyReport stopped = verify(sparse);
    CHECK(stopped.firstTick == 12);
    CHECK(stopped.ticks == 12);
    CHECK(stopped.comparedTick == -1);
    CHECK(stopped.differences.empty());
    CHECK(reportSummary(stopped).find("--keep-going") != std::string::npos);
    const VerifyReport r2 = verify(sparse, true);
    CHECK(r2.firstTick == 12);
    CHECK(r2.ticks == 20);
    CHECK(r2.comparedTick == 20);
    CHECK_FALSE(r2.differences.empty());

    // A tampered recorded hash: the tick is named, and the snapshot there shows no differing field.
    Recording badHash = record(golden("cradle").scene, {}, 30, 1);
    badHash.hashes[17] ^= 1u;
    const VerifyReport r3 = verify(badHash);
    CHECK(r3.firstTick == 17);
    CHECK(r3.differences.empty());
}

TEST_CASE("corrupt, truncated or mismatched snapshots are rejected and the live world is untouched") {
    scenes::LoadedScene2 live = scenes::loadScene2(golden("pyramid").scene, "pyramid");
    scenes::LoadedScene2 reference = scenes::loadScene2(golden("pyramid").scene, "pyramid");
    for (int t = 0; t < 30; ++t) {
        live.world->step();
        reference.world->step();
    }
    scenes::LoadedScene2 other = scenes::loadScene2(golden("mixed_pile").scene, "pile");
    for (int t = 0; t < 30; ++t) other.world->step();
    const std::vector<std::uint8_t> good = other.world->snapshot();
    const std::uint64_t liveHash = live.world->stateHash();

    auto rejected = [&](const std::vector<std::uint8_t>& bytes, const char* expectFragment) {
        std::string error;
        const bool ok = live.world->restore(bytes.data(), bytes.size(), &error);
        CHECK_FALSE(ok);
        CHECK_MESSAGE(error.find(expectFragment) != std::string::npos, error);
        CHECK(live.world->stateHash() == liveHash);
    };
    for (std::size_t len : {std::size_t(0), std::size_t(7), std::size_t(40), std::size_t(47), good.size() / 2, good.size() - 1})
        rejected(std::vector<std::uint8_t>(good.begin(), good.begin() + std::ptrdiff_t(len)), "truncated");
    std::vector<std::uint8_t> padded = good;
    padded.push_back(0);
    rejected(padded, "payload bytes");
    for (std::size_t at : {std::size_t(45), std::size_t(300), good.size() / 2, good.size() - 9}) {
        std::vector<std::uint8_t> bad = good;
        bad[at] ^= 0x10;
        rejected(bad, "checksum");
    }
    std::vector<std::uint8_t> magic = good;
    magic[0] = 'X';
    rejected(magic, "magic");
    // Headers that are consistent (valid checksum) but wrong: rebuilt with the container writer.
    auto reframe = [&](std::uint32_t version, std::uint32_t kind, std::uint64_t flags, std::uint64_t bodies,
                       const std::vector<std::uint8_t>& payload) {
        std::vector<std::uint8_t> bytes = frameSnapshot(SnapshotKind::world2, bodies, payload);
        ByteWriter patch;
        patch.u32(version);
        patch.u32(kind);
        patch.u64(flags);
        std::copy(patch.data().begin(), patch.data().end(), bytes.begin() + 8);
        bytes.resize(bytes.size() - 8);
        ByteWriter sum;
        sum.u64(hash64(bytes.data(), bytes.size()));
        bytes.insert(bytes.end(), sum.data().begin(), sum.data().end());
        return bytes;
    };
    const std::vector<std::uint8_t> payload(good.begin() + kSnapshotHeaderSize, good.end() - 8);
    const std::uint64_t flags = resultAffectingBuildFlags();
    const std::uint64_t n = std::uint64_t(other.world->bodyCount());
    {
        // The rebuilt container itself is fine: only the field changed below makes it fail.
        const std::vector<std::uint8_t> same = reframe(kSnapshotFormatVersion, 2, flags, n, payload);
        CHECK(same == good);
        World2 scratch;
        CHECK(scratch.restore(same.data(), same.size()));
    }
    rejected(reframe(kSnapshotFormatVersion + 1, 2, flags, n, payload), "format version");
    rejected(reframe(kSnapshotFormatVersion, 3, flags, n, payload), "kind");
    rejected(reframe(kSnapshotFormatVersion, 2, flags | 1u, n, payload), "flags");
    rejected(reframe(kSnapshotFormatVersion, 2, flags, n + 1, payload), "bodies");
    std::vector<std::uint8_t> shortPayload(payload.begin(), payload.end() - 3);
    rejected(reframe(kSnapshotFormatVersion, 2, flags, n, shortPayload), "truncated");
    std::vector<std::uint8_t> garbage(payload.size(), 0xff);
    rejected(reframe(kSnapshotFormatVersion, 2, flags, n, garbage), "snapshot rejected");

    // After all that the live world still steps exactly like its untouched twin.
    for (int t = 0; t < 20; ++t) {
        live.world->step();
        reference.world->step();
        REQUIRE(live.world->stateHash() == reference.world->stateHash());
    }
    // And a good snapshot does replace it.
    REQUIRE(live.world->restore(good.data(), good.size()));
    CHECK(live.world->stateHash() == other.world->stateHash());
}

TEST_CASE("flipped payload bytes behind a valid checksum: rejected, or read back exactly as written") {
    scenes::LoadedScene2 pile = scenes::loadScene2(golden("mixed_pile").scene, "pile");
    for (int t = 0; t < 40; ++t) pile.world->step();
    const std::vector<std::uint8_t> good = pile.world->snapshot();
    const std::vector<std::uint8_t> payload(good.begin() + kSnapshotHeaderSize, good.end() - 8);
    const std::uint64_t n = std::uint64_t(pile.world->bodyCount());
    std::uint64_t lcg = 12345;  // fixed sequence: the same positions on every run
    int accepted = 0, rejected = 0;
    for (int trial = 0; trial < 400; ++trial) {
        lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
        std::vector<std::uint8_t> bad = payload;
        const std::size_t at = std::size_t((lcg >> 33) % bad.size());
        bad[at] ^= std::uint8_t(1u << ((lcg >> 20) & 7u));
        const std::vector<std::uint8_t> bytes = frameSnapshot(SnapshotKind::world2, n, bad);
        World2 w;
        std::string error;
        if (w.restore(bytes.data(), bytes.size(), &error)) {
            ++accepted;
            CHECK(w.snapshot() == bytes);  // every field read is kept bit for bit
        } else {
            ++rejected;
            CHECK(error.find("snapshot rejected") == 0);
            CHECK(w.bodyCount() == 0);
        }
    }
    MESSAGE("flipped payload bits: " << accepted << " accepted (a changed value), " << rejected << " rejected");
    CHECK(rejected > 0);
    // Settings the solver cannot run with are rejected too (a pivot tolerance >= 1 crashed Lemke).
    WorldDef2 def;
    def.lcp.pivotTolerance = 1.0;
    const std::vector<std::uint8_t> badDef = World2(def).snapshot();
    std::string error;
    CHECK_FALSE(World2().restore(badDef.data(), badDef.size(), &error));
    CHECK(error.find("def.lcp") != std::string::npos);
}

TEST_CASE("snapshot files: atomic write, read back, diff; recordings: corrupt files are rejected") {
    scenes::LoadedScene2 a = scenes::loadScene2(golden("cradle").scene, "cradle");
    for (int t = 0; t < 10; ++t) a.world->step();
    const std::string pa = tempFile("a.usnap"), pb = tempFile("b.usnap");
    writeFileAtomic(pa, a.world->snapshot());
    CHECK(readBinaryFile(pa) == a.world->snapshot());
    std::ifstream leftover(pa + ".tmp." + std::to_string(::getpid()));
    CHECK_FALSE(leftover.good());
    CHECK(diffSnapshots(readBinaryFile(pa), a.world->snapshot(), "a", "a").empty());
    a.world->step();
    writeFileAtomic(pb, a.world->snapshot());
    const std::vector<FieldDifference> d = diffSnapshots(readBinaryFile(pa), readBinaryFile(pb), pa, pb);
    REQUIRE_FALSE(d.empty());
    CHECK(d.front().path == "stepCount");
    CHECK(d.front().a == "10");
    CHECK(d.front().b == "11");
    CHECK_THROWS_AS(writeFileAtomic("/nonexistent-dir/x.usnap", a.world->snapshot()), ReplayError);
    CHECK_THROWS_AS(readBinaryFile("/nonexistent-dir/x.usnap"), ReplayError);

    const std::vector<std::uint8_t> rec = serializeRecording(record(golden("cradle").scene, {}, 10, 5));
    CHECK_NOTHROW(parseRecording(rec, "rec"));
    for (std::size_t len : {std::size_t(0), std::size_t(10), rec.size() / 2, rec.size() - 1})
        CHECK_THROWS_AS(parseRecording(std::vector<std::uint8_t>(rec.begin(), rec.begin() + std::ptrdiff_t(len)), "rec"), ReplayError);
    std::vector<std::uint8_t> flipped = rec;
    flipped[rec.size() / 3] ^= 1;
    CHECK_THROWS_WITH_AS(parseRecording(flipped, "rec"), doctest::Contains("checksum"), ReplayError);
    std::remove(pa.c_str());
    std::remove(pb.c_str());
}

TEST_CASE("inputs: bad scripts and inputs that cannot be applied are errors that name the input and tick") {
    const std::pair<const char*, const char*> bad[] = {
        {R"({"inputs": [{"tick": 0, "type": "set_gravity", "gravity": [0, 1]}]})", "inputs[0].tick"},
        {R"({"inputs": [{"tick": 1, "type": "explode"}]})", "inputs[0].type"},
        {R"({"inputs": [{"tick": 1, "type": "apply_impulse", "impulse": [0, 1]}]})", "inputs[0].body"},
        {R"({"inputs": [{"tick": 1, "type": "set_gravity", "gravity": [0, "x"]}]})", "gravity[1]"},
        {R"({"inputs": [{"tick": 1, "type": "create_body", "body_def": {"shapes": [{"type": "circle", "radius": -1}]}}]})", "radius"},
        {R"({"input": []})", "inputs"},
    };
    for (const auto& item : bad) {
        const auto& text = item.first;  // no structured binding: clang 14 cannot CAPTURE one
        const auto& fragment = item.second;
        CAPTURE(text);
        CHECK_THROWS_WITH_AS(parseInputs(nlohmann::json::parse(text), "in"), doctest::Contains(fragment), ReplayError);
    }
    const nlohmann::json pile = golden("mixed_pile").scene;
    const std::pair<const char*, const char*> unusable[] = {
        {R"({"inputs": [{"tick": 2, "type": "apply_impulse", "body": 99, "impulse": [0, 1]}]})", "no body number 99"},
        {R"({"inputs": [{"tick": 2, "type": "apply_impulse", "body": 0, "impulse": [0, 1]}]})", "not dynamic"},
        {R"({"inputs": [{"tick": 2, "type": "destroy_body", "body": 4}, {"tick": 3, "type": "set_velocity", "body": 4,
             "linear_velocity": [0, 1]}]})", "inputs[1] (tick 3): body 4 was destroyed"},
    };
    for (const auto& item : unusable) {
        const auto& text = item.first;  // no structured binding: clang 14 cannot CAPTURE one
        const auto& fragment = item.second;
        CAPTURE(text);
        const InputScript script = parseInputs(nlohmann::json::parse(text), "in");
        CHECK_THROWS_WITH_AS(record(pile, script, 5, 1), doctest::Contains(fragment), ReplayError);
    }
}

}  // TEST_SUITE
