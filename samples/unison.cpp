// samples/unison.cpp — the `unison` command-line tool (DESIGN.md "Command-line contract").
// JSON results go to stdout; errors go to stderr with exit code 2 for bad input and 1 for an unsolved problem.
#include "cli.h"
#include "fp_env.h"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
    using namespace unison::cli;
    CLI::App app{"unison — deterministic rigid-body contact resolution (Lemke LCP)"};
    app.require_subcommand(1);

    std::string lcpFile;
    int maxPivots = 0;
    auto* lcp = app.add_subcommand("lcp", "solve an LCP text file: n, then A row by row, then b");
    lcp->add_option("FILE", lcpFile, "LCP text file")->required();
    lcp->add_option("--max-pivots", maxPivots, "hard pivot cap (default 100000)")->check(CLI::PositiveNumber);

    std::string resolveFile;
    auto* resolve = app.add_subcommand("resolve", "run the paper's collision resolver on a JSON problem");
    resolve->add_option("FILE", resolveFile, "resolver JSON file")->required();

    std::string sceneFile;
    int steps = 60;
    int hashEvery = 0;
    auto* run = app.add_subcommand("run", "step a 2D or 3D scene and print state hashes and final body states");
    run->add_option("SCENE", sceneFile, "scene JSON file")->required();
    run->add_option("--steps", steps, "number of steps (default 60)")->check(CLI::NonNegativeNumber);
    run->add_option("--hash-every", hashEvery, "print {\"step\", \"hash\"} every K steps (0: never)")
        ->check(CLI::NonNegativeNumber);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);  // prints help or the usage error
        return code == 0 ? 0 : 2;
    }
    const std::string env = unison::checkFloatingPointEnvironment();
    if (!env.empty()) {
        std::cerr << "error: " << env << "\n";
        return 2;
    }
    try {
        if (*run) return runScene(parseJson(readFile(sceneFile), sceneFile), sceneFile, steps, hashEvery, std::cout);
        CommandOutput out;
        if (*lcp) {
            out = runLcp(parseLcpText(readFile(lcpFile), lcpFile), maxPivots);
        } else {
            out = runResolve(parseJson(readFile(resolveFile), resolveFile), resolveFile);
        }
        std::cout << out.json.dump() << "\n";
        if (out.exitCode != 0 && out.json.contains("message")) {
            std::cerr << "unsolved: " << out.json["message"].get<std::string>() << "\n";
        }
        return out.exitCode;
    } catch (const InputError& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 2;
    }
}
