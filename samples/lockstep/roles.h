// samples/lockstep/roles.h — the three programs of the lockstep sample: the host (accepts the peers, relays
// their inputs, compares checkpoint hashes, locates a desync and reports it), a peer (simulates the match from
// the inputs, with or without rollback) and the synctest (GGPO's sync test on one machine, no network).
// Each returns the process exit code: 0 agreement, 1 desync, 2 bad settings, 3 a network failure or timeout.
#pragma once

#include "protocol.h"

#include <iosfwd>
#include <string>

namespace unison::lockstep {

struct HostOptions {
    Welcome settings;               ///< sent to every peer (localPlayer and net.seed set per peer)
    int port = 0;                   ///< 0: a free port
    bool spawnPeers = true;         ///< start the peers as child processes of this program
    std::string program;            ///< this program's path (for spawning)
    int desyncPeer = -1;            ///< the peer that injects the desync (-1: the last one)
    std::string recordFile;         ///< write the match as a recording (.urec) here
    std::string reportFile;         ///< write the desync report (JSON) here
    double timeoutSeconds = 120.0;  ///< give up after this long
};

/// Hosts a match; prints one JSON object (summary or desync report) on `out`, progress on `err`.
int runHost(const HostOptions& options, std::ostream& out, std::ostream& err);

/// Plays one peer of a match hosted at host:port; prints one JSON line with its final hash on `out`.
int runPeer(const std::string& host, int port, int wantedPlayer, std::ostream& out, std::ostream& err);

struct SynctestOptions {
    MatchConfig match;         ///< players 0: the plain testbed pyramid (scenes::pyramidScene(rows, 0.5, sleep))
    int ticks = 600;
    int distance = 1;          ///< roll back this many ticks every tick
    int desyncAt = -1;         ///< flip a velocity bit after this tick's first simulation (the test must fail)
};

/// Every tick: save, advance, restore the state `distance` ticks back, simulate again, compare hashes. Prints the
/// costs (save, restore, step, re-simulation, per tick) and the compact state's size per body as JSON.
int runSynctest(const SynctestOptions& options, std::ostream& out, std::ostream& err);

}  // namespace unison::lockstep
