// samples/lockstep/rollback.cpp — prediction, rollback and checkpoints of one peer (see rollback.h).
#include "rollback.h"

#include "state_io.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace unison::lockstep {
namespace {

using Clock = std::chrono::steady_clock;

double microsecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

constexpr int kNoRollback = 1 << 30;

}  // namespace

RollbackSession::RollbackSession(const MatchConfig& match, const SessionConfig& config)
    : mMatchConfig(match), mConfig(config), mMatch(match) {
    if (match.players < 1 || config.localPlayer < 0 || config.localPlayer >= match.players || config.ticks < 1 ||
        config.inputDelay < 0 || config.maxPrediction < 0 || config.checkEvery < 1)
        throw std::invalid_argument("rollback session: settings out of range");
    const std::size_t players = std::size_t(match.players);
    mInputs.assign(std::size_t(config.ticks) + 1, std::vector<PlayerInput>(players));
    mUsed = mInputs;
    mConfirmed.assign(players, std::min(config.inputDelay, config.ticks));  // ticks 1..inputDelay: zero inputs
    mStates.resize(64);
    mRollbackFrom = kNoRollback;
    mMatch.world().saveCompact(slot(0));
    mTickHashes.assign(std::size_t(config.ticks) + 1, 0);
    mTickHashes[0] = hash64(slot(0).data(), slot(0).size());
}

void RollbackSession::setLocalInput(int tick, PlayerInput input) {
    if (!addInput(mConfig.localPlayer, tick, input))
        throw std::logic_error("rollback session: local inputs must be made in tick order");
}

bool RollbackSession::addInput(int player, int tick, PlayerInput input) {
    if (player < 0 || player >= mMatchConfig.players || tick > mConfig.ticks) return false;
    int& known = mConfirmed[std::size_t(player)];
    if (tick != known + 1) return false;
    mInputs[std::size_t(tick)][std::size_t(player)] = input;
    known = tick;
    if (tick <= mTick && mUsed[std::size_t(tick)][std::size_t(player)] != input) {
        mRollbackFrom = std::min(mRollbackFrom, tick);
        ++mStats.mispredictions;
    }
    return true;
}

bool RollbackSession::canAdvance() const {
    const int next = mTick + 1;
    if (next > mConfig.ticks) return false;
    const int oldestKnown = *std::min_element(mConfirmed.begin(), mConfirmed.end());
    return mConfig.maxPrediction == 0 ? oldestKnown >= next : next - oldestKnown <= mConfig.maxPrediction;
}

void RollbackSession::advance() {
    reconcile();
    const int next = mTick + 1;
    bool predicted = false;
    for (int known : mConfirmed) predicted = predicted || known < next;
    if (predicted) ++mStats.predictedTicks;
    simulate(next);
    mTick = next;
}

int RollbackSession::reconcile() {
    if (mRollbackFrom > mTick) {
        mRollbackFrom = kNoRollback;
        return 0;
    }
    const int from = mRollbackFrom;
    mRollbackFrom = kNoRollback;
    restoreTick(from - 1);
    for (int t = from; t <= mTick; ++t) simulate(t);
    const int count = mTick - from + 1;
    ++mStats.rollbacks;
    mStats.resimulatedTicks += count;
    mStats.maxRollback = std::max(mStats.maxRollback, count);
    return count;
}

int RollbackSession::finalTick() const {
    int last = std::min(mTick, *std::min_element(mConfirmed.begin(), mConfirmed.end()));
    if (mRollbackFrom <= mTick) last = std::min(last, mRollbackFrom - 1);
    return last;
}

std::uint64_t RollbackSession::checkpointHash(int tick) const {
    const auto it = mCheckpoints.find(tick);
    return it == mCheckpoints.end() ? 0 : it->second;
}

void RollbackSession::dropBefore(int tick) { mBase = std::max(mBase, std::min(tick, finalTick())); }

std::uint64_t RollbackSession::compactHash(int tick) const {
    if (tick < 0 || tick > mTick) throw std::out_of_range("rollback session: tick " + std::to_string(tick) + " not simulated");
    return mTickHashes[std::size_t(tick)];
}

std::uint64_t RollbackSession::windowHash(int tick) const {
    ByteWriter w;
    for (int t = (tick - 1) / mConfig.checkEvery * mConfig.checkEvery + 1; t <= tick; ++t) w.u64(compactHash(t));
    return hash64(w.data().data(), w.data().size());
}

std::vector<std::uint8_t> RollbackSession::snapshotAt(int tick) {
    if (tick < mBase || tick > mTick) throw std::out_of_range("rollback session: tick " + std::to_string(tick) + " not kept");
    World2& world = mMatch.world();
    std::string error;
    if (!world.restoreCompact(slot(tick).data(), slot(tick).size(), &error)) throw std::runtime_error(error);
    std::vector<std::uint8_t> bytes = world.snapshot();
    if (!world.restoreCompact(slot(mTick).data(), slot(mTick).size(), &error)) throw std::runtime_error(error);
    return bytes;
}

void RollbackSession::simulate(int tick) {
    std::vector<PlayerInput>& used = mUsed[std::size_t(tick)];
    for (int p = 0; p < mMatchConfig.players; ++p)
        used[std::size_t(p)] = mConfirmed[std::size_t(p)] >= tick ? mInputs[std::size_t(tick)][std::size_t(p)]
                                                                   : bestGuess(p);
    Clock::time_point start = Clock::now();
    mMatch.tick(used);
    mStats.stepUs += microsecondsSince(start);
    ++mStats.steps;
    if (tick == mConfig.desyncAt) {
        const auto [body, field] = flipVelocityBit(mMatch.world());
        mInjectedBody = body;
        mInjectedField = field;
    }
    if (std::size_t(tick - mBase) >= mStates.size()) {  // grow the ring, keeping every kept state at its tick
        std::vector<CompactState> bigger(mStates.size() * 2);
        for (int t = mBase; t < tick; ++t) bigger[std::size_t(t) % bigger.size()] = std::move(slot(t));
        mStates.swap(bigger);
    }
    start = Clock::now();
    mMatch.world().saveCompact(slot(tick));
    mStats.saveUs += microsecondsSince(start);
    ++mStats.saves;
    mStats.maxStateBytes = std::max(mStats.maxStateBytes, slot(tick).size());
    mTickHashes[std::size_t(tick)] = hash64(slot(tick).data(), slot(tick).size());
    if (isCheckpoint(tick)) mCheckpoints[tick] = mMatch.world().stateHash();
}

void RollbackSession::restoreTick(int tick) {
    const Clock::time_point start = Clock::now();
    std::string error;
    if (!mMatch.world().restoreCompact(slot(tick).data(), slot(tick).size(), &error))
        throw std::runtime_error("rollback to tick " + std::to_string(tick) + ": " + error);
    mStats.restoreUs += microsecondsSince(start);
    ++mStats.restores;
}

PlayerInput RollbackSession::bestGuess(int player) const {
    const int known = mConfirmed[std::size_t(player)];
    return known >= 1 ? mInputs[std::size_t(known)][std::size_t(player)] : PlayerInput{};
}

}  // namespace unison::lockstep
