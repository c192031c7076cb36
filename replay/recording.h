// replay/recording.h — recorded matches (.urec): record, save, load, verify, and the desync report.
//
// Owns: Recording (the scene, the inputs, the state hash after every tick, full snapshots every K ticks and at the
// last tick), its binary file format, and verification, which replays the recording through the same Session2 or
// Session3 as record() and compares every tick's hash.
// The file (little-endian, like core/state_io.h): magic "UNISREC\0", u32 format version, u64 result-affecting
// build flags, the scene JSON text and the inputs JSON text (u64 length + bytes each), u32 steps, u32 snapshot
// interval, u64 hash count + the hashes (ticks 0..steps), u64 snapshot count + (u32 tick, u64 length, bytes) each,
// then the XXH3 of everything before it.
// Desync report: the first tick whose hash differs, and the field-level differences between the replayed state
// and the recorded snapshot at that tick (K = 1, or the tick is a multiple of K), or, when asked to keep going, at
// the first snapshot tick after it.
// Reading is bounded by the file: counts are checked against the bytes left before anything is allocated, the file
// is at most policy::kMaxBinaryBytes, and its scene and inputs are JSON under the same limits as files.
#pragma once

#include "inputs.h"
#include "state_io.h"

#include <cstdint>
#include <string>
#include <vector>

namespace unison::replay {

struct RecordedSnapshot {
    int tick = 0;
    std::vector<std::uint8_t> bytes;  ///< World2::snapshot() or World3::snapshot() after that tick
};

struct Recording {
    nlohmann::json scene;                   ///< the initial scene
    InputScript inputs;                     ///< per-tick inputs
    int steps = 0;                          ///< ticks recorded
    int snapshotEvery = 0;                  ///< K: snapshots at ticks 0, K, 2K, ... and at `steps`
    std::vector<std::uint64_t> hashes;      ///< (steps + 1): state hash after tick t; [0] is the loaded scene
    std::vector<RecordedSnapshot> snapshots;  ///< ascending ticks
};

/// Runs a scene (2D or 3D by its "dimension") with inputs for `steps` ticks, hashing every tick and snapshotting
/// every `snapshotEvery` ticks (>= 1). A 3D scene's mesh `obj` files (relative to `baseDir`) are inlined into the
/// stored scene. Throws ReplayError on a bad scene, inputs of the other dimension or an input that cannot be applied.
Recording record(const nlohmann::json& scene, const InputScript& inputs, int steps, int snapshotEvery,
                 const std::string& baseDir = "");

std::vector<std::uint8_t> serializeRecording(const Recording& rec);
/// Parses a recording file's bytes; truncated, corrupt or foreign data throws ReplayError naming `what`.
Recording parseRecording(const std::vector<std::uint8_t>& bytes, const std::string& what);

/// The result of verify().
struct VerifyReport {
    bool match = true;
    int ticks = 0;                       ///< ticks replayed
    int firstTick = -1;                  ///< first tick whose hash differs (-1: none)
    std::uint64_t recordedHash = 0, replayedHash = 0;  ///< at firstTick
    int comparedTick = -1;               ///< tick of the recorded snapshot compared field by field (-1: none)
    std::vector<FieldDifference> differences;  ///< recorded (a) vs replayed (b) at comparedTick
    std::vector<int> bodyNumbers;        ///< input body number of each difference's body (-1: none / world)
};

/// Replays a recording tick by tick and stops at the first tick whose hash differs (its fields are compared when a
/// snapshot was recorded at that tick). With keepGoing it replays on to the next recorded snapshot and compares the
/// fields there (work up to the snapshot interval more). Throws ReplayError when the recording's own scene or
/// inputs are bad, or when a replayed step overflows.
VerifyReport verify(const Recording& rec, bool keepGoing = false);

/// {"status": "match"|"desync", "ticks", and for a desync "first_desync_tick", "recorded_hash", "replayed_hash",
/// "compared_snapshot_tick", "differing_fields", "differences": [{"body", "body_number", "field", "recorded",
/// "replayed"}] (at most `limit`)}.
nlohmann::json reportToJson(const VerifyReport& report, std::size_t limit);
/// One line for a person: "desync at tick 42: body 3:1 (number 2) velocity.x recorded ... replayed ...".
std::string reportSummary(const VerifyReport& report);

/// 16 lower-case hex digits.
std::string hexHash(std::uint64_t h);

}  // namespace unison::replay
