// tests/test_lockstep.cpp — the lockstep sample (samples/lockstep/): rollback sessions exchanging inputs through a
// simulated lagging network end on the hashes of a straight run with the real inputs; the synctest passes and
// catches a deliberate one-bit desync; and real matches (host + 3 peer processes over ENet on 127.0.0.1) agree at
// every checkpoint, match the host's offline replay, and report an injected desync within K ticks with the exact
// body and field.
#include "test_support.h"

#include "process_run.h"
#include "recording.h"
#include "roles.h"
#include "rollback.h"
#include "snapshot_file.h"

#include <cstring>
#include <map>
#include <sstream>

using namespace unison;
using namespace unison::lockstep;

namespace {

/// The inputs every peer ends up using: zero for ticks <= delay (nobody can send them in time), the bots' after.
std::vector<std::vector<PlayerInput>> realInputs(const MatchConfig& match, int ticks, int delay) {
    std::vector<std::vector<PlayerInput>> inputs(std::size_t(ticks), std::vector<PlayerInput>(std::size_t(match.players)));
    for (int t = delay + 1; t <= ticks; ++t)
        for (int p = 0; p < match.players; ++p) inputs[std::size_t(t - 1)][std::size_t(p)] = botInput(match, p, t);
    return inputs;
}

/// State hash after every tick (index tick, [0]: the scene) of a straight simulation with `inputs`.
std::vector<std::uint64_t> straightHashes(const MatchConfig& match, const std::vector<std::vector<PlayerInput>>& inputs) {
    MatchWorld world(match);
    std::vector<std::uint64_t> hashes{world.world().stateHash()};
    for (const auto& frame : inputs) {
        world.tick(frame);
        hashes.push_back(world.world().stateHash());
    }
    return hashes;
}

/// Peers connected by a simulated network: each input reaches each other peer after 0..maxLag rounds (seeded),
/// in tick order per player (the real relay resends until acknowledged, so order and completeness hold there
/// too). Every round each peer reconciles and advances at most one tick, like a peer paced by its clock.
std::vector<std::unique_ptr<RollbackSession>> playOverLaggingNetwork(const MatchConfig& match, SessionConfig config,
                                                                     int maxLag, std::uint64_t seed) {
    std::vector<std::unique_ptr<RollbackSession>> peers;
    for (int p = 0; p < match.players; ++p) {
        config.localPlayer = p;
        peers.push_back(std::make_unique<RollbackSession>(match, config));
    }
    struct InFlight {
        int arrives, player, tick;
        PlayerInput input;
    };
    std::vector<std::vector<InFlight>> inbox(std::size_t(match.players));  // per receiving peer
    std::uint64_t rng = seed;
    auto lag = [&] {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        return int((rng >> 33) % std::uint64_t(maxLag + 1));
    };
    for (int round = 0; round < 100000; ++round) {
        bool allDone = true;
        for (int p = 0; p < match.players; ++p) {
            RollbackSession& s = *peers[std::size_t(p)];
            // Deliver what has arrived, in tick order per player.
            std::vector<InFlight>& box = inbox[std::size_t(p)];
            for (bool progress = true; progress;) {
                progress = false;
                for (std::size_t i = 0; i < box.size(); ++i) {
                    if (box[i].arrives <= round && s.addInput(box[i].player, box[i].tick, box[i].input)) {
                        box.erase(box.begin() + std::ptrdiff_t(i));
                        progress = true;
                        break;
                    }
                }
            }
            s.reconcile();
            const int target = std::min(config.ticks, s.currentTick() + 1 + config.inputDelay);
            for (int t = s.nextLocalTick(); t <= target; t = s.nextLocalTick()) {
                const PlayerInput in = botInput(match, p, t);
                s.setLocalInput(t, in);
                for (int q = 0; q < match.players; ++q)
                    if (q != p) inbox[std::size_t(q)].push_back({round + lag(), p, t, in});
            }
            if (s.canAdvance()) s.advance();
            allDone = allDone && s.finalTick() == config.ticks;
        }
        if (allDone) break;
    }
    return peers;
}

std::string lockstepProgram() { return UNISON_LOCKSTEP_PATH; }

MatchConfig matchOf(int players, int rows) {
    MatchConfig match;
    match.players = players;
    match.rows = rows;
    return match;
}

SessionConfig sessionOf(int ticks, int inputDelay, int maxPrediction, int checkEvery) {
    SessionConfig config;
    config.ticks = ticks;
    config.inputDelay = inputDelay;
    config.maxPrediction = maxPrediction;
    config.checkEvery = checkEvery;
    return config;
}

double parseDouble(const std::string& text) { return std::stod(text); }

std::uint64_t bitsOf(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return bits;
}

}  // namespace

TEST_SUITE("lockstep") {

TEST_CASE("rollback over a lagging network ends on the straight run's hashes at every checkpoint") {
    const MatchConfig match = matchOf(3, 6);
    const SessionConfig config = sessionOf(240, 1, 8, 10);
    const std::vector<std::uint64_t> expected = straightHashes(match, realInputs(match, config.ticks, config.inputDelay));
    const auto peers = playOverLaggingNetwork(match, config, 5, 7);
    int rollbacks = 0;
    for (const auto& peer : peers) {
        REQUIRE(peer->finalTick() == config.ticks);
        for (int c = config.checkEvery; c <= config.ticks; c += config.checkEvery)
            CHECK_MESSAGE(peer->checkpointHash(c) == expected[std::size_t(c)], "checkpoint " << c);
        rollbacks += peer->stats().rollbacks;
        CHECK(peer->stats().maxRollback <= config.maxPrediction);
        CHECK(peer->stats().maxStateBytes > 0);
    }
    CHECK(rollbacks > 0);  // the lag did force predictions that turned out wrong
}

TEST_CASE("lockstep mode never predicts and never rolls back, with the same hashes") {
    const MatchConfig match = matchOf(2, 5);
    const SessionConfig config = sessionOf(150, 2, 0, 15);
    const std::vector<std::uint64_t> expected = straightHashes(match, realInputs(match, config.ticks, config.inputDelay));
    const auto peers = playOverLaggingNetwork(match, config, 4, 11);
    for (const auto& peer : peers) {
        CHECK(peer->stats().predictedTicks == 0);
        CHECK(peer->stats().rollbacks == 0);
        CHECK(peer->checkpointHash(config.ticks) == expected.back());
    }
}

TEST_CASE("a desync injected at tick T changes that tick's compact state and every checkpoint from T on") {
    const MatchConfig match = matchOf(2, 4);
    SessionConfig config = sessionOf(60, 0, 0, 10);
    RollbackSession clean(match, config);
    config.desyncAt = 33;
    RollbackSession broken(match, config);
    for (RollbackSession* s : {&clean, &broken}) {
        for (int t = 1; t <= config.ticks; ++t) {
            for (int p = 0; p < match.players; ++p) s->addInput(p, t, botInput(match, p, t));
            s->advance();
        }
    }
    CHECK(broken.injectedField().rfind("velocity.", 0) == 0);
    CHECK(clean.compactHash(32) == broken.compactHash(32));
    CHECK(clean.compactHash(33) != broken.compactHash(33));
    CHECK(clean.checkpointHash(30) == broken.checkpointHash(30));
    CHECK(clean.windowHash(30) == broken.windowHash(30));
    for (int c = 40; c <= 60; c += 10) CHECK(clean.checkpointHash(c) != broken.checkpointHash(c));
    CHECK(clean.windowHash(40) != broken.windowHash(40));  // ticks 31..40 include the flipped one
    // The snapshots of tick 33 differ in exactly the flipped field, by its last bit.
    const std::vector<std::uint8_t> a = clean.snapshotAt(33), b = broken.snapshotAt(33);
    World2 wa, wb;
    REQUIRE(wa.restore(a.data(), a.size()));
    REQUIRE(wb.restore(b.data(), b.size()));
    const std::vector<FieldDifference> diffs = diffFields(wa.stateFields(), wb.stateFields());
    REQUIRE(diffs.size() == 1);
    CHECK(diffs[0].body == broken.injectedBody());
    CHECK(diffs[0].path == broken.injectedField());
    CHECK((bitsOf(parseDouble(diffs[0].a)) ^ bitsOf(parseDouble(diffs[0].b))) == 1u);
}

TEST_CASE("synctest: passes on the pyramid with players, and names the field of a deliberate desync") {
    SynctestOptions options;
    options.match = matchOf(3, 6);
    options.ticks = 120;
    options.distance = 3;
    std::ostringstream out, err;
    REQUIRE(runSynctest(options, out, err) == 0);
    const nlohmann::json pass = nlohmann::json::parse(out.str());
    CHECK(pass["synctest"] == "pass");
    CHECK(pass["bytes_per_body"]["max"].get<double>() <= 200.0);
    options.desyncAt = 50;
    std::ostringstream out2, err2;
    CHECK(runSynctest(options, out2, err2) == 1);
    const nlohmann::json fail = nlohmann::json::parse(out2.str());
    CHECK(fail["tick"] == 50);  // tick 50's first pass had the flip, its re-simulation from tick 47 has not
    CHECK(fail["report"]["differences"][0]["field"].get<std::string>().rfind("velocity.", 0) == 0);
}

TEST_CASE("a networked match: 3 peer processes agree at every checkpoint and with the host's replay") {
    const std::string rec = test::tempFile("unison_lockstep", "match.urec");
    const test::ProcessRun r =
        test::runProgram(lockstepProgram(), "--peers 3 --ticks 240 --rows 8 --fast --check-every 10 --record " + rec);
    REQUIRE_MESSAGE(r.exitCode == 0, r.err);
    const std::vector<nlohmann::json> lines = r.jsonLines();
    REQUIRE(lines.size() == 4);  // each peer's final hash, then the host's summary
    const nlohmann::json& summary = lines.back();
    CHECK(summary["status"] == "match");
    CHECK(summary["checkpoints_agreed"] == 24);
    CHECK(summary["replay_agrees"] == true);
    for (std::size_t i = 0; i < 3; ++i) CHECK(lines[i]["final_hash"] == summary["final_hash"]);
    // The same inputs simulated here, in this process, give the same final hash.
    const MatchConfig match = matchOf(3, 8);
    CHECK(summary["final_hash"] == replay::hexHash(straightHashes(match, realInputs(match, 240, 3)).back()));
    // The recording the host wrote verifies.
    const replay::Recording recording = replay::parseRecording(replay::readBinaryFile(rec), rec);
    CHECK(replay::verify(recording).match);
    CHECK(replay::hexHash(recording.hashes.back()) == summary["final_hash"]);
    std::remove(rec.c_str());
}

TEST_CASE("a networked match with a desync: reported within K ticks with the exact body and field") {
    const test::ProcessRun r = test::runProgram(lockstepProgram(), "--peers 3 --ticks 240 --rows 8 --fast --check-every 10 --desync-at 97");
    REQUIRE_MESSAGE(r.exitCode == 1, r.err);
    const nlohmann::json report = r.jsonLines().back();
    CHECK(report["status"] == "desync");
    CHECK(report["first_desync_tick"] == 97);
    CHECK(report["checkpoint_tick"] == 100);
    CHECK(report["last_agreed_tick"] == 90);
    CHECK(report["differing_fields"] == 1);
    CHECK(report["peers"] == nlohmann::json::array({0, 2}));
    const nlohmann::json& d = report["differences"][0];
    // The body the desyncing peer flips is the one the same session picks in this process.
    const MatchConfig match = matchOf(3, 8);
    SessionConfig config = sessionOf(97, 3, 0, 10);
    config.desyncAt = 97;
    RollbackSession local(match, config);
    const auto inputs = realInputs(match, 97, 3);
    for (int t = 1; t <= 97; ++t) {
        for (int p = 0; p < match.players; ++p) local.addInput(p, t, inputs[std::size_t(t - 1)][std::size_t(p)]);
        local.advance();
    }
    CHECK(d["body"] == describeBody(local.injectedBody()));
    CHECK(d["field"] == local.injectedField());
    CHECK((bitsOf(parseDouble(d["peer_0"])) ^ bitsOf(parseDouble(d["peer_2"]))) == 1u);
    CHECK(r.err.find("desync at tick 97") != std::string::npos);
}

TEST_CASE("rollback over a simulated bad network (latency, jitter, loss): peers agree, rollbacks happened") {
    const test::ProcessRun r = test::runProgram(
        lockstepProgram(), "--peers 3 --ticks 180 --rows 6 --rollback --latency-ms 30 --jitter-ms 10 --loss 0.1 --net-seed 5");
    REQUIRE_MESSAGE(r.exitCode == 0, r.err);
    const nlohmann::json summary = r.jsonLines().back();
    CHECK(summary["status"] == "match");
    CHECK(summary["replay_agrees"] == true);
    CHECK(summary["net"]["dropped_by_host"].get<int>() > 0);
    int rollbacks = 0;
    for (const nlohmann::json& p : summary["peer_stats"]) rollbacks += p["rollbacks"].get<int>();
    CHECK(rollbacks > 0);
    const MatchConfig match = matchOf(3, 6);
    CHECK(summary["final_hash"] == replay::hexHash(straightHashes(match, realInputs(match, 180, 1)).back()));
}

TEST_CASE("rollback with a desync: found through the window of compact-state hashes, even if it heals") {
    // A one-ulp velocity difference can be lost to rounding within a few ticks (here the state hashes at checkpoint
    // 60 may agree again); the window hash of ticks 41..60 still differs, and the report names tick 55.
    const test::ProcessRun r = test::runProgram(lockstepProgram(), "--peers 3 --ticks 200 --rollback --latency-ms 30 "
                                                "--jitter-ms 10 --loss 0.1 --desync-at 55 --check-every 20");
    REQUIRE_MESSAGE(r.exitCode == 1, r.err);
    const nlohmann::json report = r.jsonLines().back();
    CHECK(report["first_desync_tick"] == 55);
    CHECK(report["checkpoint_tick"] == 60);
    CHECK(report["differing_fields"] == 1);
    CHECK(report["differences"][0]["field"].get<std::string>().rfind("velocity.", 0) == 0);
    MESSAGE("state hashes at checkpoint 60 agree again: " << (report["checkpoint_hashes"]["peer_0"] == report["checkpoint_hashes"]["peer_2"]));
}

TEST_CASE("bad settings exit 2") {
    CHECK(test::runProgram(lockstepProgram(), "--peers 0").exitCode == 2);
    CHECK(test::runProgram(lockstepProgram(), "--peers 2 --desync-peer 5").exitCode == 2);
    CHECK(test::runProgram(lockstepProgram(), "--loss 2").exitCode == 2);
}

}  // TEST_SUITE
