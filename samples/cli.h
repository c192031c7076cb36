// samples/cli.h — the commands of the `unison` tool as library functions, so tests can call them directly.
//
// Owns: the file formats of DESIGN.md "Command-line contract" (the LCP text file, the resolver JSON) and the JSON
// the tool prints. Each command returns the JSON to print and an exit code: 0 solved, 1 unsolved; bad input throws
// cli::InputError (exit code 2).
#pragma once

#include "json_fields.h"
#include "lcp.h"

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

/// `unison run`: steps a scene, printing {"step", "hash"} every `hashEvery` steps (0: never) and a final JSON
/// object with every body's state and the step statistics to `out`. Returns 0, or 1 when some island's LCP
/// failed during the run. Bad scenes throw InputError.
int runScene(const nlohmann::json& scene, const std::string& what, int steps, int hashEvery, std::ostream& out);

/// `unison run` for a scene with "dimension": 3 (runScene dispatches to it); relative `obj` paths are resolved
/// against the folder of `what` (the scene file).
int runScene3(const nlohmann::json& scene, const std::string& what, int steps, int hashEvery, std::ostream& out);

/// A state hash as the 16 lower-case hex digits the run output prints.
std::string hashHex(std::uint64_t hash);

}  // namespace unison::cli
