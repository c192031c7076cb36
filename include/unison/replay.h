// unison/replay.h — recorded matches: record a scene with its per-tick inputs, keep the state hash of every tick
// and snapshots every K ticks in one byte string (the .urec format of docs/replay.md), and verify a recording by
// replaying it tick by tick. Scenes and inputs are JSON text in the formats of docs/formats.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace unison {

/// What verifying a recording found.
struct VerifyResult {
    bool match = true;              ///< every tick's replayed state hash equals the recorded one
    int ticks = 0;                  ///< ticks replayed
    int firstDesyncTick = -1;       ///< first tick whose hash differs (-1: none)
    std::uint64_t recordedHash = 0; ///< at firstDesyncTick
    std::uint64_t replayedHash = 0; ///< at firstDesyncTick
    int differingFields = 0;        ///< state fields that differ at the first snapshot tick at or after the desync
    std::string summary;            ///< one line for a person ("all 600 ticks match", or where the desync is)
    std::string reportJson;         ///< the full report as JSON (the shape of `unison verify --report`)
};

/// Records `steps` ticks of a scene (JSON text) with inputs (JSON text {"inputs": [...]}, or empty for none),
/// snapshotting every `snapshotEvery` (>= 1) ticks. Returns the recording's bytes; empty with a message in
/// *error for a bad scene, bad inputs or bad counts.
std::vector<std::uint8_t> recordMatch(const std::string& sceneJson, const std::string& inputsJson, int steps,
                                      int snapshotEvery, std::string* error = nullptr);

/// Replays a recording and compares every tick's state hash. False with a message in *error when the bytes are
/// not a valid recording (a desync is not an error: it is reported in *out).
bool verifyRecording(const std::uint8_t* data, std::size_t size, VerifyResult* out, std::string* error = nullptr);

/// The state hash after every tick that a recording holds ((steps + 1) values, [0] before the first step).
bool recordingHashes(const std::uint8_t* data, std::size_t size, std::vector<std::uint64_t>* out,
                     std::string* error = nullptr);

}  // namespace unison
