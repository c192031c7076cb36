// samples/cli.h — the commands of the `unison` tool as library functions, so tests can call them directly.
//
// Owns: the file formats of DESIGN.md "Command-line contract" (the LCP text file, the resolver JSON) and the JSON
// the tool prints. Each command returns the JSON to print and an exit code: 0 solved, 1 unsolved; bad input throws
// cli::InputError (exit code 2).
#pragma once

#include "json_fields.h"
#include <unison/lcp.h>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <iosfwd>
#include <string>

namespace unison::cli {

/// Bad user input: the message names the file position or key. Exit code 2.
using InputError = jsonio::JsonError;
using jsonio::array;
using jsonio::boolean;
using jsonio::integer;
using jsonio::member;
using jsonio::number;
using jsonio::numbers;
using jsonio::parseJson;
using jsonio::readFile;

/// What a command prints on stdout and the exit code it ends with.
struct CommandOutput {
    nlohmann::json json;
    int exitCode = 0;
};

/// Parses the LCP text format: n, then the n*n entries of A row by row, then the n entries of b, all
/// whitespace-separated. `what` names the source in error messages.
Lcp parseLcpText(const std::string& text, const std::string& what);

/// `unison lcp`: {"status", "pivots", "z", "w", "residual"} (+ "work", "scaled_residual"); exit 0 only if solved.
CommandOutput runLcp(const Lcp& lcp, int maxPivots);

/// `unison resolve`: the paper's resolver on one JSON problem (DESIGN.md); exit 0 only if solved.
CommandOutput runResolve(const nlohmann::json& input, const std::string& what);

/// Optional snapshot of `unison run`: after step `at` (0: the loaded scene; -1: none) write World2::snapshot() or
/// World3::snapshot() to `path` (atomically).
struct RunSnapshot {
    int at = -1;
    std::string path;
};

/// How `unison run` may spend each step: worker threads and a per-step budget in work units (0 = unlimited;
/// core/step_budget.h). The hash lines do not depend on `threads`.
struct RunBudget {
    int threads = 1;
    std::uint64_t budget = 0;
};

/// `unison run`: steps a scene, printing {"step", "hash"} every `hashEvery` steps (0: never) and a final JSON
/// object with every body's state and the step statistics to `out` (with `worst_step_ms` and `mean_step_ms`, wall
/// clock, and `max_step_work`, `approximate_islands`, `exact_islands`). Returns 0, or 1 when some island's LCP
/// failed during the run. Bad scenes throw InputError.
int runScene(const nlohmann::json& scene, const std::string& what, int steps, int hashEvery, std::ostream& out,
             const RunSnapshot& snapshot = {}, const RunBudget& budget = {});

/// `unison record SCENE --inputs INPUTS --steps N -o OUT [--snapshot-every K]`: records a match (replay/recording.h)
/// and prints {"steps", "final_hash", "snapshots", "bytes"}. Returns 0; bad input throws InputError.
int recordCommand(const std::string& sceneFile, const std::string& inputsFile, int steps, int snapshotEvery,
                  const std::string& outFile, std::ostream& out);

/// `unison verify REC [--inputs FILE] [--keep-going] [--report FILE]`: replays a recording (with its own inputs, or
/// with FILE's instead, to see where an input change makes a match diverge) and prints its report
/// (replay::reportToJson). It stops at the first tick whose hash differs; with keepGoing it replays on to the next
/// recorded snapshot and lists the fields that differ there. Returns 0 when every tick matches, 1 on a desync (a
/// one-line summary also goes to `err`); a bad file throws InputError. With `reportFile`, the report (every
/// differing field, up to 1000) is also written there as indented JSON.
int verifyCommand(const std::string& recordingFile, const std::string& inputsFile, bool keepGoing, std::ostream& out,
                  std::ostream& err, const std::string& reportFile = "");

/// `unison view REC -o PAGE [--report REPORT]`: writes the replay viewer page of a recording (samples/view_page.h),
/// marking a desync report's tick and bodies; prints {"ticks", "bodies", "contacts",
/// "ticks_differing_from_recording", "bytes"}. Returns 0; a bad file throws InputError.
int viewCommand(const std::string& recordingFile, const std::string& outFile, const std::string& reportFile,
                std::ostream& out);

/// `unison diff A B`: prints {"equal", "differing_fields", "differences": [{"body", "field", "a", "b"}]} for two
/// snapshot files. Returns 0 when equal, 1 when they differ; a bad file throws InputError.
int diffCommand(const std::string& fileA, const std::string& fileB, std::ostream& out);

/// A state hash as the 16 lower-case hex digits the run output prints.
std::string hashHex(std::uint64_t hash);

}  // namespace unison::cli
