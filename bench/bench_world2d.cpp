// bench/bench_world2d.cpp — Unison's World2 against Box2D 2.4.1 on the same 2D scenes, in one run (issue 3).
//
// Each scene comes from scenes/make_scenes2d as JSON, with sleeping off so both engines do the full work every
// step; Unison loads it through scenes::loadScene2, Box2D through bench/box2d_peer. Each engine runs the same
// number of steps in a loop timed with steady_clock (read after every step, so the time of the first K steps is
// known too). Unison's World2::stats() is read every step for the largest complementarity residual, the deepest
// penetration and the islands whose friction LCP failed.
//
// "Stack stayed up" (pyramids): the last body of a pyramid scene is its top box. The testbed layout leaves 0.25 m
// between rows, so the top box falls rows * 0.25 m before it lands (sqrt(rows / 20) s). Its position at the settle
// step (that landing time plus --settle-seconds, when the pile has come to rest) is the reference; the stack stayed
// up when the top box settled near its standing height (within 0.5 m; Box2D's 1 cm shape skin lifts it a little)
// and afterwards moved less than 5 cm from the reference horizontally and never sank more than 5 cm below it.
// Rising is not falling: Box2D's pile, compressed by the landing, keeps decompressing towards its skin-to-skin
// height for many seconds (its 20-row top rises about 13 cm between 2 s and 12 s, at under 1 cm/s), so a rise is
// allowed up to the standing height + 0.5 m (beyond that the box was thrown) and reported in the table. A run that
// ends before the settle step is not judged ("n/a"); --quick runs are mostly too short for it.
//
// Unison is still slow on big landing piles (seconds per step on a 20-row pyramid, README "The 2D world"), so
// Unison's loop stops once it has used --budget-seconds on a scene and the row says "stopped after K steps"; a
// step that has started is never interrupted. The step-time ratio is then taken over the K steps both engines ran.
// Benchmarks report; they never gate CI: the exit code is 0 unless something threw.
//
// pyramid40's budget is at least --stand-budget-seconds (default 900), so its stand test is judged in a default run.
//
// Usage: bench_world2d [--quick] [--steps N] [--budget-seconds S] [--settle-seconds S] [--stand-seconds S]
//                      [--stand-budget-seconds S] [--filter SUBSTRING] [--json FILE]
#include "box2d_peer.h"
#include "make_scenes2d.h"
#include "scene_json.h"
#include "world2d.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace {

using unison::Vec2;
using Clock = std::chrono::steady_clock;

constexpr double kStandTolerance = 0.05;     // m: the top box may move (sideways, or down) this much and stand
constexpr double kSettledHeightSlack = 0.5;  // m: the settled top box is this close to its standing height

struct SceneSpec {
    std::string name;
    std::string description;
    nlohmann::json scene;
    int steps = 0;               // steps both engines run
    bool pyramid = false;        // judge "stack stayed up" on the last body
    double standingTopY = 0.0;   // centre height of the top box of a perfectly stacked pile (m)
    double landingSeconds = 0.0; // time the top box falls before it lands (s)
    double minBudgetSeconds = 0.0;  // Unison's budget on this scene is at least this (pyramid40's stand test)
};

// A pyramid scene of `rows` rows: the top box stands at rows - 0.5 m and falls rows * 0.25 m before it lands.
SceneSpec pyramidSpec(std::string name, std::string description, nlohmann::json scene, int steps, int rows) {
    SceneSpec spec{std::move(name), std::move(description), std::move(scene), steps, true, rows - 0.5, 0.0};
    spec.landingSeconds = std::sqrt(2.0 * 0.25 * rows / 10.0);
    return spec;
}

// The settle step of a scene: the top box has landed and had `settleSeconds` to come to rest.
int settleStepOf(const SceneSpec& spec, double settleSeconds, double hz) {
    return int(std::lround((spec.landingSeconds + settleSeconds) * hz));
}

// One engine's run of one scene.
struct EngineRun {
    int steps = 0;                 // steps done
    bool stopped = false;          // stopped early by the time budget
    std::vector<double> cumMs;     // (steps) time from the loop start to the end of step k + 1
    std::vector<Vec2> top;         // (steps) position of the last body after step k + 1
    double worstStepMs = 0.0;
    double totalMs() const { return cumMs.empty() ? 0.0 : cumMs.back(); }
    double msPerStep() const { return steps > 0 ? totalMs() / steps : 0.0; }
};

// Unison's step statistics accumulated over a run.
struct UnisonStats {
    double maxResidual = 0.0;
    double maxPenetration = 0.0;
    std::int64_t failedIslands = 0;
    std::int64_t pivots = 0;
    int maxIslandPivots = 0;
};

// Verdict on "stack stayed up" for one engine.
struct Standing {
    bool judged = false;       // the run went past the settle step
    bool settledUp = false;    // top box settled near its standing height
    bool stood = false;        // settledUp, then sideways and downward moves < kStandTolerance, no throw upwards
    double maxSideways = 0.0;  // m, largest |x - x_ref| after the settle step
    double maxDrop = 0.0;      // m, largest y_ref - y after the settle step (>= 0)
    double maxRise = 0.0;      // m, largest y - y_ref after the settle step (>= 0)
    double secondsAfterSettle = 0.0;
};

struct Row {
    const SceneSpec* spec = nullptr;
    int bodies = 0;
    EngineRun unison, box2d;
    UnisonStats stats;
    int settleStep = 0;
    Standing unisonStand, box2dStand;
    int commonSteps = 0;       // steps both engines ran
    double ratio = 0.0;        // Unison time / Box2D time over the common steps
    double topGap = 0.0;       // m, distance between the engines' top bodies after the last common step
};

// Runs `step` up to `steps` times, recording the last body's position through `top` after each step, until the
// loop has used `budgetSeconds`.
EngineRun runEngine(int steps, double budgetSeconds, const std::function<void()>& step, const std::function<Vec2()>& top,
                    const std::function<void()>& afterStep) {
    EngineRun run;
    run.cumMs.reserve(std::size_t(steps));
    run.top.reserve(std::size_t(steps));
    const Clock::time_point start = Clock::now();
    double previousMs = 0.0;
    for (int k = 0; k < steps; ++k) {
        step();
        afterStep();
        run.top.push_back(top());
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        run.cumMs.push_back(ms);
        run.worstStepMs = std::max(run.worstStepMs, ms - previousMs);
        previousMs = ms;
        run.steps = k + 1;
        if (ms > 1e3 * budgetSeconds && k + 1 < steps) {
            run.stopped = true;
            break;
        }
    }
    return run;
}

Standing judgeStanding(const EngineRun& run, int settleStep, double standingTopY, double hz) {
    Standing s;
    if (run.steps <= settleStep) return s;
    s.judged = true;
    const Vec2 ref = run.top[std::size_t(settleStep - 1)];
    s.settledUp = std::fabs(ref.y - standingTopY) <= kSettledHeightSlack;
    for (int k = settleStep; k < run.steps; ++k) {
        const Vec2 p = run.top[std::size_t(k)];
        s.maxSideways = std::max(s.maxSideways, std::fabs(p.x - ref.x));
        s.maxDrop = std::max(s.maxDrop, ref.y - p.y);
        s.maxRise = std::max(s.maxRise, p.y - ref.y);
    }
    const bool thrown = ref.y + s.maxRise > standingTopY + kSettledHeightSlack;
    s.stood = s.settledUp && s.maxSideways < kStandTolerance && s.maxDrop < kStandTolerance && !thrown;
    s.secondsAfterSettle = (run.steps - settleStep) / hz;
    return s;
}

Row runScene(const SceneSpec& spec, double budgetSeconds, double settleSeconds) {
    Row row;
    row.spec = &spec;
    const double hz = spec.scene.value("hz", 60.0);
    row.settleStep = settleStepOf(spec, settleSeconds, hz);

    {
        unison::bench::Box2dPeer peer(spec.scene, spec.name);
        row.bodies = peer.bodyCount();
        const int last = peer.bodyCount() - 1;
        row.box2d = runEngine(spec.steps, budgetSeconds, [&] { peer.step(); }, [&] { return peer.position(last); }, [] {});
    }
    {
        unison::scenes::LoadedScene2 loaded = unison::scenes::loadScene2(spec.scene, spec.name);
        unison::World2& world = *loaded.world;
        const unison::BodyId last = loaded.bodies.back();
        UnisonStats& st = row.stats;
        row.unison = runEngine(
            spec.steps, budgetSeconds, [&] { world.step(); }, [&] { return world.state(last)->position; },
            [&] {
                const unison::StepStats2& s = world.stats();
                st.maxResidual = std::max(st.maxResidual, s.maxResidual);
                st.maxPenetration = std::max(st.maxPenetration, s.maxPenetration);
                st.failedIslands += s.failedIslands;
                st.pivots += s.pivots;
                st.maxIslandPivots = std::max(st.maxIslandPivots, s.maxIslandPivots);
            });
    }
    row.commonSteps = std::min(row.unison.steps, row.box2d.steps);
    if (row.commonSteps > 0) {
        const std::size_t k = std::size_t(row.commonSteps - 1);
        row.ratio = row.unison.cumMs[k] / std::max(row.box2d.cumMs[k], 1e-9);
        const Vec2 d = row.unison.top[k] - row.box2d.top[k];
        row.topGap = std::sqrt(d.x * d.x + d.y * d.y);
    }
    if (spec.pyramid) {
        row.unisonStand = judgeStanding(row.unison, row.settleStep, spec.standingTopY, hz);
        row.box2dStand = judgeStanding(row.box2d, row.settleStep, spec.standingTopY, hz);
    }
    return row;
}

std::string fmt(const char* format, double x) {
    char buf[48];
    std::snprintf(buf, sizeof buf, format, x);
    return buf;
}

std::string fmtMs(double ms) { return fmt(ms < 1.0 ? "%.4f" : ms < 100.0 ? "%.2f" : "%.0f", ms); }

std::string standText(const Row& r, const Standing& s) {
    if (!r.spec->pyramid) return "-";
    if (!s.judged) return "n/a";
    if (!s.settledUp) return "no(fell)";
    return s.stood ? "yes" : "no";
}

std::string moveText(const Row& r, const Standing& s) {
    if (!r.spec->pyramid || !s.judged) return "-";
    return fmt("%.1f", 100.0 * s.maxSideways) + fmt("/%.1f", 100.0 * s.maxDrop) + fmt("/%.1f", 100.0 * s.maxRise);
}

const Row* findRow(const std::vector<Row>& rows, const std::string& name) {
    for (const Row& r : rows) {
        if (r.spec->name == name) return &r;
    }
    return nullptr;
}

std::string stoppedNote(const Row& r) {
    return r.unison.stopped ? "unison stopped after " + std::to_string(r.unison.steps) + " of " +
                                  std::to_string(r.spec->steps) + " steps (too slow)"
                            : "";
}

nlohmann::json toJson(const Row& r) {
    auto engine = [](const EngineRun& e) {
        return nlohmann::json{{"steps", e.steps}, {"stopped", e.stopped}, {"total_ms", e.totalMs()},
                              {"ms_per_step", e.msPerStep()}, {"worst_step_ms", e.worstStepMs},
                              {"top_final", {e.top.empty() ? 0.0 : e.top.back().x, e.top.empty() ? 0.0 : e.top.back().y}}};
    };
    auto stand = [](const Standing& s) {
        return nlohmann::json{{"judged", s.judged}, {"settled_up", s.settledUp}, {"stood", s.stood},
                              {"max_sideways_m", s.maxSideways}, {"max_drop_m", s.maxDrop},
                              {"max_rise_m", s.maxRise}, {"seconds_after_settle", s.secondsAfterSettle}};
    };
    nlohmann::json j;
    j["scene"] = r.spec->name;
    j["bodies"] = r.bodies;
    j["planned_steps"] = r.spec->steps;
    j["unison"] = engine(r.unison);
    j["unison"]["max_residual"] = r.stats.maxResidual;
    j["unison"]["max_penetration_m"] = r.stats.maxPenetration;
    j["unison"]["failed_islands"] = r.stats.failedIslands;
    j["unison"]["pivots"] = r.stats.pivots;
    j["unison"]["max_island_pivots"] = r.stats.maxIslandPivots;
    j["box2d"] = engine(r.box2d);
    j["common_steps"] = r.commonSteps;
    j["ratio"] = r.ratio;
    j["top_gap_m"] = r.topGap;
    if (r.spec->pyramid) {
        j["settle_step"] = r.settleStep;
        j["unison"]["standing"] = stand(r.unisonStand);
        j["box2d"]["standing"] = stand(r.box2dStand);
    }
    return j;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Unison World2 vs Box2D 2.4.1 on the shared 2D scenes (sleeping off)"};
    bool quick = false;
    int steps = 300;
    double budgetSeconds = 60.0;
    double settleSeconds = 1.0;
    double standSeconds = 10.0;
    double standBudgetSeconds = 900.0;
    std::string filter;
    std::string jsonPath;
    app.add_flag("--quick", quick, "60 steps of the small scenes only (CI smoke run)");
    app.add_option("--steps", steps, "steps per scene (default 300; --quick: 60)")->check(CLI::PositiveNumber);
    app.add_option("--budget-seconds", budgetSeconds, "stop Unison's run of a scene after this much time")
        ->check(CLI::PositiveNumber);
    app.add_option("--settle-seconds", settleSeconds,
                   "time a pyramid gets to come to rest after its top box lands (default 1; --quick: 0.25)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--stand-seconds", standSeconds,
                   "pyramid40 runs at least settle + this long, to judge 'stands 10 s' (default 10; not in --quick)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--stand-budget-seconds", standBudgetSeconds,
                   "pyramid40's budget is at least this, so 'stands 10 s' gets judged (default 900; its 745 steps "
                   "took about 380 s in the fourth session)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--filter", filter, "only scenes whose name contains this substring");
    app.add_option("--json", jsonPath, "also write the results as JSON to FILE");
    CLI11_PARSE(app, argc, argv);
    if (quick && app.count("--steps") == 0) steps = 60;
    if (quick && app.count("--settle-seconds") == 0) settleSeconds = 0.25;

    try {
        namespace sc = unison::scenes;
        const int hz = 60;  // every generated scene runs at 60 Hz
        std::vector<SceneSpec> specs;
        specs.push_back(pyramidSpec("pyramid20", "Box2D testbed pyramid, 20 rows (210 boxes)",
                                    sc::pyramidScene(20, 0.5, false), steps, 20));
        if (!quick) {
            // Long enough to judge "stands 10 s": settle step plus the stand time, or --steps if longer.
            SceneSpec p40 = pyramidSpec("pyramid40", "testbed layout, 40 rows (820 boxes)",
                                        sc::pyramidScene(40, 0.5, false), steps, 40);
            p40.steps = std::max(steps, settleStepOf(p40, settleSeconds, hz) + int(std::lround(standSeconds * hz)));
            p40.minBudgetSeconds = standBudgetSeconds;
            specs.push_back(std::move(p40));
        }
        specs.push_back(pyramidSpec("pyramids40x5", "40 separate 5-row pyramids (600 boxes)",
                                    sc::manyPyramidsScene(40, 5, false), steps, 5));
        if (!quick) {
            specs.push_back({"circles2000", "2000 circles r 0.25 dropped side by side (2000 one-contact islands)",
                             sc::scatteredCirclesScene(2000, false), steps, false, 0.0, 0.0});
            // Not a target of the issue, reported because it is Unison's weak case: the pile becomes one island
            // with ~6000 contacts (a friction LCP of ~24000 unknowns), solved by Lemke every step.
            specs.push_back({"circlepile2000", "2000 circles r 0.25 falling into a container (one pile)",
                             sc::fallingCirclesScene(2000, false), steps, false, 0.0, 0.0});
        }

        std::printf("bench_world2d: Unison World2 vs Box2D 2.4.1 (8 velocity / 3 position iterations), sleeping off, "
                    "60 Hz\n");
        std::printf("budget %.0f s of Unison time per scene (pyramid40: %.0f s); pyramids are judged from their settle step (top box "
                    "landed + %.2f s): the top box (last body) settled within %.1f m of its standing height, then moves < %.0f "
                    "cm sideways and sinks < %.0f cm (rising up to the standing height + %.1f m allowed)\n\n",
                    budgetSeconds, std::max(budgetSeconds, standBudgetSeconds), settleSeconds, kSettledHeightSlack, 100.0 * kStandTolerance, 100.0 * kStandTolerance,
                    kSettledHeightSlack);
        std::printf("%-13s %6s %6s | %10s %9s %9s %9s | %8s %7s %6s %7s | %6s %14s %14s %8s %8s %9s  %s\n", "scene",
                    "bodies", "steps", "U ms/step", "U worst", "B ms/step", "U/B", "max res", "pen mm", "failed",
                    "piv/stp", "settle", "U top cm", "B top cm", "U up", "B up", "U-B top m", "notes");

        std::vector<Row> rows;
        rows.reserve(specs.size());
        for (const SceneSpec& spec : specs) {
            if (!filter.empty() && spec.name.find(filter) == std::string::npos) continue;
            Row r = runScene(spec, std::max(budgetSeconds, spec.minBudgetSeconds), settleSeconds);
            std::string notes = stoppedNote(r);
            if (r.box2d.stopped) notes += (notes.empty() ? "" : "; ") + std::string("box2d stopped (budget)");
            const std::string settle = spec.pyramid ? std::to_string(r.settleStep) : "-";
            std::printf("%-13s %6d %6d | %10s %9s %9s %8.1fx | %8.1e %7.2f %6lld %7.0f | %6s %14s %14s %8s %8s %9.3f  %s\n",
                        spec.name.c_str(), r.bodies, r.unison.steps, fmtMs(r.unison.msPerStep()).c_str(),
                        fmtMs(r.unison.worstStepMs).c_str(), fmtMs(r.box2d.msPerStep()).c_str(), r.ratio,
                        r.stats.maxResidual, 1e3 * r.stats.maxPenetration, (long long)r.stats.failedIslands,
                        r.unison.steps > 0 ? double(r.stats.pivots) / r.unison.steps : 0.0, settle.c_str(),
                        moveText(r, r.unisonStand).c_str(), moveText(r, r.box2dStand).c_str(),
                        standText(r, r.unisonStand).c_str(), standText(r, r.box2dStand).c_str(), r.topGap, notes.c_str());
            std::fflush(stdout);
            rows.push_back(std::move(r));
        }
        std::printf("\ncolumns: U/B = Unison time / Box2D time over the steps both ran; max res = largest scaled "
                    "complementarity residual of any island; pen = deepest penetration; failed = islands whose "
                    "friction LCP failed (summed over steps); settle = step the stack is judged from; top cm = largest sideways move / drop / rise of the top box after settling; "
                    "up = stack stayed up; U-B top = distance between the engines' last bodies after the last common "
                    "step\n");

        std::printf("\nsummary\n");
        const std::string notRun = quick ? "n/a (not run in --quick)" : "n/a (filtered out)";
        if (const Row* p = findRow(rows, "pyramid20")) {
            const bool pass = !p->unison.stopped && p->ratio <= 4.0;
            const std::string note = stoppedNote(*p);
            std::printf("pyramid20 step time <= 4x Box2D: %s (%.1fx over %d steps%s%s)\n", pass ? "PASS" : "FAIL",
                        p->ratio, p->commonSteps, note.empty() ? "" : "; ", note.c_str());
        } else {
            std::printf("pyramid20 step time <= 4x Box2D: %s\n", notRun.c_str());
        }
        {
            const Row* a = findRow(rows, "pyramids40x5");
            const Row* b = findRow(rows, "circles2000");
            std::string detail;
            bool allPass = true;
            for (const auto& [r, label] : {std::pair{a, "40 pyramids "}, std::pair{b, "2000 circles "}}) {
                if (!detail.empty()) detail += ", ";
                if (!r) {
                    detail += label + notRun;
                    continue;
                }
                detail += label + fmt("%.1fx", r->ratio);
                if (r->unison.stopped) detail += " (" + stoppedNote(*r) + ")";
                allPass = allPass && !r->unison.stopped && r->ratio <= 2.0;
            }
            // A failure on part of the scenes fails the target; a pass on part of them does not pass it.
            const char* verdict = !allPass ? "FAIL" : (a && b) ? "PASS" : "n/a";
            std::printf("many small islands (40 pyramids, 2000 circles) <= 2x Box2D: %s (%s)\n", verdict, detail.c_str());
        }
        if (const Row* p = findRow(rows, "pyramid40")) {
            auto verdict = [&](const Standing& s, const EngineRun& e) -> std::string {
                const std::string why = e.stopped ? "stopped after " + std::to_string(e.steps) + " steps: too slow"
                                                  : "run too short";
                if (!s.judged) return "no (" + why + ", before the settle step)";
                const std::string moves = fmt("sideways %.1f cm", 100.0 * s.maxSideways) +
                                          fmt(", drop %.1f cm", 100.0 * s.maxDrop) +
                                          fmt(", rise %.1f cm", 100.0 * s.maxRise);
                if (!s.settledUp) return "no (fell before settling)";
                if (!s.stood) return "no (" + moves + ")";
                if (s.secondsAfterSettle + 1e-9 < standSeconds)
                    return "no (stood " + fmt("%.1f s, then ", s.secondsAfterSettle) + why + ")";
                return "yes (" + moves + ")";
            };
            std::printf("pyramid40 stands %.0f s (top moves < 5 cm sideways, sinks < 5 cm): unison %s, box2d %s\n", standSeconds,
                        verdict(p->unisonStand, p->unison).c_str(), verdict(p->box2dStand, p->box2d).c_str());
        } else {
            std::printf("pyramid40 stands %.0f s (top moves < 5 cm sideways, sinks < 5 cm): %s\n", standSeconds, notRun.c_str());
        }

        if (!jsonPath.empty()) {
            nlohmann::json out;
            out["quick"] = quick;
            out["budget_seconds"] = budgetSeconds;
            out["stand_budget_seconds"] = standBudgetSeconds;
            out["scenes"] = nlohmann::json::array();
            for (const Row& r : rows) out["scenes"].push_back(toJson(r));
            std::ofstream file(jsonPath);
            file << out.dump(2) << "\n";
            if (!file) std::fprintf(stderr, "bench_world2d: could not write %s\n", jsonPath.c_str());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_world2d: %s\n", e.what());
        return 1;
    }
    return 0;
}
