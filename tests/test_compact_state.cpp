// tests/test_compact_state.cpp — compact (rollback) states of World2 and World3 (core/compact_state.h): save,
// step on, restore gives back the exact state hash and a bit-identical continuation; restoring across a body
// creation, or corrupt bytes, is refused with the world untouched; the size per body of the 20-row pyramid.
#include "test_support.h"

#include "compact_state.h"
#include "make_scenes2d.h"
#include "make_scenes3d.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "state_io.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace unison;

namespace {

World2 pyramid(int rows) {
    scenes::LoadedScene2 s = scenes::loadScene2(scenes::pyramidScene(rows, 0.5, false), "pyramid");
    return std::move(*s.world);
}

/// Saves at every tick in `saveTicks`, runs on to `endTick`, then for each saved tick restores it and checks the
/// hash equals the one recorded then, and that stepping on from it reproduces every later recorded hash.
template <class World>
void checkRoundTrips(World& world, const std::vector<int>& saveTicks, int endTick) {
    std::vector<std::uint64_t> hashes{world.stateHash()};
    std::vector<CompactState> saved(saveTicks.size());
    for (int t = 1; t <= endTick; ++t) {
        world.step();
        hashes.push_back(world.stateHash());
        for (std::size_t i = 0; i < saveTicks.size(); ++i)
            if (saveTicks[i] == t) world.saveCompact(saved[i]);
    }
    for (std::size_t i = 0; i < saveTicks.size(); ++i) {
        std::string error;
        REQUIRE_MESSAGE(world.restoreCompact(saved[i].data(), saved[i].size(), &error), error);
        CHECK(world.stateHash() == hashes[std::size_t(saveTicks[i])]);
        CHECK(world.stepCount() == std::uint64_t(saveTicks[i]));
        for (int t = saveTicks[i] + 1; t <= endTick; ++t) {
            world.step();
            REQUIRE_MESSAGE(world.stateHash() == hashes[std::size_t(t)], "tick " << t << " after restoring tick "
                                                                               << saveTicks[i]);
        }
    }
}

}  // namespace

TEST_SUITE("compact_state") {

TEST_CASE("2D: restore gives back the saved tick's state hash and a bit-identical continuation") {
    World2 world = pyramid(10);
    // Ticks while the pile lands (contacts appear, warm starts change), then resting.
    checkRoundTrips(world, {1, 7, 30, 90}, 120);
}

TEST_CASE("2D: gravity changes, impulses and sleeping bodies are part of the compact state") {
    scenes::LoadedScene2 s = scenes::loadScene2(scenes::pyramidScene(4, 0.5, true), "pyramid");
    World2& world = *s.world;
    for (int t = 0; t < 200; ++t) world.step();  // the pile sleeps
    CompactState asleep;
    world.saveCompact(asleep);
    const std::uint64_t asleepHash = world.stateHash();
    world.setGravity({1.0, -9.0});
    world.applyImpulse(s.bodies[3], {0.5, 2.0}, world.state(s.bodies[3])->center);
    for (int t = 0; t < 10; ++t) world.step();
    CHECK(world.stateHash() != asleepHash);
    REQUIRE(world.restoreCompact(asleep.data(), asleep.size()));
    CHECK(world.stateHash() == asleepHash);
    CHECK(world.def().gravity.x == 0.0);
    CHECK_FALSE(world.info(s.bodies[3])->awake);
}

TEST_CASE("2D: a state saved before a body was created or destroyed is refused, the world untouched") {
    scenes::LoadedScene2 s = scenes::loadScene2(scenes::pyramidScene(3, 0.5, false), "pyramid");
    World2& world = *s.world;
    world.step();
    CompactState before;
    world.saveCompact(before);
    Circle ball;
    REQUIRE(makeCircle({0.0, 0.0}, 0.3, &ball).empty());
    BodyDef2 def;
    def.position = {5.0, 3.0};
    const BodyId extra = world.createBody(def, {toShape(ball)});
    REQUIRE_FALSE(extra.isNull());
    world.step();
    const std::uint64_t h = world.stateHash();
    std::string error;
    CHECK_FALSE(world.restoreCompact(before.data(), before.size(), &error));
    CHECK(error.find("created or destroyed") != std::string::npos);
    CHECK(world.stateHash() == h);
    // Destroying it again does not bring the old bodies back: the freed slot is now on the free list.
    world.destroyBody(extra);
    CHECK_FALSE(world.restoreCompact(before.data(), before.size()));
}

TEST_CASE("2D: truncated or corrupt compact states are refused, the world untouched") {
    World2 world = pyramid(5);
    for (int t = 0; t < 40; ++t) world.step();
    CompactState good;
    world.saveCompact(good);
    world.step();
    const std::uint64_t h = world.stateHash();
    const std::vector<std::uint8_t> bytes(good.data(), good.data() + good.size());
    auto refused = [&](const std::vector<std::uint8_t>& data, std::size_t size, const char* reason) {
        std::string error;
        CHECK_FALSE(world.restoreCompact(data.data(), size, &error));
        CHECK_MESSAGE(error.find(reason) != std::string::npos, error);
        CHECK(world.stateHash() == h);
    };
    for (std::size_t cut : {std::size_t(0), std::size_t(1), bytes.size() / 2, bytes.size() - 1}) refused(bytes, cut, "compact state");
    std::vector<std::uint8_t> longer = bytes;
    longer.push_back(0);
    refused(longer, longer.size(), "checksum");
    for (std::size_t at : {std::size_t(0), std::size_t(5), bytes.size() / 3, bytes.size() - 9}) {
        std::vector<std::uint8_t> flipped = bytes;
        flipped[at] ^= 0x10;
        refused(flipped, flipped.size(), "checksum");
    }
    // Behind a valid checksum (recomputed here, as a forger would), the layout is still checked.
    auto resealed = [](std::vector<std::uint8_t> data) {
        const std::uint64_t sum = hash64(data.data(), data.size() - 8);
        for (int k = 0; k < 8; ++k) data[data.size() - 8 + std::size_t(k)] = std::uint8_t(sum >> (8 * k));
        return data;
    };
    std::vector<std::uint8_t> format = bytes;
    format[0] = 99;
    refused(resealed(format), format.size(), "unknown format");
    std::vector<std::uint8_t> cut = bytes;
    cut.erase(cut.end() - 12, cut.end() - 8);  // the last 4 bytes of the touching pairs
    refused(resealed(cut), cut.size(), "compact state");
    // Non-finite numbers behind a valid checksum: the gravity (right after the format byte and the one-byte step
    // count) and a body's position (found by its bytes).
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::uint8_t> badGravity = bytes;
    std::memcpy(&badGravity[2], &nan, 8);
    refused(resealed(badGravity), badGravity.size(), "gravity is not finite");
    World2 saved = pyramid(5);
    for (int t = 0; t < 40; ++t) saved.step();
    double x = 0.0;
    for (const BodyId id : saved.bodyIds())
        if (saved.info(id)->type == BodyType::dynamicBody) {
            x = saved.state(id)->position.x;
            break;
        }
    std::uint8_t xBytes[8];
    std::memcpy(xBytes, &x, 8);
    const auto at = std::search(bytes.begin(), bytes.end(), xBytes, xBytes + 8);
    REQUIRE(at != bytes.end());
    std::vector<std::uint8_t> badPose = bytes;
    std::memcpy(&badPose[std::size_t(at - bytes.begin())], &nan, 8);
    refused(resealed(badPose), badPose.size(), "not finite");
    REQUIRE(world.restoreCompact(bytes.data(), bytes.size()));
}

TEST_CASE("encoding: signed zeros, the warm-start flags and off-origin centres of mass come back bit for bit") {
    using namespace compact_detail;
    // The flags' bits 23-31, reversed, are their own inverse, and the flags most entries carry fit in one byte.
    for (std::uint32_t h = 0; h < 512; ++h) CHECK(reverseHighBits(reverseHighBits(h)) == h);
    CHECK(reverseHighBits(kActiveSetEntry >> 23) < 128u);
    CHECK(reverseHighBits((kActiveSetEntry | kSettledEntry | kSettledCount) >> 23) < 128u);
    CHECK(reverseHighBits(kApproximateEntry >> 23) == 1u);
    // A zero's sign is a code of its own: -0.0 is not written as a double, and not read back as +0.0.
    CHECK(impulseCode(0.0) == kImpulsePlusZero);
    CHECK(impulseCode(-0.0) == kImpulseMinusZero);
    CHECK(impulseCode(-1.0) == kImpulseValue);
    CHECK(impulseCode(std::numeric_limits<double>::denorm_min()) == kImpulseValue);
    // A box whose centre of mass is off its origin (its centre is written, 16 bytes more than for the same box
    // about its origin, whose centre has the position's bits and is left out); the continuation after a restore
    // is bit-identical either way.
    auto withBox = [](Vec2 boxCenter, World2& world) {
        Polygon box;
        REQUIRE(makeBox(0.5, 0.25, boxCenter, 0.2, &box).empty());
        BodyDef2 def;
        def.position = {-4.0, 2.0};
        def.angularVelocity = 1.5;
        const BodyId id = world.createBody(def, {toShape(box)});
        REQUIRE_FALSE(id.isNull());
        return id;
    };
    World2 centred = pyramid(4);
    World2 world = pyramid(4);
    const BodyId plain = withBox({0.0, 0.0}, centred);
    const BodyId tilted = withBox({0.3, -0.1}, world);
    CHECK(centred.state(plain)->center.x == centred.state(plain)->position.x);
    CHECK(world.state(tilted)->center.x != world.state(tilted)->position.x);
    CompactState a, b;
    centred.saveCompact(a);
    world.saveCompact(b);
    CHECK(b.size() == a.size() + 16);
    checkRoundTrips(world, {1, 25, 70}, 90);
}

TEST_CASE("2D: the 20-row pyramid's compact state stays within 200 bytes per body, warm starts included") {
    World2 world = pyramid(20);
    CompactState state;
    std::size_t largest = 0;
    for (int t = 1; t <= 600; ++t) {
        world.step();
        if (t % 20 == 0) {
            world.saveCompact(state);
            largest = std::max(largest, state.size());
        }
    }
    const double perBody = double(largest) / world.bodyCount();
    MESSAGE("20-row pyramid: largest compact state " << largest << " bytes, " << perBody << " bytes per body");
    CHECK(perBody <= 200.0);
    // A full snapshot holds shapes and settings too: the compact state is far smaller.
    CHECK(largest * 2 < world.snapshot().size());
}

TEST_CASE("3D: restore gives back the saved tick's state hash and a bit-identical continuation") {
    scenes::LoadedScene3 s = scenes::loadScene3(scenes::boxPile3Scene(12, true, false), "box pile");
    checkRoundTrips(*s.world, {1, 15, 60}, 90);
    World3& world = *s.world;
    CompactState state;
    world.saveCompact(state);
    const std::uint64_t h = world.stateHash();
    world.setGravity(Vec3(0.0, -5.0, 1.0));
    world.step();
    REQUIRE(world.restoreCompact(state.data(), state.size()));
    CHECK(world.stateHash() == h);
    CHECK_FALSE(world.restoreCompact(state.data(), state.size() - 1));
}

}  // TEST_SUITE
