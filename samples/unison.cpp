// samples/unison.cpp — the `unison` command-line tool (DESIGN.md "Command-line contract").
// JSON results go to stdout; errors go to stderr with exit code 2 for bad input and 1 for an unsolved problem.
#include "cli.h"
#include "fp_env.h"
#include "step_budget.h"

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
    int snapshotAt = -1;
    std::string snapshotOut;
    run->add_option("--snapshot-at", snapshotAt, "write a snapshot after step T (0: the loaded scene) to -o FILE")
        ->check(CLI::NonNegativeNumber);
    run->add_option("-o,--output", snapshotOut, "snapshot file (.usnap) for --snapshot-at");
    RunBudget runBudget;
    double budgetMs = 0.0;
    run->add_option("--threads", runBudget.threads, "worker threads (default 1); the hashes do not depend on it")
        ->check(CLI::PositiveNumber);
    auto* budgetUnits = run->add_option("--budget", runBudget.budget, "per-step budget in work units (0: unlimited)")
                            ->check(CLI::NonNegativeNumber);
    run->add_option("--budget-ms", budgetMs, "per-step budget in milliseconds of the reference machine")
        ->check(CLI::PositiveNumber)
        ->excludes(budgetUnits);

    std::string inputsFile, recordOut;
    int recordSteps = 60, snapshotEvery = 30;
    auto* record = app.add_subcommand("record", "record a 2D or 3D scene with per-tick inputs: hashes and snapshots");
    record->add_option("SCENE", sceneFile, "scene JSON file")->required();
    record->add_option("--inputs", inputsFile, "inputs JSON file (docs/formats.md); none if omitted");
    record->add_option("--steps", recordSteps, "number of ticks (default 60)")->check(CLI::NonNegativeNumber);
    record->add_option("--snapshot-every", snapshotEvery, "full snapshot every K ticks (default 30)")
        ->check(CLI::PositiveNumber);
    record->add_option("-o,--output", recordOut, "recording file (.urec)")->required();

    std::string verifyFile;
    auto* verify = app.add_subcommand("verify", "replay a recording; exit 0 if every tick's hash matches");
    verify->add_option("RECORDING", verifyFile, "recording file (.urec)")->required();
    std::string verifyInputs, verifyReport;
    verify->add_option("--inputs", verifyInputs, "replay with these inputs instead of the recorded ones");
    bool keepGoing = false;
    verify->add_flag("--keep-going", keepGoing,
                     "after the first mismatch, replay on to the next recorded snapshot to list the differing fields");
    verify->add_option("--report", verifyReport, "also write the report (JSON) to this file");

    std::string viewFile, viewOut, viewReport;
    auto* view = app.add_subcommand("view", "write a self-contained HTML page that plays a recording");
    view->add_option("RECORDING", viewFile, "recording file (.urec)")->required();
    view->add_option("-o,--output", viewOut, "page to write (.html)")->required();
    view->add_option("--report", viewReport, "desync report (JSON) to mark on the timeline");

    std::string diffA, diffB;
    auto* diff = app.add_subcommand("diff", "list the fields that differ between two snapshot files");
    diff->add_option("A", diffA, "snapshot file (.usnap)")->required();
    diff->add_option("B", diffB, "snapshot file (.usnap)")->required();

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
        if (*run) {
            if ((snapshotAt >= 0) != !snapshotOut.empty()) throw InputError("--snapshot-at and -o go together");
            if (budgetMs > 0.0) runBudget.budget = unison::work::fromMilliseconds(budgetMs);
            return runScene(parseJson(readFile(sceneFile), sceneFile), sceneFile, steps, hashEvery, std::cout,
                            RunSnapshot{snapshotAt, snapshotOut}, runBudget);
        }
        if (*record) return recordCommand(sceneFile, inputsFile, recordSteps, snapshotEvery, recordOut, std::cout);
        if (*verify) return verifyCommand(verifyFile, verifyInputs, keepGoing, std::cout, std::cerr, verifyReport);
        if (*view) return viewCommand(viewFile, viewOut, viewReport, std::cout);
        if (*diff) return diffCommand(diffA, diffB, std::cout);
        CommandOutput out;
        if (*lcp) {
            out = runLcp(parseLcpText(readFile(lcpFile, unison::policy::kMaxLcpTextBytes), lcpFile), maxPivots);
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
    } catch (const nlohmann::json::exception& e) {
        // A reader that missed a type check: still bad input, never an abort. (Messages of this kind name types,
        // not the text.)
        std::cerr << "error: unexpected JSON value: " << e.what() << "\n";
        return 2;
    }
}
