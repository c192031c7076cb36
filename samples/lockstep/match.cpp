// samples/lockstep/match.cpp — the lockstep sample's match (see match.h).
#include "match.h"

#include "make_scenes2d.h"
#include "scene_json.h"

#include <cmath>
#include <cstring>

namespace unison::lockstep {
namespace {

constexpr double kBallRadius = 0.4;

/// splitmix64: a well-mixed 64-bit value from a counter (the bots' only source of randomness).
std::uint64_t mix(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

/// The pyramid's base centre (scenes::pyramidScene with half size 0.5: row 0 from x = -7, boxes 1.125 m apart).
double pyramidCentre(int rows) { return -7.0 + 0.5 * 1.125 * (rows - 1); }

double playerStartX(const MatchConfig& match, int player) {
    const double halfBase = 0.5 * 1.125 * (match.rows - 1) + 0.5;
    const double side = player % 2 == 0 ? -1.0 : 1.0;
    return pyramidCentre(match.rows) + side * (halfBase + 3.0 + 1.5 * (player / 2));
}

}  // namespace

nlohmann::json matchScene(const MatchConfig& match) {
    nlohmann::json scene = scenes::pyramidScene(match.rows, 0.5, match.sleep);
    for (int p = 0; p < match.players; ++p) {
        scene["bodies"].push_back({{"type", "dynamic"},
                                   {"position", {playerStartX(match, p), kBallRadius}},
                                   {"shapes",
                                    {{{"type", "circle"}, {"radius", kBallRadius}, {"density", 1.0}, {"friction", 0.6}}}}});
    }
    return scene;
}

int playerBody(const MatchConfig& match, int player) { return 1 + match.rows * (match.rows + 1) / 2 + player; }

PlayerInput botInput(const MatchConfig& match, int player, int tick) {
    const std::uint64_t r = mix(mix(match.seed ^ (std::uint64_t(player) << 40)) ^ std::uint64_t(tick));
    const int toward = player % 2 == 0 ? 1 : -1;  // towards the pyramid
    PlayerInput in;
    const int roll = int(r % 64);
    if (roll < 10) {  // a push, mostly towards the pyramid
        in.dx = std::int8_t(toward * int((r >> 8) % 10) - 2 * toward + int((r >> 16) % 5) - 2);
    } else if (roll == 10) {  // a jump
        in.dy = std::int8_t(20 + int((r >> 24) % 20));
        in.dx = std::int8_t(toward * int((r >> 32) % 6));
    }
    return in;
}

MatchWorld::MatchWorld(const MatchConfig& match) {
    scenes::LoadedScene2 loaded = scenes::loadScene2(matchScene(match), "match scene");
    mWorld = std::move(*loaded.world);
    mBodies = std::move(loaded.bodies);
    for (int p = 0; p < match.players; ++p) mPlayers.push_back(mBodies[std::size_t(playerBody(match, p))]);
}

void MatchWorld::tick(const std::vector<PlayerInput>& inputs) {
    for (std::size_t p = 0; p < inputs.size() && p < mPlayers.size(); ++p) {
        const PlayerInput in = inputs[p];
        if (in == PlayerInput{}) continue;
        const BodyId id = mPlayers[p];
        // The same call as replay::Session2's apply_impulse without a point, so recordings replay identically.
        mWorld.applyImpulse(id, {kImpulseUnit * in.dx, kImpulseUnit * in.dy}, mWorld.state(id)->center);
    }
    mWorld.step();
}

replay::InputScript toInputScript(const MatchConfig& match, const std::vector<std::vector<PlayerInput>>& inputs) {
    replay::InputScript script;
    script.dimension = 2;
    for (std::size_t t = 0; t < inputs.size(); ++t) {
        for (std::size_t p = 0; p < inputs[t].size(); ++p) {
            const PlayerInput in = inputs[t][p];
            if (in == PlayerInput{}) continue;
            replay::InputAction a;
            a.tick = int(t) + 1;
            a.type = replay::InputType::applyImpulse;
            a.body = playerBody(match, int(p));
            a.vector = {kImpulseUnit * in.dx, kImpulseUnit * in.dy};
            script.actions.push_back(a);
        }
    }
    return script;
}

std::pair<BodyId, std::string> flipVelocityBit(World2& world) {
    BodyId fastest;
    double best = -1.0;
    for (BodyId id : world.bodyIds()) {
        if (world.info(id)->type != BodyType::dynamicBody) continue;
        const Vec2 v = world.state(id)->velocity;
        const double speed2 = v.x * v.x + v.y * v.y;
        if (speed2 > best) {
            best = speed2;
            fastest = id;
        }
    }
    if (fastest.isNull()) return {fastest, ""};
    const BodyState2& s = *world.state(fastest);
    Vec2 v = s.velocity;
    const bool useX = std::fabs(v.x) >= std::fabs(v.y);
    double& c = useX ? v.x : v.y;
    std::uint64_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    bits ^= 1u;
    std::memcpy(&c, &bits, sizeof bits);
    world.setVelocity(fastest, v, s.angularVelocity);
    return {fastest, useX ? "velocity.x" : "velocity.y"};
}

}  // namespace unison::lockstep
