// samples/lockstep/protocol.h — the messages between the lockstep host and its peers, and their byte form.
//
// What crosses the network: the match settings once (welcome), then only inputs (each peer's own, relayed by the
// host to the others), state hashes at checkpoints, and — only to locate a desync — compact-state hashes of a
// range of ticks and two full snapshots. Every message starts with its MessageType byte; fields are little-endian
// (core/state_io.h ByteWriter). Inputs travel unreliably and redundantly: each message repeats every input the
// receiver has not acknowledged yet, so a lost message costs nothing but time.
#pragma once

#include "match.h"
#include "net.h"
#include "rollback.h"

#include <cstdint>
#include <string>
#include <vector>

namespace unison::lockstep {

constexpr std::uint32_t kProtocolVersion = 1;

enum class MessageType : std::uint8_t {
    hello = 1,      ///< peer -> host: protocol version, wanted player index (-1: any)
    welcome,        ///< host -> peer: the match settings (Welcome)
    start,          ///< host -> peer: every peer is here, the clock starts
    inputs,         ///< peer -> host: acknowledgements + the peer's unacknowledged inputs (unreliable)
    relay,          ///< host -> peer: acknowledgement + other players' unacknowledged inputs (unreliable)
    hash,           ///< peer -> host: state hash after a checkpoint tick and the window hash up to it
    checkOk,        ///< host -> peer: every peer agreed at a checkpoint; older states may be forgotten
    queryHashes,    ///< host -> peer: compact-state hashes of ticks [from, to], please
    hashes,         ///< peer -> host: those hashes
    querySnapshot,  ///< host -> peer: the full snapshot after a tick, please
    snapshot,       ///< peer -> host: that snapshot
    done,           ///< peer -> host: last tick final, with the peer's statistics
    stop,           ///< host -> peer: the match is over
};

/// The settings the host sends each peer.
struct Welcome {
    MatchConfig match;
    SessionConfig session;  ///< localPlayer is the receiving peer's player
    NetConditions net;      ///< conditions of the peer's messages to the host (seed differs per peer)
    bool realtime = true;   ///< pace ticks at match hz (else as fast as inputs allow)
    double hz = 60.0;
};

/// A run of one player's inputs: ticks first, first + 1, ...
struct InputRun {
    int player = 0;
    int first = 1;
    std::vector<PlayerInput> inputs;
};

/// What a peer reports when its last tick is final.
struct PeerDone {
    int tick = 0;
    std::uint64_t finalHash = 0;
    SessionStats stats;
    int dropped = 0;  ///< messages the peer's simulated link dropped
    double stalledMs = 0.0;  ///< realtime: time a due tick waited for inputs (lockstep) or the prediction window
};

/// A decoded message; only the members of its type are set.
struct Message {
    MessageType type = MessageType::hello;
    std::uint32_t version = 0;
    int wantedPlayer = -1;
    Welcome welcome;
    std::vector<int> acks;          ///< inputs: last tick of each player's inputs the sender has
    int ack = 0;                    ///< relay: last tick of the receiver's inputs the host has
    std::vector<InputRun> runs;     ///< inputs (one run), relay (one per other player)
    int tick = 0;                   ///< hash, checkOk, querySnapshot, snapshot
    int from = 0, to = 0;           ///< queryHashes; hashes uses from
    std::uint64_t hash = 0;         ///< hash: World2::stateHash() of the checkpoint
    std::uint64_t window = 0;       ///< hash: RollbackSession::windowHash() of the checkpoint
    std::vector<std::uint64_t> hashList;  ///< hashes
    std::vector<std::uint8_t> bytes;      ///< snapshot
    PeerDone done;
};

std::vector<std::uint8_t> encodeHello(int wantedPlayer);
std::vector<std::uint8_t> encodeWelcome(const Welcome& w);
std::vector<std::uint8_t> encodeSimple(MessageType type);  ///< start, stop
std::vector<std::uint8_t> encodeInputs(const std::vector<int>& acks, const InputRun& run);
std::vector<std::uint8_t> encodeRelay(int ack, const std::vector<InputRun>& runs);
std::vector<std::uint8_t> encodeTick(MessageType type, int tick);  ///< checkOk, querySnapshot
std::vector<std::uint8_t> encodeHash(int tick, std::uint64_t hash, std::uint64_t window);
std::vector<std::uint8_t> encodeQueryHashes(int from, int to);
std::vector<std::uint8_t> encodeHashes(int from, const std::vector<std::uint64_t>& hashes);
std::vector<std::uint8_t> encodeSnapshot(int tick, const std::vector<std::uint8_t>& bytes);
std::vector<std::uint8_t> encodeDone(const PeerDone& d);

/// Decodes a message; false with *error for a malformed one (it is then ignored by the receiver).
bool decodeMessage(const std::vector<std::uint8_t>& bytes, Message* out, std::string* error);

}  // namespace unison::lockstep
