// tests/process_run.h — running a built program from a test: its exit code, stdout and stderr, and temporary files.
#pragma once

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace unison::test {

struct ProcessRun {
    int exitCode = -1;
    std::string out, err;
    /// Every non-empty line of stdout that is a JSON object.
    std::vector<nlohmann::json> jsonLines() const {
        std::vector<nlohmann::json> lines;
        std::size_t start = 0;
        for (std::size_t end; (end = out.find('\n', start)) != std::string::npos; start = end + 1) {
            const std::string line = out.substr(start, end - start);
            if (!line.empty() && line.front() == '{') lines.push_back(nlohmann::json::parse(line));
        }
        return lines;
    }
};

/// A path in $TMPDIR (or /tmp) unique to this process: prefix_pid_name.
inline std::string tempFile(const std::string& prefix, const std::string& name) {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir ? dir : "/tmp") + "/" + prefix + "_" + std::to_string(::getpid()) + "_" + name;
}

inline std::string readWhole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Runs `program args` through the shell, capturing stdout and stderr.
inline ProcessRun runProgram(const std::string& program, const std::string& args) {
    const std::string out = tempFile("unison_run", "stdout"), err = tempFile("unison_run", "stderr");
    const int status = std::system((program + " " + args + " >" + out + " 2>" + err).c_str());
    ProcessRun r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = readWhole(out);
    r.err = readWhole(err);
    std::remove(out.c_str());
    std::remove(err.c_str());
    return r;
}

}  // namespace unison::test
