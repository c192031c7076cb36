// samples/lockstep/match.h — the match the lockstep sample plays: its scene (the testbed pyramid and one player
// ball per peer), the seeded bot that makes each player's inputs, and how one tick's inputs act on the world.
//
// Only inputs cross the network, so everything here is a pure function of the match settings: every peer builds
// the same world from matchScene() and applies the same inputs in player order, and the recording of a match
// (toInputScript) replays through replay::Session2 to the same hashes.
// Tick t, as in replay/inputs.h: apply the inputs of tick t, then step once; the state hash of tick t is taken
// after that step.
#pragma once

#include "inputs.h"
#include "world2d.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace unison::lockstep {

/// One player's input of one tick: a push of (dx, dy) * kImpulseUnit N s at the ball's centre of mass.
struct PlayerInput {
    std::int8_t dx = 0, dy = 0;
};
inline bool operator==(PlayerInput a, PlayerInput b) { return a.dx == b.dx && a.dy == b.dy; }
inline bool operator!=(PlayerInput a, PlayerInput b) { return !(a == b); }

/// N s per input unit.
constexpr double kImpulseUnit = 0.05;

/// What every peer must agree on before the first tick.
struct MatchConfig {
    int players = 3;          ///< one ball per peer
    int rows = 10;            ///< rows of the testbed pyramid between the players
    std::uint64_t seed = 1;   ///< seeds every bot
    bool sleep = true;        ///< bodies may fall asleep
};

/// Scene JSON (2D): scenes::pyramidScene(rows) (ground, then the boxes), then one ball per player (radius 0.4 m,
/// density 1, friction 0.6) resting on the ground, even players left of the pyramid and odd ones right of it.
nlohmann::json matchScene(const MatchConfig& match);

/// Body number (scene order) of player p's ball.
int playerBody(const MatchConfig& match, int player);

/// The bot's input for player p at tick t: a pure function of (seed, p, t) — mostly pushes towards the pyramid,
/// sometimes a jump, often nothing.
PlayerInput botInput(const MatchConfig& match, int player, int tick);

/// A match's world and its players' balls.
class MatchWorld {
public:
    explicit MatchWorld(const MatchConfig& match);
    /// Applies one input per player (in player order), then steps.
    void tick(const std::vector<PlayerInput>& inputs);
    World2& world() { return mWorld; }
    const World2& world() const { return mWorld; }
    /// Body id of each scene body number.
    const std::vector<BodyId>& bodies() const { return mBodies; }

private:
    World2 mWorld;
    std::vector<BodyId> mBodies;
    std::vector<BodyId> mPlayers;
};

/// The inputs of ticks 1..inputs.size() ([tick - 1][player]) as a replay input script (apply_impulse at the
/// centre of mass, nothing for a zero input), for `unison record`-style recordings of a match.
replay::InputScript toInputScript(const MatchConfig& match, const std::vector<std::vector<PlayerInput>>& inputs);

/// Flips the lowest bit of the larger velocity component of the fastest dynamic body (a one-bit desync). Returns
/// the body and the field name ("velocity.x" or "velocity.y").
std::pair<BodyId, std::string> flipVelocityBit(World2& world);

}  // namespace unison::lockstep
