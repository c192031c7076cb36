// tests/cli_runner.h — runs the `unison` tool as a real process on files in a temporary folder, for the suites that
// test its contract (test_cli.cpp, test_hostile_inputs.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace cli_runner {

struct Run {
    int exitCode = -1;
    std::string out;
    std::string err;
};

inline std::string tempPath(const std::string& name) {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir ? dir : "/tmp") + "/unison_test_cli_" + std::to_string(::getpid()) + "_" + name;
}

inline std::string writeTemp(const std::string& name, const std::string& text) {
    const std::string path = tempPath(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Every line of `out` parsed as JSON.
inline std::vector<nlohmann::json> jsonLines(const std::string& out) {
    std::vector<nlohmann::json> lines;
    std::size_t start = 0;
    for (std::size_t end; (end = out.find('\n', start)) != std::string::npos; start = end + 1)
        lines.push_back(nlohmann::json::parse(out.substr(start, end - start)));
    return lines;
}

inline Run unison(const std::string& args) {
    const std::string out = tempPath("stdout"), err = tempPath("stderr");
    const std::string cmd = std::string(UNISON_CLI_PATH) + " " + args + " >" + out + " 2>" + err;
    const int status = std::system(cmd.c_str());
    Run r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    std::remove(out.c_str());
    std::remove(err.c_str());
    return r;
}

}  // namespace cli_runner

using namespace cli_runner;
