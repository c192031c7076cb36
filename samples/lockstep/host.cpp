// samples/lockstep/host.cpp — the host of a networked match (see roles.h).
//
// The host does not simulate during the match: it relays every peer's inputs to the others, compares what the
// peers report at each checkpoint (the state hash, and a hash of every tick's compact-state hash since the previous
// checkpoint, so a difference that vanished again before the checkpoint is caught too), and at the end checks the agreed hashes against its own offline
// replay of the inputs it relayed (replay::record). When the hashes of a checkpoint differ it locates the desync:
// it asks one peer of the majority and one that differs for the compact-state hash of every tick since the last
// agreed checkpoint, takes the first tick where they differ, fetches both peers' full snapshots of that tick and
// reports their field-by-field difference (replay/desync_report.h).
#include "roles.h"

#include "desync_report.h"
#include "recording.h"
#include "snapshot_file.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <ostream>
#include <thread>

extern char** environ;

namespace unison::lockstep {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

constexpr int kMaxRun = 64;
constexpr double kRelayEveryMs = 4.0;
constexpr std::size_t kReportedDifferences = 50;

std::uint64_t linkSeed(std::uint64_t seed, int player, bool toPeer) {
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + std::uint64_t(player) * 2 + (toPeer ? 1 : 0);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    return z ^ (z >> 31);
}

/// Starts `count` peers of this program; returns their process ids (0 for one that failed to start).
std::vector<pid_t> spawnPeers(const std::string& program, int port, int count, std::ostream& err) {
    std::vector<pid_t> pids;
    for (int p = 0; p < count; ++p) {
        std::vector<std::string> args = {program, "--connect", "127.0.0.1", "--port", std::to_string(port),
                                         "--player", std::to_string(p)};
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_t pid = 0;
        if (posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
            err << "host: cannot start peer " << p << " (" << program << ")\n";
            pid = 0;
        }
        pids.push_back(pid);
    }
    return pids;
}

/// Waits for the peers to exit (up to `seconds`), then ends those still running.
void reapPeers(std::vector<pid_t>& pids, double seconds) {
    const Clock::time_point begin = Clock::now();
    for (pid_t& pid : pids) {
        while (pid > 0) {
            int status = 0;
            const pid_t r = waitpid(pid, &status, WNOHANG);
            if (r == pid || r < 0) {
                pid = 0;
            } else if (secondsSince(begin) > seconds) {
                kill(pid, SIGTERM);
                waitpid(pid, &status, 0);
                pid = 0;
            } else {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
        }
    }
}

/// What a peer reports at a checkpoint: the state hash and the window hash (RollbackSession::windowHash).
using Checkpoint = std::pair<std::uint64_t, std::uint64_t>;

/// The match as the host sees it: who is who, the inputs relayed so far, the hashes reported.
struct HostState {
    int players = 0;
    std::vector<int> playerOf;                   // connection -> player (-1: not joined)
    std::vector<int> connectionOf;               // player -> connection
    std::vector<std::vector<PlayerInput>> inputs;  // player -> inputs of ticks 1..known (index tick - 1)
    std::vector<std::vector<int>> has;           // [peer][player]: last tick of player's inputs peer has
    std::vector<bool> fresh;                     // player sent new inputs since the last relay
    std::map<int, std::vector<Checkpoint>> hashes;  // checkpoint tick -> per player ({0, 0}: not reported yet)
    int agreedUpTo = 0;                          // last checkpoint every peer agreed on
    std::vector<std::pair<int, std::uint64_t>> agreed;  // (tick, hash) of each agreed checkpoint
    std::vector<bool> doneReceived;
    std::vector<PeerDone> done;
    int known(int p) const { return int(inputs[std::size_t(p)].size()); }
};

/// Locating a desync: the two peers compared and what they answered.
struct Investigation {
    bool active = false;
    int checkpoint = 0, a = -1, b = -1;
    std::uint64_t hashA = 0, hashB = 0;
    std::vector<std::uint64_t> listA, listB;
    int fromA = 0, fromB = 0;
    bool haveA = false, haveB = false;
    int tick = -1;
    std::vector<std::uint8_t> snapA, snapB;
    bool snapshotsAsked = false;
};

}  // namespace

int runHost(const HostOptions& options, std::ostream& out, std::ostream& err) {
    const Welcome& settings = options.settings;
    const int players = settings.match.players;
    const int ticks = settings.session.ticks;
    const int delay = std::min(settings.session.inputDelay, ticks);
    std::string error;
    std::unique_ptr<Endpoint> ep = Endpoint::listen(options.port, players, &error);
    if (!ep) {
        err << "host: " << error << "\n";
        return 3;
    }
    err << "host: listening on 127.0.0.1:" << ep->port() << " for " << players << " peers\n";
    std::vector<pid_t> pids;
    if (options.spawnPeers) pids = spawnPeers(options.program, ep->port(), players, err);
    const Clock::time_point begin = Clock::now();
    auto fail = [&](const std::string& why) {
        err << "host: " << why << "\n";
        for (int c = 0; c < players; ++c) ep->send(c, encodeSimple(MessageType::stop), true);
        ep->disconnectAll(1000);
        reapPeers(pids, 3.0);
        return 3;
    };

    HostState st;
    st.players = players;
    st.connectionOf.assign(std::size_t(players), -1);
    st.inputs.assign(std::size_t(players), std::vector<PlayerInput>(std::size_t(delay)));  // ticks 1..delay: zero
    st.has.assign(std::size_t(players), std::vector<int>(std::size_t(players), delay));
    st.fresh.assign(std::size_t(players), false);
    st.doneReceived.assign(std::size_t(players), false);
    st.done.resize(std::size_t(players));
    std::vector<NetEvent> events;

    // ---- Lobby: every peer says hello, gets its player and the settings, then everyone starts. ----
    int joined = 0;
    while (joined < players) {
        if (secondsSince(begin) > 30.0) return fail("only " + std::to_string(joined) + " of " + std::to_string(players) + " peers joined");
        events.clear();
        ep->poll(10, events);
        for (const NetEvent& e : events) {
            if (e.connection >= int(st.playerOf.size())) st.playerOf.resize(std::size_t(e.connection) + 1, -1);
            Message m;
            if (e.type != NetEvent::Type::received || !decodeMessage(e.bytes, &m, nullptr) || m.type != MessageType::hello)
                continue;
            if (m.version != kProtocolVersion || st.playerOf[std::size_t(e.connection)] >= 0) continue;
            int p = m.wantedPlayer;
            if (p < 0 || p >= players || st.connectionOf[std::size_t(p)] >= 0) {
                p = 0;
                while (p < players && st.connectionOf[std::size_t(p)] >= 0) ++p;
            }
            if (p >= players) continue;
            st.playerOf[std::size_t(e.connection)] = p;
            st.connectionOf[std::size_t(p)] = e.connection;
            ++joined;
        }
    }
    const int desyncPeer = options.desyncPeer >= 0 ? options.desyncPeer : players - 1;
    for (int p = 0; p < players; ++p) {
        Welcome w = settings;
        w.session.localPlayer = p;
        w.session.desyncAt = p == desyncPeer ? settings.session.desyncAt : -1;
        w.net.seed = linkSeed(settings.net.seed, p, false);
        NetConditions down = settings.net;
        down.seed = linkSeed(settings.net.seed, p, true);
        ep->setConditions(st.connectionOf[std::size_t(p)], down);
        ep->send(st.connectionOf[std::size_t(p)], encodeWelcome(w), true);
    }
    for (int p = 0; p < players; ++p) ep->send(st.connectionOf[std::size_t(p)], encodeSimple(MessageType::start), true);
    const Clock::time_point matchStart = Clock::now();

    // ---- The match: relay inputs, compare checkpoints, locate a desync. ----
    Investigation inv;
    nlohmann::json report;
    Clock::time_point lastRelay = Clock::now();
    std::vector<int> lastAckSent(std::size_t(players), -1);
    bool finished = false;
    while (!finished) {
        if (secondsSince(begin) > options.timeoutSeconds) return fail("timed out");
        events.clear();
        ep->poll(1, events);
        for (const NetEvent& e : events) {
            const int p = e.connection >= 0 && e.connection < int(st.playerOf.size()) ? st.playerOf[std::size_t(e.connection)] : -1;
            if (p < 0) continue;
            if (e.type == NetEvent::Type::disconnected) return fail("peer " + std::to_string(p) + " left the match");
            Message m;
            if (e.type != NetEvent::Type::received || !decodeMessage(e.bytes, &m, &error)) continue;
            switch (m.type) {
                case MessageType::inputs: {
                    for (int q = 0; q < players && q < int(m.acks.size()); ++q)
                        st.has[std::size_t(p)][std::size_t(q)] = std::max(st.has[std::size_t(p)][std::size_t(q)], m.acks[std::size_t(q)]);
                    const InputRun& run = m.runs.front();
                    for (std::size_t i = 0; i < run.inputs.size(); ++i) {
                        if (run.first + int(i) != st.known(p) + 1 || st.known(p) >= ticks) continue;
                        st.inputs[std::size_t(p)].push_back(run.inputs[i]);
                        st.fresh[std::size_t(p)] = true;
                    }
                    break;
                }
                case MessageType::hash: {
                    std::vector<Checkpoint>& h = st.hashes[m.tick];
                    h.resize(std::size_t(players), Checkpoint{0, 0});
                    h[std::size_t(p)] = {m.hash, m.window};
                    break;
                }
                case MessageType::hashes:
                    if (p == inv.a) {
                        inv.listA = m.hashList;
                        inv.fromA = m.from;
                        inv.haveA = true;
                    }
                    if (p == inv.b) {
                        inv.listB = m.hashList;
                        inv.fromB = m.from;
                        inv.haveB = true;
                    }
                    break;
                case MessageType::snapshot:
                    if (p == inv.a && m.tick == inv.tick) inv.snapA = m.bytes;
                    if (p == inv.b && m.tick == inv.tick) inv.snapB = m.bytes;
                    break;
                case MessageType::done:
                    st.doneReceived[std::size_t(p)] = true;
                    st.done[std::size_t(p)] = m.done;
                    break;
                default: break;
            }
        }
        // Relay: every peer gets the inputs of the others it has not acknowledged, and the host's acknowledgement.
        bool anyFresh = false;
        for (bool f : st.fresh) anyFresh = anyFresh || f;
        if (anyFresh || secondsSince(lastRelay) * 1000.0 >= kRelayEveryMs) {
            for (int r = 0; r < players; ++r) {
                std::vector<InputRun> runs;
                for (int q = 0; q < players; ++q) {
                    if (q == r) continue;
                    const int from = st.has[std::size_t(r)][std::size_t(q)] + 1;
                    InputRun run{q, from, {}};
                    for (int t = from; t <= st.known(q) && int(run.inputs.size()) < kMaxRun; ++t)
                        run.inputs.push_back(st.inputs[std::size_t(q)][std::size_t(t - 1)]);
                    if (!run.inputs.empty()) runs.push_back(std::move(run));
                }
                if (runs.empty() && lastAckSent[std::size_t(r)] == st.known(r)) continue;
                ep->send(st.connectionOf[std::size_t(r)], encodeRelay(st.known(r), runs), false);
                lastAckSent[std::size_t(r)] = st.known(r);
            }
            std::fill(st.fresh.begin(), st.fresh.end(), false);
            lastRelay = Clock::now();
        }
        // Checkpoints in tick order, once every peer has reported.
        while (!inv.active && !st.hashes.empty()) {
            const auto it = st.hashes.begin();
            if (std::count(it->second.begin(), it->second.end(), Checkpoint{0, 0}) > 0) break;
            const std::vector<Checkpoint> h = it->second;
            const int tick = it->first;
            st.hashes.erase(it);
            if (std::count(h.begin(), h.end(), h.front()) == players) {
                st.agreedUpTo = tick;
                st.agreed.push_back({tick, h.front().first});
                for (int q = 0; q < players; ++q) ep->send(st.connectionOf[std::size_t(q)], encodeTick(MessageType::checkOk, tick), true);
                continue;
            }
            // The majority hash (ties: the lowest player's) and the lowest player that differs from it.
            int a = 0;
            for (int q = 0; q < players; ++q)
                if (std::count(h.begin(), h.end(), h[std::size_t(q)]) > std::count(h.begin(), h.end(), h[std::size_t(a)])) a = q;
            int b = 0;
            while (h[std::size_t(b)] == h[std::size_t(a)]) ++b;
            inv = Investigation{};
            inv.active = true;
            inv.checkpoint = tick;
            inv.a = a;
            inv.b = b;
            inv.hashA = h[std::size_t(a)].first;
            inv.hashB = h[std::size_t(b)].first;
            err << "host: checkpoint " << tick << ": peer " << b << " disagrees with peer " << a << "; locating the desync\n";
            for (int q : {a, b}) ep->send(st.connectionOf[std::size_t(q)], encodeQueryHashes(st.agreedUpTo, tick), true);
        }
        if (inv.active && inv.haveA && inv.haveB && !inv.snapshotsAsked) {
            inv.tick = inv.checkpoint;  // no differing compact state: compare the checkpoint itself
            for (int t = std::max(inv.fromA, inv.fromB); t <= inv.checkpoint; ++t) {
                const std::size_t ia = std::size_t(t - inv.fromA), ib = std::size_t(t - inv.fromB);
                if (ia < inv.listA.size() && ib < inv.listB.size() && inv.listA[ia] != inv.listB[ib]) {
                    inv.tick = t;
                    break;
                }
            }
            for (int q : {inv.a, inv.b}) ep->send(st.connectionOf[std::size_t(q)], encodeTick(MessageType::querySnapshot, inv.tick), true);
            inv.snapshotsAsked = true;
        }
        if (inv.active && !inv.snapA.empty() && !inv.snapB.empty()) {
            const MatchWorld numbering(settings.match);
            const std::string nameA = "peer_" + std::to_string(inv.a), nameB = "peer_" + std::to_string(inv.b);
            report = replay::snapshotDesyncReport(
                inv.tick, inv.snapA, inv.snapB, nameA, nameB,
                [&](BodyId id) {
                    const std::vector<BodyId>& ids = numbering.bodies();
                    const auto it = std::find(ids.begin(), ids.end(), id);
                    return it == ids.end() ? -1 : int(it - ids.begin());
                },
                kReportedDifferences);
            report["status"] = "desync";
            report["checkpoint_tick"] = inv.checkpoint;
            report["last_agreed_tick"] = st.agreedUpTo;
            report["peers"] = {inv.a, inv.b};
            report["checkpoint_hashes"] = {{nameA, replay::hexHash(inv.hashA)}, {nameB, replay::hexHash(inv.hashB)}};
            finished = true;
        }
        bool allDone = true;
        for (bool d : st.doneReceived) allDone = allDone && d;
        if (!inv.active && allDone && st.agreedUpTo == ticks) finished = true;
    }
    const double matchSeconds = secondsSince(matchStart);
    for (int q = 0; q < players; ++q) ep->send(st.connectionOf[std::size_t(q)], encodeSimple(MessageType::stop), true);
    ep->disconnectAll(2000);
    reapPeers(pids, 5.0);

    // ---- Offline referee: the host replays the inputs it relayed and checks the agreed hashes. ----
    int replayable = ticks;
    for (int p = 0; p < players; ++p) replayable = std::min(replayable, st.known(p));
    std::vector<std::vector<PlayerInput>> frames(std::size_t(replayable), std::vector<PlayerInput>(std::size_t(players), PlayerInput{}));
    for (int t = 0; t < replayable; ++t)
        for (int p = 0; p < players; ++p) frames[std::size_t(t)][std::size_t(p)] = st.inputs[std::size_t(p)][std::size_t(t)];
    const replay::Recording rec = replay::record(matchScene(settings.match), toInputScript(settings.match, frames), replayable,
                                                 settings.session.checkEvery);
    bool replayAgrees = true;
    for (const auto& [tick, hash] : st.agreed) replayAgrees = replayAgrees && rec.hashes[std::size_t(tick)] == hash;
    if (!options.recordFile.empty()) replay::writeFileAtomic(options.recordFile, replay::serializeRecording(rec));

    nlohmann::json summary = {{"peers", players},
                              {"ticks", ticks},
                              {"mode", settings.session.maxPrediction > 0 ? "rollback" : "lockstep"},
                              {"input_delay", settings.session.inputDelay},
                              {"check_every", settings.session.checkEvery},
                              {"checkpoints_agreed", st.agreed.size()},
                              {"replay_agrees", replayAgrees},
                              {"match_seconds", matchSeconds},
                              {"net", {{"latency_ms", settings.net.latencyMs}, {"jitter_ms", settings.net.jitterMs},
                                       {"loss", settings.net.loss}, {"seed", settings.net.seed}, {"dropped_by_host", ep->dropped()}}}};
    if (!inv.active) {
        summary["status"] = "match";
        summary["final_hash"] = replay::hexHash(st.agreed.empty() ? 0 : st.agreed.back().second);
        nlohmann::json stats = nlohmann::json::array();
        for (int p = 0; p < players; ++p) {
            const SessionStats& s = st.done[std::size_t(p)].stats;
            stats.push_back({{"peer", p},
                             {"final_hash", replay::hexHash(st.done[std::size_t(p)].finalHash)},
                             {"rollbacks", s.rollbacks},
                             {"resimulated_ticks", s.resimulatedTicks},
                             {"max_rollback", s.maxRollback},
                             {"predicted_ticks", s.predictedTicks},
                             {"mispredictions", s.mispredictions},
                             {"dropped", st.done[std::size_t(p)].dropped},
                             {"stalled_ms", st.done[std::size_t(p)].stalledMs},
                             {"step_us", s.steps ? s.stepUs / s.steps : 0.0},
                             {"save_us", s.saves ? s.saveUs / s.saves : 0.0},
                             {"restore_us", s.restores ? s.restoreUs / s.restores : 0.0},
                             {"max_state_bytes", s.maxStateBytes}});
        }
        summary["peer_stats"] = stats;
        out << summary.dump() << std::endl;
        return replayAgrees ? 0 : 1;
    }
    report["match"] = summary;
    if (!options.reportFile.empty()) replay::writeJsonFile(options.reportFile, report);
    out << report.dump() << std::endl;
    err << "host: " << replay::desyncSummary(report) << "\n";
    return 1;
}

}  // namespace unison::lockstep
