// tests/cli_runner.h — the `unison` tool as a real process on files in a temporary folder, for the suites that test
// its contract (test_cli.cpp, test_hostile_inputs.cpp); built on tests/process_run.h.
#pragma once

#include "process_run.h"

#include <fstream>
#include <string>
#include <vector>

namespace cli_runner {

using Run = unison::test::ProcessRun;

inline std::string tempPath(const std::string& name) { return unison::test::tempFile("unison_test_cli", name); }

inline std::string writeTemp(const std::string& name, const std::string& text) {
    const std::string path = tempPath(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

inline std::string slurp(const std::string& path) { return unison::test::readWhole(path); }

/// Every JSON object line of `out`.
inline std::vector<nlohmann::json> jsonLines(const std::string& out) { return Run{0, out, ""}.jsonLines(); }

/// `unison run` output without its wall-clock fields (stats.worst_step_ms and mean_step_ms differ run to run).
inline std::string withoutTimes(const std::string& out) {
    std::string kept;
    for (nlohmann::json line : jsonLines(out)) {
        if (line.contains("stats")) {
            line["stats"].erase("worst_step_ms");
            line["stats"].erase("mean_step_ms");
        }
        kept += line.dump() + "\n";
    }
    return kept;
}

/// Runs `unison ARGS` (the name `unison` is the project's namespace).
inline Run cli(const std::string& args) { return unison::test::runProgram(UNISON_CLI_PATH, args); }

}  // namespace cli_runner

using namespace cli_runner;
