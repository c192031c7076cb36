// bench/bench_lcp.cpp — Unison's Lemke against Siconos numerics' lexicographic Lemke on the scenes/ LCP families.
//
// For every case of scenes::standardCases(): Unison cold, Unison warm-started from its own cold basis, and
// Siconos lcp_lexicolemke, each timed with steady_clock as the minimum over enough repetitions to fill a time
// budget. Correctness is judged here, not taken from the solvers: the complementarity residual is recomputed from
// (A, b, z) for both, and a status counts as right only when it matches the case's mathematical expectation.
// Benchmarks report; they never gate CI: the exit code is 0 unless something threw.
//
// A second table (bench_lcp_manifolds.cpp) runs the contact LCPs assembled from Box2D 2.4.1's own manifolds of settled
// pyramids, with Unison's fast path (a hook, the same Lemke until it is wired), Unison's Lemke and Siconos.
//
// Usage: bench_lcp [--quick] [--json FILE] [--filter SUBSTRING]
#include "bench_lcp_manifolds.h"
#include <unison/lcp.h>
#include "lcp_families.h"
#include "siconos_peer.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace {

using unison::Lcp;
using unison::LcpOptions;
using unison::LcpResult;
using unison::LcpStatus;
using unison::LemkeSolver;
using unison::scenes::LcpCase;

constexpr double kResidualLimit = 1e-9;  // scaled residual above this = failed, for either solver

std::string statusString(LcpStatus status) { return unison::statusName(status); }

struct Timing {
    double bestMs = 0.0;  // minimum over repetitions
    int reps = 0;
};

// Runs `run` at least once and until `budgetMs` of total time or `maxReps` runs; returns the fastest run.
Timing timeRepeated(const std::function<void()>& run, double budgetMs, int maxReps) {
    Timing t;
    double total = 0.0;
    t.bestMs = 1e300;
    while (t.reps < maxReps && (t.reps == 0 || total < budgetMs)) {
        const auto start = std::chrono::steady_clock::now();
        run();
        const auto stop = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(stop - start).count();
        total += ms;
        t.bestMs = std::min(t.bestMs, ms);
        ++t.reps;
    }
    return t;
}

struct UnisonRun {
    LcpResult result;
    double recomputedResidual = 0.0;  // scaled, from (A, b, z) here
    Timing timing;
};

struct SiconosRun {
    bool ran = false;
    unison::bench::SiconosResult result;
    double residual = 0.0;  // scaled, from (A, b, z) here
    std::string status;     // solved / infeasible (stopped without a valid answer) / pivot_limit
    int cap = 0;            // iteration cap given to lcp_lexicolemke
    Timing timing;
};

struct Row {
    const LcpCase* c = nullptr;
    UnisonRun cold;
    bool warmRan = false;
    UnisonRun warm;
    SiconosRun siconos;
    bool unisonRight = false;
    bool siconosRight = false;
    std::string notes;
};

bool isHardFamily(const std::string& name) {
    for (const char* prefix : {"murty", "llt", "cubes", "jammed", "squeezed"}) {
        if (name.rfind(prefix, 0) == 0) return true;
    }
    return name.find("_friction") != std::string::npos;
}

// Right status: the expected one with a residual we verified ourselves, or an honest pivot_limit where the exact
// pivot path is longer than the cap.
bool rightStatus(const LcpCase& c, const std::string& status, double recomputedResidual) {
    if (status == c.expected) return status != "solved" || recomputedResidual <= kResidualLimit;
    return c.capAcceptable && status == "pivot_limit";
}

UnisonRun runUnison(const LcpCase& c, const LcpOptions& options, double budgetMs) {
    UnisonRun run;
    LemkeSolver solver;
    // Unison gets the matrix in compressed rows, as a world step would build it (the conversion is not timed,
    // just as Siconos' own matrix set-up is not).
    const unison::SparseLcp sparse = unison::toSparse(c.lcp);
    const auto start = std::chrono::steady_clock::now();
    run.result = solver.solve(sparse, options);
    const double firstMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    run.recomputedResidual = run.result.status == LcpStatus::solved ? unison::scenes::scaledResidual(c.lcp, run.result.z) : 0.0;
    if (firstMs >= budgetMs) {
        run.timing.bestMs = firstMs;  // long enough on its own; buffer sizing is noise at this scale
        run.timing.reps = 1;
    } else {
        // The first call sized the solver's buffers; time the reuse, as a game loop would.
        run.timing = timeRepeated([&] { (void)solver.solve(sparse, options); }, budgetMs, 100000);
    }
    return run;
}

SiconosRun runSiconos(const LcpCase& c, double budgetMs) {
    SiconosRun run;
    run.ran = true;
    // Same cap as Unison where affordable; a lexicolemke iteration updates the whole n x 2(n + 1) tableau, so for
    // large n the cap is cut to keep one cycling run near 10 s (never below 20 n, far above a normal path).
    const double perIteration = double(c.lcp.n) * 2.0 * double(c.lcp.n + 1);
    const double affordable = std::max(20.0 * c.lcp.n, 1e10 / perIteration);
    run.cap = int(std::min(double(LcpOptions::kDefaultMaxPivots), affordable));
    unison::bench::SiconosPeer peer(c.lcp, run.cap);
    run.result = peer.solve();
    run.residual = unison::scenes::scaledResidual(c.lcp, run.result.z);
    if (run.result.info == 1) {
        run.status = "pivot_limit";
    } else if (run.result.info == 0 && run.residual <= kResidualLimit) {
        run.status = "solved";
    } else {
        run.status = "infeasible";  // lexicolemke stopped (info 0 on a ray, too) without a valid answer
    }
    const double firstMs = run.result.seconds * 1e3;
    if (firstMs >= budgetMs) {
        run.timing.bestMs = firstMs;  // one run longer than the budget is enough
        run.timing.reps = 1;
    } else {
        run.timing = timeRepeated([&] { (void)peer.solve(); }, budgetMs, 100000);
        run.timing.bestMs = std::min(run.timing.bestMs, firstMs);
    }
    return run;
}

std::string fmtMs(double ms) {
    char buf[32];
    if (ms < 1.0) std::snprintf(buf, sizeof buf, "%.4f", ms);
    else if (ms < 100.0) std::snprintf(buf, sizeof buf, "%.2f", ms);
    else std::snprintf(buf, sizeof buf, "%.0f", ms);
    return buf;
}

std::string fmtRes(double r) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1e", r);
    return buf;
}

const Row* findRow(const std::vector<Row>& rows, const std::string& name) {
    for (const Row& r : rows) {
        if (r.c->name == name) return &r;
    }
    return nullptr;
}

nlohmann::json toJson(const Row& r) {
    nlohmann::json j;
    j["case"] = r.c->name;
    j["n"] = r.c->lcp.n;
    j["expected"] = r.c->expected;
    j["expected_pivots"] = r.c->expectedPivots;
    j["unison"] = {{"status", statusString(r.cold.result.status)},
                   {"pivots", r.cold.result.pivots},
                   {"work", r.cold.result.work},
                   {"ms", r.cold.timing.bestMs},
                   {"reps", r.cold.timing.reps},
                   {"scaled_residual_reported", r.cold.result.scaledResidual},
                   {"scaled_residual_recomputed", r.cold.recomputedResidual},
                   {"right", r.unisonRight}};
    if (r.warmRan) {
        j["unison_warm"] = {{"status", statusString(r.warm.result.status)},
                            {"pivots", r.warm.result.pivots},
                            {"warm_started", r.warm.result.warmStarted},
                            {"ms", r.warm.timing.bestMs},
                            {"scaled_residual_recomputed", r.warm.recomputedResidual}};
    }
    if (r.siconos.ran) {
        j["siconos"] = {{"info", r.siconos.result.info},
                        {"iterations", r.siconos.result.iterations},
                        {"iteration_cap", r.siconos.cap},
                        {"status", r.siconos.status},
                        {"ms", r.siconos.timing.bestMs},
                        {"reps", r.siconos.timing.reps},
                        {"scaled_residual_recomputed", r.siconos.residual},
                        {"right", r.siconosRight}};
    }
    j["notes"] = r.notes;
    return j;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Unison Lemke vs Siconos lexicolemke on the scenes/ LCP families"};
    bool quick = false;
    std::string jsonPath;
    std::string filter;
    app.add_flag("--quick", quick, "only the small cases (CI smoke run, well under 20 s)");
    app.add_option("--json", jsonPath, "also write the results as JSON to FILE");
    app.add_option("--filter", filter, "only cases whose name contains this substring");
    CLI11_PARSE(app, argc, argv);

    try {
        const double budgetMs = quick ? 10.0 : 50.0;
        const std::vector<LcpCase> cases = unison::scenes::standardCases(quick);
        std::vector<Row> rows;
        rows.reserve(cases.size());

        std::printf("%-24s %5s %-10s | %-11s %6s %9s %8s | %6s %9s | %4s %6s %9s %8s | %7s  %s\n", "case", "n", "expect",
                    "unison", "piv", "ms", "sres", "w.piv", "w.ms", "s.if", "s.iter", "s.ms", "s.sres", "s/u", "flags");
        for (const LcpCase& c : cases) {
            if (!filter.empty() && c.name.find(filter) == std::string::npos) continue;
            Row r;
            r.c = &c;
            r.cold = runUnison(c, LcpOptions{}, budgetMs);
            const std::string coldStatus = statusString(r.cold.result.status);
            r.unisonRight = rightStatus(c, coldStatus, r.cold.recomputedResidual);
            if (r.cold.result.status == LcpStatus::solved && c.expectedPivots >= 0 && r.cold.result.pivots != c.expectedPivots)
                r.notes += " pivots!=" + std::to_string(c.expectedPivots);
            if (r.cold.result.status == LcpStatus::solved &&
                std::fabs(r.cold.result.scaledResidual - r.cold.recomputedResidual) > 1e-12 + 1e-3 * r.cold.recomputedResidual)
                r.notes += " reported-residual-differs";

            if (r.cold.result.status == LcpStatus::solved) {
                LcpOptions warmOptions;
                warmOptions.warmBasis = &r.cold.result.basis;
                r.warm = runUnison(c, warmOptions, budgetMs);
                r.warmRan = true;
                if (!r.warm.result.warmStarted) r.notes += " warm-basis-discarded";
                if (!rightStatus(c, statusString(r.warm.result.status), r.warm.recomputedResidual))
                    r.notes += " WARM-FAILED";
            }

            r.siconos = runSiconos(c, budgetMs);
            r.siconosRight = rightStatus(c, r.siconos.status, r.siconos.residual);

            const std::string uFlag = r.unisonRight ? "" : " UNISON-FAILED";
            const std::string sFlag = r.siconosRight ? "" : " SICONOS-FAILED";
            char ratio[32];
            std::snprintf(ratio, sizeof ratio, "%.1fx", r.siconos.timing.bestMs / std::max(r.cold.timing.bestMs, 1e-9));
            std::printf("%-24s %5d %-10s | %-11s %6d %9s %8s | %6s %9s | %4d %6d %9s %8s | %7s %s%s%s\n", c.name.c_str(),
                        c.lcp.n, c.expected.c_str(), coldStatus.c_str(), r.cold.result.pivots,
                        fmtMs(r.cold.timing.bestMs).c_str(), fmtRes(r.cold.recomputedResidual).c_str(),
                        r.warmRan ? std::to_string(r.warm.result.pivots).c_str() : "-",
                        r.warmRan ? fmtMs(r.warm.timing.bestMs).c_str() : "-", r.siconos.result.info,
                        r.siconos.result.iterations, fmtMs(r.siconos.timing.bestMs).c_str(),
                        fmtRes(r.siconos.residual).c_str(), ratio, uFlag.c_str(), sFlag.c_str(), r.notes.c_str());
            std::fflush(stdout);
            rows.push_back(std::move(r));
        }

        // Cross-check: the hand-built jammed-particle LCP is what the resolver assembles from the same scene.
        {
            const LcpCase hand = unison::scenes::jammedParticle(0.5);
            const auto scene = unison::scenes::jammedParticleScene(0.5);
            const Lcp assembled = unison::assembleCollisionLcp(scene.bodies, scene.contacts, unison::ResolverOptions{});
            const bool same = assembled.n == hand.lcp.n && assembled.A == hand.lcp.A && assembled.b == hand.lcp.b;
            std::printf("\ncross-check jammed_e0.5: assembleCollisionLcp(scene) %s the hand-built infeasible LCP\n",
                        same ? "matches" : "DIFFERS FROM");
        }

        std::printf("\nsummary\n");
        if (const Row* p = findRow(rows, "pyramid20_nondegenerate")) {
            // The same n = 800 contact LCP with its exact ties removed: the one both solvers can solve, so the fair
            // speed comparison.
            const double speedup = p->siconos.timing.bestMs / std::max(p->cold.timing.bestMs, 1e-9);
            const bool pass = p->unisonRight && p->siconosRight && speedup >= 10.0;
            std::printf("target pyramid20 (ties removed, both must solve) cold speedup >= 10x: %s (measured %.1fx, "
                        "unison %s ms, siconos %s ms%s)\n",
                        pass ? "PASS" : "FAIL", speedup, fmtMs(p->cold.timing.bestMs).c_str(),
                        fmtMs(p->siconos.timing.bestMs).c_str(), p->siconosRight ? "" : ", siconos FAILED");
        }
        if (const Row* p = findRow(rows, "pyramid20")) {
            const double speedup = p->siconos.timing.bestMs / std::max(p->cold.timing.bestMs, 1e-9);
            const bool pass = p->unisonRight && speedup >= 10.0;
            std::printf("target pyramid20 cold speedup >= 10x: %s (measured %.1fx, unison %s %s ms, siconos %s ms%s)\n",
                        pass ? "PASS" : "FAIL", speedup, statusString(p->cold.result.status).c_str(),
                        fmtMs(p->cold.timing.bestMs).c_str(), fmtMs(p->siconos.timing.bestMs).c_str(),
                        p->siconosRight ? "" : ", siconos FAILED: its time is a wrong answer's or its cap's");
            if (p->warmRan) {
                const bool warmPass = p->warm.result.status == LcpStatus::solved && p->warm.timing.bestMs < 1.0 &&
                                      p->warm.result.pivots <= 5;
                std::printf("warm start at n≈800 (pyramid20): pivots %d, time %s ms: %s (< 1 ms, <= 5 pivots)\n",
                            p->warm.result.pivots, fmtMs(p->warm.timing.bestMs).c_str(), warmPass ? "PASS" : "FAIL");
            } else {
                std::printf("warm start at n≈800 (pyramid20): FAIL (cold solve did not succeed)\n");
            }
        } else {
            std::printf("target pyramid20 cold speedup >= 10x: n/a (not run%s)\n", quick ? " in --quick" : "");
            std::printf("warm start at n≈800: n/a (not run%s)\n", quick ? " in --quick" : "");
        }
        if (const Row* p = findRow(rows, "pyramid10_friction"); p && p->warmRan) {
            std::printf("warm start, friction n≈800 (pyramid10_friction): pivots %d, time %s ms (info only)\n",
                        p->warm.result.pivots, fmtMs(p->warm.timing.bestMs).c_str());
        }
        int hard = 0, unisonHard = 0, siconosHard = 0;
        std::string unisonMisses;
        for (const Row& r : rows) {
            if (!isHardFamily(r.c->name)) continue;
            ++hard;
            if (r.unisonRight) ++unisonHard;
            else unisonMisses += " " + r.c->name;
            if (r.siconosRight) ++siconosHard;
        }
        std::printf("hard families right status: %d/%d%s%s (siconos %d/%d)\n", unisonHard, hard,
                    unisonMisses.empty() ? "" : "  missed:", unisonMisses.c_str(), siconosHard, hard);
        int all = 0, unisonAll = 0;
        for (const Row& r : rows) {
            ++all;
            if (r.unisonRight) ++unisonAll;
        }
        std::printf("all cases right status: %d/%d\n", unisonAll, all);

        const nlohmann::json manifolds = unison::bench::runManifoldFamily(quick, budgetMs, filter);

        if (!jsonPath.empty()) {
            nlohmann::json out;
            out["quick"] = quick;
            out["cases"] = nlohmann::json::array();
            for (const Row& r : rows) out["cases"].push_back(toJson(r));
            out["box2d_manifold_cases"] = manifolds;
            std::ofstream file(jsonPath);
            file << out.dump(2) << "\n";
            if (!file) std::fprintf(stderr, "bench_lcp: could not write %s\n", jsonPath.c_str());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_lcp: %s\n", e.what());
        return 1;
    }
    return 0;
}
