// samples/lockstep/main.cpp — `lockstep`: a networked match of the 2D world over ENet on 127.0.0.1.
//
//   lockstep --peers 3 --ticks 600                  host + 3 peer processes, lockstep; exit 0 when all agree
//   lockstep --peers 3 --ticks 600 --desync-at 200  one peer flips a velocity bit: desync report, exit 1
//   lockstep --rollback --latency-ms 40 --jitter-ms 10 --loss 0.05   rollback over a bad simulated network
//   lockstep --synctest --rows 20 --players 0       save/advance/restore/re-advance every tick, with costs
//   lockstep --connect 127.0.0.1 --port P --player I  one peer (the host starts these itself unless --no-spawn)
// JSON goes to stdout (each peer's final hash, then the host's summary or desync report); progress to stderr.
// Exit codes: 0 agreement, 1 desync, 2 bad settings, 3 network failure or timeout.
#include "fp_env.h"
#include "roles.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <unistd.h>

int main(int argc, char** argv) {
    using namespace unison::lockstep;
    CLI::App app{"lockstep — a networked match of the deterministic 2D world (ENet on 127.0.0.1)"};
    HostOptions host;
    Welcome& w = host.settings;
    w.session.inputDelay = -1;  // chosen by mode below unless given
    int players = -1;
    bool rollback = false, fast = false, noSpawn = false, synctest = false;
    int distance = 1;
    std::string connect;
    int peerPlayer = -1;
    app.add_option("--peers", w.match.players, "number of peers, one player ball each (default 3)")->check(CLI::Range(1, 16));
    app.add_option("--ticks", w.session.ticks, "ticks of the match at 60 Hz (default 600)")->check(CLI::Range(1, 1000000));
    app.add_option("--rows", w.match.rows, "rows of the pyramid (default 10)")->check(CLI::Range(0, 40));
    app.add_option("--seed", w.match.seed, "seed of the bots' inputs (default 1)");
    app.add_option("--input-delay", w.session.inputDelay, "ticks between making an input and its tick (default 3, rollback 1)")
        ->check(CLI::Range(0, 60));
    app.add_option("--check-every", w.session.checkEvery, "K: compare state hashes every K ticks (default 10)")
        ->check(CLI::Range(1, 100000));
    app.add_option("--desync-at", w.session.desyncAt, "one peer flips the last bit of a body's velocity after this tick")
        ->check(CLI::Range(1, 1000000));
    app.add_option("--desync-peer", host.desyncPeer, "the peer that desyncs (default the last)")->check(CLI::Range(0, 15));
    app.add_flag("--rollback", rollback, "predict missing inputs and roll back when they arrive (else lockstep)");
    app.add_option("--max-prediction", w.session.maxPrediction, "rollback: ticks ahead of a missing input (default 8)")
        ->check(CLI::Range(1, 120));
    app.add_option("--latency-ms", w.net.latencyMs, "simulated one-way latency (ms)")->check(CLI::Range(0.0, 2000.0));
    app.add_option("--jitter-ms", w.net.jitterMs, "simulated jitter: latency varies by +- this (ms)")->check(CLI::Range(0.0, 2000.0));
    app.add_option("--loss", w.net.loss, "probability of losing an input message")->check(CLI::Range(0.0, 0.9));
    app.add_option("--net-seed", w.net.seed, "seed of the simulated network (default 1)");
    app.add_flag("--fast", fast, "do not pace ticks at 60 Hz: run as fast as the inputs arrive");
    app.add_option("--port", host.port, "host port on 127.0.0.1 (default: any free port)")->check(CLI::Range(0, 65535));
    app.add_flag("--no-spawn", noSpawn, "do not start the peers (run them with --connect)");
    app.add_option("--record", host.recordFile, "write the match as a recording (.urec) for `unison verify` / `unison view`");
    app.add_option("--report", host.reportFile, "write the desync report (JSON) here");
    app.add_option("--timeout", host.timeoutSeconds, "give up after this many seconds (default 120)")->check(CLI::PositiveNumber);
    app.add_flag("--synctest", synctest, "no network: save, advance, restore, advance again and compare, every tick");
    app.add_option("--players", players, "synctest: player balls (default 3; 0: the plain pyramid)")->check(CLI::Range(0, 16));
    app.add_option("--distance", distance, "synctest: roll back this many ticks every tick (default 1)")->check(CLI::Range(1, 120));
    app.add_option("--connect", connect, "run one peer of the match hosted at this address");
    app.add_option("--player", peerPlayer, "peer: the player index to ask for")->check(CLI::Range(0, 15));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    const std::string env = unison::checkFloatingPointEnvironment();
    if (!env.empty()) {
        std::cerr << "error: " << env << "\n";
        return 2;
    }
    try {
        if (!connect.empty()) return runPeer(connect, host.port, peerPlayer, std::cout, std::cerr);
        if (synctest) {
            SynctestOptions s;
            s.match = w.match;
            s.match.players = players < 0 ? 3 : players;
            s.match.sleep = s.match.players > 0;  // the plain pyramid stays awake, as in the benchmarks
            s.ticks = w.session.ticks;
            s.distance = distance;
            s.desyncAt = w.session.desyncAt;
            return runSynctest(s, std::cout, std::cerr);
        }
        if (w.session.inputDelay < 0) w.session.inputDelay = rollback ? 1 : 3;
        if (rollback && w.session.maxPrediction == 0) w.session.maxPrediction = 8;
        if (!rollback) w.session.maxPrediction = 0;
        if (host.desyncPeer >= w.match.players) {
            std::cerr << "error: --desync-peer must be below --peers\n";
            return 2;
        }
        w.realtime = !fast;
        host.spawnPeers = !noSpawn;
        char self[4096];
        const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
        host.program = n > 0 ? std::string(self, std::size_t(n)) : std::string(argv[0]);
        return runHost(host, std::cout, std::cerr);
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 2;
    }
}
