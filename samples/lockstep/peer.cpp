// samples/lockstep/peer.cpp — one peer of a networked match (see roles.h): receives the settings, makes its bot's
// inputs, sends them to the host, simulates with the inputs the host relays (rollback.h), reports checkpoint
// hashes, and answers the host's questions about its past states when a desync is being located.
#include "roles.h"

#include "recording.h"

#include <algorithm>
#include <chrono>
#include <ostream>

namespace unison::lockstep {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr int kMaxRun = 64;            // inputs per message at most
constexpr double kResendMs = 8.0;      // resend unacknowledged inputs this often
constexpr double kSilenceMs = 20000.0;  // give up when the host is silent this long

/// Waits for the welcome and the start. False on timeout or disconnection.
bool joinMatch(Endpoint& ep, Welcome* welcome, std::ostream& err) {
    bool haveWelcome = false;
    const Clock::time_point begin = Clock::now();
    std::vector<NetEvent> events;
    while (msSince(begin) < kSilenceMs) {
        events.clear();
        ep.poll(10, events);
        for (const NetEvent& e : events) {
            if (e.type == NetEvent::Type::disconnected) {
                err << "peer: the host closed the connection before the start\n";
                return false;
            }
            Message m;
            if (e.type != NetEvent::Type::received || !decodeMessage(e.bytes, &m, nullptr)) continue;
            if (m.type == MessageType::welcome) {
                *welcome = m.welcome;
                haveWelcome = true;
            } else if (m.type == MessageType::start && haveWelcome) {
                return true;
            }
        }
    }
    err << "peer: no start from the host\n";
    return false;
}

}  // namespace

int runPeer(const std::string& host, int port, int wantedPlayer, std::ostream& out, std::ostream& err) {
    std::string error;
    std::unique_ptr<Endpoint> ep = Endpoint::connect(host, port, 5000, &error);
    if (!ep) {
        err << "peer: " << error << "\n";
        return 3;
    }
    ep->send(0, encodeHello(wantedPlayer), true);
    Welcome w;
    if (!joinMatch(*ep, &w, err)) return 3;
    ep->setConditions(0, w.net);
    const int me = w.session.localPlayer;
    const int ticks = w.session.ticks;
    RollbackSession session(w.match, w.session);
    const Clock::time_point start = Clock::now();
    Clock::time_point lastHeard = start, lastSend = start - std::chrono::hours(1);
    int hostHas = std::min(w.session.inputDelay, ticks);  // last tick of my inputs the host has
    std::vector<int> sentAcks;
    int hashesUpTo = 0;
    bool doneSent = false, stopped = false, stalled = false;
    double stalledMs = 0.0;
    Clock::time_point stallStart = start;
    std::vector<NetEvent> events;
    while (!stopped) {
        // Sleep until the next tick is due (or 1 ms), waking up for traffic.
        int wait = session.canAdvance() && !w.realtime ? 0 : 1;
        events.clear();
        ep->poll(wait, events);
        for (const NetEvent& e : events) {
            if (e.type == NetEvent::Type::disconnected) {
                err << "peer " << me << ": the host closed the connection\n";
                return 3;
            }
            Message m;
            if (e.type != NetEvent::Type::received || !decodeMessage(e.bytes, &m, &error)) continue;
            lastHeard = Clock::now();
            switch (m.type) {
                case MessageType::relay:
                    hostHas = std::max(hostHas, m.ack);
                    for (const InputRun& run : m.runs)
                        for (std::size_t i = 0; i < run.inputs.size(); ++i)
                            session.addInput(run.player, run.first + int(i), run.inputs[i]);
                    break;
                case MessageType::checkOk: session.dropBefore(m.tick); break;
                case MessageType::queryHashes: {
                    std::vector<std::uint64_t> hashes;
                    const int from = std::max(m.from, 0);
                    for (int t = from; t <= std::min(m.to, session.finalTick()); ++t) hashes.push_back(session.compactHash(t));
                    ep->send(0, encodeHashes(from, hashes), true);
                    break;
                }
                case MessageType::querySnapshot:
                    if (m.tick >= session.oldestKept() && m.tick <= session.finalTick())
                        ep->send(0, encodeSnapshot(m.tick, session.snapshotAt(m.tick)), true);
                    break;
                case MessageType::stop: stopped = true; break;
                default: break;
            }
        }
        if (msSince(lastHeard) > kSilenceMs) {
            err << "peer " << me << ": the host has been silent for " << kSilenceMs / 1000 << " s\n";
            return 3;
        }
        session.reconcile();
        bool newInputs = false;
        while (session.currentTick() < ticks) {
            // Tick t + 1 is due 1/hz after tick t (realtime); its local input is made now, for tick t + 1 + delay.
            if (w.realtime && msSince(start) < 1000.0 * session.currentTick() / w.hz) break;
            const int target = std::min(ticks, session.currentTick() + 1 + w.session.inputDelay);
            for (int t = session.nextLocalTick(); t <= target; t = session.nextLocalTick()) {
                session.setLocalInput(t, botInput(w.match, me, t));
                newInputs = true;
            }
            if (!session.canAdvance()) {
                // A due tick that cannot run yet: the match stalls here (counted in realtime only).
                if (w.realtime && !stalled) stallStart = Clock::now();
                stalled = w.realtime;
                break;
            }
            if (stalled) stalledMs += msSince(stallStart);
            stalled = false;
            session.advance();
        }
        // My inputs the host lacks, and what I have of everyone's.
        std::vector<int> acks;
        for (int p = 0; p < w.match.players; ++p) acks.push_back(session.confirmedUpTo(p));
        const int mine = session.nextLocalTick() - 1;
        if (newInputs || acks != sentAcks || (mine > hostHas && msSince(lastSend) >= kResendMs)) {
            InputRun run{me, hostHas + 1, {}};
            for (int t = hostHas + 1; t <= mine && int(run.inputs.size()) < kMaxRun; ++t) run.inputs.push_back(session.input(me, t));
            ep->send(0, encodeInputs(acks, run), false);
            sentAcks = acks;
            lastSend = Clock::now();
        }
        const int settled = session.finalTick();
        for (int c = hashesUpTo + 1; c <= settled; ++c)
            if (session.isCheckpoint(c)) ep->send(0, encodeHash(c, session.checkpointHash(c), session.windowHash(c)), true);
        hashesUpTo = std::max(hashesUpTo, settled);
        if (!doneSent && settled == ticks) {
            PeerDone d{ticks, session.checkpointHash(ticks), session.stats(), ep->dropped(), stalledMs};
            ep->send(0, encodeDone(d), true);
            doneSent = true;
            out << nlohmann::json{{"peer", me}, {"ticks", ticks}, {"final_hash", replay::hexHash(d.finalHash)}}.dump() << std::endl;
        }
    }
    ep->disconnectAll(1000);
    return 0;
}

}  // namespace unison::lockstep
