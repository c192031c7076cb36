// samples/lockstep/rollback.h — one peer's simulation of a match, without the network: the input table, the
// compact states of recent ticks, prediction and rollback, and the checkpoint hashes.
//
// Lockstep (maxPrediction 0): tick t is simulated only when every player's input of tick t is known. Rollback
// (maxPrediction P > 0): tick t may be simulated up to P ticks ahead of the oldest missing input; a missing input
// is predicted as that player's last known input (GGPO's "repeat last"). When the real input arrives and differs
// from the one used, reconcile() restores the compact state saved before that tick and simulates forward again
// with the inputs now known, so the state converges to the one every peer computes from the real inputs.
// Invariants: the state after every tick in [oldestKept(), currentTick()] is saved (World2::saveCompact); ticks
// <= finalTick() were simulated with real inputs only and never change again; inputs of ticks 1..inputDelay are
// zero for every player (nobody can send them in time).
#pragma once

#include "compact_state.h"
#include "match.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace unison::lockstep {

/// How a peer runs its match.
struct SessionConfig {
    int localPlayer = 0;    ///< whose inputs this peer makes
    int ticks = 600;        ///< last tick of the match
    int inputDelay = 2;     ///< a local input made at tick t is for tick t + inputDelay
    int maxPrediction = 0;  ///< 0: lockstep; > 0: rollback, at most this many ticks ahead of a missing input
    int checkEvery = 10;    ///< K: checkpoint hashes at ticks K, 2K, ... and at the last tick
    int desyncAt = -1;      ///< >= 1: after simulating this tick, flip one velocity bit (a deliberate bug)
};

/// Costs and counts of a session (times in microseconds of wall clock, outside every hash).
struct SessionStats {
    int rollbacks = 0;             ///< reconcile() calls that restored a state
    int resimulatedTicks = 0;      ///< ticks simulated again by rollbacks
    int maxRollback = 0;           ///< most ticks simulated again by one rollback
    int predictedTicks = 0;        ///< ticks first simulated with at least one predicted input
    int mispredictions = 0;        ///< predicted inputs that turned out wrong
    double stepUs = 0, saveUs = 0, restoreUs = 0;  ///< totals
    int steps = 0, saves = 0, restores = 0;        ///< counts
    std::size_t maxStateBytes = 0;                 ///< largest compact state
};

class RollbackSession {
public:
    RollbackSession(const MatchConfig& match, const SessionConfig& config);

    /// This peer's input of `tick`; call for each tick in order, tick > inputDelay.
    void setLocalInput(int tick, PlayerInput input);
    /// Next tick whose local input is still to be made.
    int nextLocalTick() const { return mConfirmed[std::size_t(mConfig.localPlayer)] + 1; }
    /// A real input of any player. Only the next tick after that player's known ones is taken (inputs of a player
    /// must arrive in tick order; repeats are ignored); returns whether it was taken.
    bool addInput(int player, int tick, PlayerInput input);
    /// Known inputs of a player: every tick up to this one.
    int confirmedUpTo(int player) const { return mConfirmed[std::size_t(player)]; }
    const PlayerInput& input(int player, int tick) const { return mInputs[std::size_t(tick)][std::size_t(player)]; }

    /// True when tick currentTick() + 1 may be simulated now.
    bool canAdvance() const;
    /// Simulates the next tick (with predicted inputs where real ones are missing) and saves its state.
    void advance();
    /// Rolls back and simulates again when an input that arrived differs from the one used. Returns the number of
    /// ticks simulated again (0: nothing to do).
    int reconcile();

    int currentTick() const { return mTick; }
    /// Every tick up to this one was simulated with real inputs (after reconcile()).
    int finalTick() const;
    /// The state hash after a checkpoint tick (latest simulation of it), or 0 if not simulated yet.
    std::uint64_t checkpointHash(int tick) const;
    /// XXH3 of the compact-state hashes of every tick after the previous checkpoint up to `tick`: a divergence
    /// that heals before the checkpoint (a one-ulp difference lost to rounding) still changes it.
    std::uint64_t windowHash(int tick) const;
    bool isCheckpoint(int tick) const { return tick % mConfig.checkEvery == 0 || tick == mConfig.ticks; }

    /// Oldest tick whose compact state is kept.
    int oldestKept() const { return mBase; }
    /// Forgets the states of ticks before `tick` (never the current one).
    void dropBefore(int tick);
    /// XXH3 of the compact state after `tick` (any simulated tick).
    std::uint64_t compactHash(int tick) const;
    /// The full snapshot (World2::snapshot()) of the state after `tick` (kept ticks only).
    std::vector<std::uint8_t> snapshotAt(int tick);

    const SessionStats& stats() const { return mStats; }
    /// The body and field flipped by the desync injection (empty when none happened).
    const std::string& injectedField() const { return mInjectedField; }
    BodyId injectedBody() const { return mInjectedBody; }
    const MatchWorld& match() const { return mMatch; }

private:
    void simulate(int tick);  // inputs as known now, step, inject, save, checkpoint hash
    CompactState& slot(int tick) { return mStates[std::size_t(tick) % mStates.size()]; }
    const CompactState& slot(int tick) const { return mStates[std::size_t(tick) % mStates.size()]; }
    void restoreTick(int tick);
    PlayerInput bestGuess(int player) const;  // the last known input of a player

    MatchConfig mMatchConfig;
    SessionConfig mConfig;
    MatchWorld mMatch;
    std::vector<std::vector<PlayerInput>> mInputs;  // (ticks + 1) x players: real inputs where known
    std::vector<std::vector<PlayerInput>> mUsed;    // (ticks + 1) x players: inputs the latest simulation used
    std::vector<int> mConfirmed;                    // (players) last tick with a known input
    int mTick = 0;
    int mRollbackFrom = 1 << 30;  // earliest tick simulated with an input that has since turned out wrong
    std::vector<CompactState> mStates;  // ring: the state after tick t is at t % size, for t in [mBase, mTick]
    int mBase = 0;
    std::map<int, std::uint64_t> mCheckpoints;
    std::vector<std::uint64_t> mTickHashes;  // (ticks + 1) compactHash of the latest simulation of each tick
    SessionStats mStats;
    std::string mInjectedField;
    BodyId mInjectedBody;
};

}  // namespace unison::lockstep
