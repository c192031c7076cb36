// bench/bench_world3d.cpp — Unison's World3 against Bullet 3.24 (double precision) on the same 3D scenes, in one
// run: Bullet's sequential-impulse solver (SI) and Bullet's MLCP solver with btLemkeSolver.
//
// Scenes (scenes/make_scenes3d, sleeping off so every engine does the full work every step):
//   stack   5 cubes of 1 m: resting centre heights after the run. Tolerance: every cube within 2 cm of Bullet SI's.
//   spheres 5 balls dropped 4 m with e = 0, 1/4, ..., 1: apex of the first rebound, against the closed form e^2 h and
//           against Bullet SI. Tolerance: 5 % of h (a bounce that starts inside a step may gain up to (1 + e) v dt).
//   pile    100 cubes of 0.5 m dropped into a pen, twice: landing flat in 25 columns, and landing on edges and
//           toppling (scenes::boxPile3Scene). Both settle as 5 islands of 5 columns: the top layers, turned and
//           shifted, rest on their neighbours.
//   drop    100 cubes of 0.5 m tilted 0.3 rad, dropped in 4 layers from up to 6.4 m into the same pen, landing on
//           corners into one heap (scenes::dropHeap3Scene).
//           For pile and drop: each engine's mean and worst step time, the ratios Unison / Bullet SI, the mean height
//           of the cubes, the deepest penetration, Unison's largest complementarity residual, pivots per step and
//           fallbacks (Unison: islands whose friction LCP failed and got the bounded approximation; Bullet MLCP:
//           solves that fell back to SI). Targets for the heaps: step time <= 4x Bullet SI's, worst step <= 20x
//           Bullet SI's worst, penetration <= 2 cm, residual <= 1e-6, no fallback. An engine that has used
//           --budget-seconds of step time stops there (Unison and Bullet's MLCP take far longer per step once a pile
//           is one island); the table says how many steps each ran.
// Timings are steady_clock around each step() call. Benchmarks report; the exit code is 0 unless something threw.
//
// --validate (ctest's bullet_agreement) runs only the stack and the spheres and exits 1 outside a tolerance.
//
// Usage: bench_world3d [--quick] [--validate] [--pile-steps N] [--pile-boxes N] [--budget-seconds S] [--json FILE]
#include "bullet_peer.h"
#include "make_scenes3d.h"
#include "scene_json3d.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace {

using namespace unison;
using bench::BulletPeer;
using bench::BulletSolver;
using Clock = std::chrono::steady_clock;

// One engine behind a common face: step, body centre, body velocity, and what it reports.
struct Engine {
    std::string name;
    std::function<void()> step;
    std::function<Vec3(int)> center;
    std::function<Vec3(int)> velocity;
    double seconds = 0.0;
    double maxResidual = 0.0;
    double maxApproximateResidual = 0.0;                      // Unison only: of the islands given the approximation
    double maxPenetration = 0.0;                              // m, deepest over the steps run
    std::function<double()> penetration = [] { return 0.0; };  // deepest penetration of the last step (m)
    int failed = 0;
    long pivots = 0, discardedGuesses = 0, basisChange = 0, pathIslands = 0, restarts = 0;  // Unison only (StepStats)
    int pivotSteps = 0;                                       // steps with at least one pivot
    std::function<int()> fallbacks = [] { return 0; };
};

struct Engines {
    scenes::LoadedScene3 unison;
    std::unique_ptr<BulletPeer> si, mlcp;
    std::vector<Engine> list;
};

Vec3 toVec(const std::array<double, 3>& a) { return Vec3(a[0], a[1], a[2]); }

// Builds Unison, Bullet SI and (optionally) Bullet MLCP-Lemke on the same scene.
std::unique_ptr<Engines> makeEngines(const nlohmann::json& scene, bool withMlcp) {
    auto e = std::make_unique<Engines>();
    e->unison = scenes::loadScene3(scene, "scene");
    World3* w = e->unison.world.get();
    const std::vector<BodyId> ids = e->unison.bodies;
    Engine u;
    u.name = "Unison (exact LCP)";
    Engines* self = e.get();
    u.step = [w, self] {
        w->step();
        self->list[0].maxResidual = std::max(self->list[0].maxResidual, w->stats().maxResidual);
        Engine& me = self->list[0];
        const StepStats3& st = w->stats();
        me.failed += st.failedIslands;
        me.maxApproximateResidual = std::max(me.maxApproximateResidual, st.maxApproximateResidual);
        me.pivots += st.pivots;
        me.pivotSteps += st.pivots > 0 ? 1 : 0;
        me.discardedGuesses += st.discardedGuesses;
        me.basisChange += st.basisChange;
        me.pathIslands += st.activeSetIslands;
        me.restarts += st.interiorPointRestarts;
    };
    u.fallbacks = [self] { return self->list[0].failed; };  // friction LCPs replaced by the frictionless one
    u.penetration = [w] { return w->stats().maxPenetration; };
    u.center = [w, ids](int i) { return w->state(ids[std::size_t(i)])->center; };
    u.velocity = [w, ids](int i) { return w->state(ids[std::size_t(i)])->velocity; };
    e->list.push_back(u);
    for (BulletSolver kind : {BulletSolver::sequentialImpulse, BulletSolver::mlcpLemke}) {
        if (kind == BulletSolver::mlcpLemke && !withMlcp) continue;
        auto& peer = kind == BulletSolver::mlcpLemke ? e->mlcp : e->si;
        peer = std::make_unique<BulletPeer>(scene, kind);
        BulletPeer* p = peer.get();
        Engine b;
        b.name = BulletPeer::solverName(kind);
        b.step = [p] { p->step(); };
        b.center = [p](int i) { return toVec(p->center(i)); };
        b.velocity = [p](int i) { return toVec(p->velocity(i)); };
        b.fallbacks = [p] { return p->fallbacks(); };
        b.penetration = [p] { return p->maxPenetration(); };
        e->list.push_back(b);
    }
    return e;
}

void timedStep(Engine& e) {
    const auto t0 = Clock::now();
    e.step();
    e.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    e.maxPenetration = std::max(e.maxPenetration, e.penetration());
}

nlohmann::json runStack(int steps) {
    const int n = 5;
    auto e = makeEngines(scenes::boxStack3Scene(n, false), true);
    for (int s = 0; s < steps; ++s)
        for (Engine& eng : e->list) timedStep(eng);
    std::printf("\nstack: 5 cubes of 1 m, %d steps; resting centre heights (m)\n", steps);
    std::printf("  %-30s", "box");
    for (int i = 1; i <= n; ++i) std::printf(" %8d", i);
    std::printf("\n");
    nlohmann::json out = {{"steps", steps}};
    double worst = 0.0;
    for (Engine& eng : e->list) {
        std::printf("  %-30s", eng.name.c_str());
        for (int i = 1; i <= n; ++i) {
            const double y = eng.center(i).y();
            std::printf(" %8.4f", y);
            out[eng.name].push_back(y);
            if (&eng != &e->list[1]) continue;
            worst = std::max(worst, std::fabs(y - e->list[0].center(i).y()));
        }
        std::printf("\n");
    }
    const bool ok = worst <= 0.02;
    std::printf("  largest |Unison - Bullet SI| = %.4f m (tolerance 0.02 m): %s\n", worst, ok ? "within" : "OUTSIDE");
    out["max_difference_vs_si"] = worst;
    out["within_tolerance"] = ok;
    return out;
}

nlohmann::json runSpheres(int steps) {
    auto e = makeEngines(scenes::spheres3Scene(false), true);
    const int n = 5;
    const double h = 4.0, r = 0.5;
    std::vector<std::vector<double>> apex(e->list.size(), std::vector<double>(n, -1.0));
    std::vector<std::vector<int>> bounces(e->list.size(), std::vector<int>(n, 0));
    std::vector<std::vector<double>> prevVy(e->list.size(), std::vector<double>(n, -1.0));
    for (int s = 0; s < steps; ++s) {
        for (std::size_t k = 0; k < e->list.size(); ++k) {
            Engine& eng = e->list[k];
            timedStep(eng);
            for (int i = 0; i < n; ++i) {
                const double vy = eng.velocity(i + 1).y();
                if (prevVy[k][std::size_t(i)] < 0.0 && vy > 0.0) ++bounces[k][std::size_t(i)];
                if (bounces[k][std::size_t(i)] == 1 && prevVy[k][std::size_t(i)] > 0.0 && vy <= 0.0 && apex[k][std::size_t(i)] < 0.0)
                    apex[k][std::size_t(i)] = eng.center(i + 1).y() - r;
                prevVy[k][std::size_t(i)] = vy;
            }
        }
    }
    std::printf("\nspheres: 5 balls dropped %.0f m, first rebound height (m) (-: no rebound)\n", h);
    std::printf("  %-30s", "e");
    for (int i = 0; i < n; ++i) std::printf(" %8.2f", i / 4.0);
    std::printf("\n  %-30s", "closed form e^2 h");
    for (int i = 0; i < n; ++i) std::printf(" %8.3f", (i / 4.0) * (i / 4.0) * h);
    std::printf("\n");
    nlohmann::json out = {{"steps", steps}};
    double worstForm = 0.0, worstSi = 0.0;
    for (std::size_t k = 0; k < e->list.size(); ++k) {
        std::printf("  %-30s", e->list[k].name.c_str());
        for (int i = 0; i < n; ++i) {
            const double a = std::max(0.0, apex[k][std::size_t(i)]);
            if (apex[k][std::size_t(i)] < 0.0) std::printf(" %8s", "-");
            else std::printf(" %8.3f", a);
            out[e->list[k].name].push_back(a);
            if (k == 0) {
                worstForm = std::max(worstForm, std::fabs(a - (i / 4.0) * (i / 4.0) * h));
                worstSi = std::max(worstSi, std::fabs(a - std::max(0.0, apex[1][std::size_t(i)])));
            }
        }
        std::printf("\n");
    }
    std::printf("  Unison: largest |apex - e^2 h| = %.3f m, largest |Unison - Bullet SI| = %.3f m (tolerance %.2f m = 5%% of h)\n",
                worstForm, worstSi, 0.05 * h);
    out["max_difference_closed_form"] = worstForm;
    out["max_difference_vs_si"] = worstSi;
    out["within_tolerance"] = worstForm <= 0.05 * h && worstSi <= 0.05 * h;
    return out;
}

// A heap of `boxes` cubes (bodies 2 .. boxes + 1 after the ground and the pen): every engine runs up to `steps`
// steps or its budget of step time.
nlohmann::json runPile(const std::string& title, const nlohmann::json& scene, int steps, int boxes, double budget,
                       bool heapTargets) {
    auto e = makeEngines(scene, true);
    // Engines step in turn; one that has used `budget` seconds stops (a started step is never interrupted). The
    // target ratio to Bullet SI is taken over the steps Unison and SI both ran (Bullet's MLCP, which stops first on
    // the heaps, does not shorten it); the MLCP ratio over the steps all three ran.
    std::vector<std::vector<double>> times(e->list.size());
    for (int s = 0; s < steps; ++s) {
        for (std::size_t k = 0; k < e->list.size(); ++k) {
            Engine& eng = e->list[k];
            if (eng.seconds >= budget) continue;
            const double before = eng.seconds;
            timedStep(eng);
            times[k].push_back(eng.seconds - before);
        }
    }
    std::size_t common = std::size_t(steps);
    for (const auto& t : times) common = std::min(common, t.size());
    const std::size_t withSi = std::min(times[0].size(), times[1].size());
    auto firstSteps = [&](std::size_t k, std::size_t count) {
        double sum = 0.0;
        for (std::size_t i = 0; i < count; ++i) sum += times[k][i];
        return sum;
    };
    auto worstOf = [&](std::size_t k) {
        double worst = 0.0;
        for (double t : times[k]) worst = std::max(worst, t);
        return worst;
    };
    std::printf("\n%s: %d cubes, up to %d steps (%.1f s), sleeping off, budget %.0f s per engine\n", title.c_str(),
                boxes, steps, steps / 60.0, budget);
    std::printf("  %-30s %7s %12s %12s %14s %10s %12s %10s\n", "engine", "steps", "ms/step", "worst ms", "mean height m",
                "pen mm", "residual", "fallbacks");
    nlohmann::json out = {{"steps", steps}, {"boxes", boxes}, {"common_steps", common}};
    for (std::size_t k = 0; k < e->list.size(); ++k) {
        Engine& eng = e->list[k];
        double mean = 0.0;
        for (int i = 0; i < boxes; ++i) mean += eng.center(i + 2).y() / boxes;
        char residual[32] = "-";
        if (k == 0) std::snprintf(residual, sizeof residual, "%.1e", eng.maxResidual);
        const int ran = int(times[k].size());
        std::printf("  %-30s %7d %12.3f %12.3f %14.4f %10.1f %12s %10d\n", eng.name.c_str(), ran, 1e3 * eng.seconds / ran,
                    1e3 * worstOf(k), mean, 1e3 * eng.maxPenetration, residual, eng.fallbacks());
        out[eng.name] = {{"steps", ran}, {"ms_per_step", 1e3 * eng.seconds / ran}, {"worst_step_ms", 1e3 * worstOf(k)},
                         {"mean_height", mean}, {"max_penetration_m", eng.maxPenetration}, {"fallbacks", eng.fallbacks()}};
    }
    const Engine& un = e->list[0];
    // Why Unison pivots: the active set moves (basisChange: a pivot changes at most two of its unknowns), and a
    // stale guess is abandoned for a cold start (discarded) after a wasted warm path.
    std::printf("  Unison pivots: %ld in %d of %zu steps (%.0f per step); basis change %ld (%.2f pivots per changed "
                "unknown); guesses discarded for a cold start: %ld\n", un.pivots, un.pivotSteps, times[0].size(),
                times[0].empty() ? 0.0 : double(un.pivots) / double(times[0].size()), un.basisChange,
                un.basisChange > 0 ? double(un.pivots) / double(un.basisChange) : 0.0, un.discardedGuesses);
    // Islands of 64+ contacts go to the active-set path first (docs/solver.md); Lemke takes what it does not certify.
    std::printf("  Unison islands answered by the active-set path: %ld (interior-point restarts %ld)\n", un.pathIslands,
                un.restarts);
    out["unison_path_islands"] = un.pathIslands;
    out["unison_interior_point_restarts"] = un.restarts;
    out["unison_pivots"] = un.pivots;
    out["unison_basis_change"] = un.basisChange;
    out["unison_discarded_guesses"] = un.discardedGuesses;
    const double u = firstSteps(0, withSi), si = firstSteps(1, withSi);
    const double uCommon = firstSteps(0, common), siCommon = firstSteps(1, common), mlcp = firstSteps(2, common);
    const double worstRatio = worstOf(0) / std::max(worstOf(1), 1e-12);
    const bool allRan = int(times[0].size()) == steps;
    auto verdict = [&](bool ok) { return ok ? "met" : "NOT met"; };
    std::printf("  over the first %zu steps: Unison / Bullet SI step time = %.2f (target <= %s): %s%s\n", withSi, u / si,
                heapTargets ? "4" : "2", verdict(u / si <= (heapTargets ? 4.0 : 2.0)),
                allRan ? "" : " (Unison stopped by its budget)");
    std::printf("  over the first %zu steps (all three ran): Unison / Bullet SI = %.2f; Bullet MLCP-Lemke / Unison step time = "
                "%.2f (info; an earlier target was >= 10)\n", common, uCommon / siCommon, mlcp / uCommon);
    if (heapTargets) {
        std::printf("  worst step: Unison / Bullet SI = %.1f (target <= 20): %s\n", worstRatio, verdict(worstRatio <= 20.0));
        std::printf("  Unison deepest penetration = %.1f mm (target <= 20 mm): %s\n", 1e3 * un.maxPenetration,
                    verdict(un.maxPenetration <= 0.02));
    }
    std::printf("  Unison largest complementarity residual = %.2e (target <= 1e-6): %s; islands whose friction LCP "
                "failed (fallbacks, target 0): %d\n", un.maxResidual, verdict(un.maxResidual <= 1e-6), un.failed);
    if (un.failed > 0)
        std::printf("  the failed islands got the approximation: its largest residual %.2e\n",
                    un.maxApproximateResidual);
    out["unison_over_si"] = u / si;
    out["unison_over_si_steps"] = withSi;
    out["unison_over_si_common_steps"] = uCommon / siCommon;
    out["unison_worst_over_si_worst"] = worstRatio;
    out["mlcp_over_unison"] = mlcp / uCommon;
    out["unison_max_residual"] = un.maxResidual;
    out["unison_max_penetration_m"] = un.maxPenetration;
    out["unison_failed_islands"] = un.failed;
    out["unison_max_approximate_residual"] = un.maxApproximateResidual;
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_world3d: Unison World3 vs Bullet 3.24 (SI and MLCP-Lemke) on the shared 3D scenes"};
    bool quick = false;
    int pileSteps = 300, pileBoxes = 100;
    double budget = 60.0;
    std::string jsonFile;
    bool validate = false;
    app.add_flag("--quick", quick, "short runs (smoke test)");
    app.add_flag("--validate", validate, "only the stack and spheres scenes; exit 1 when a tolerance is not met");
    app.add_option("--pile-steps", pileSteps, "steps of the pile scene")->check(CLI::PositiveNumber);
    app.add_option("--pile-boxes", pileBoxes, "cubes in the pile")->check(CLI::Range(1, 1000));
    app.add_option("--budget-seconds", budget, "pile: an engine stops after this much step time")->check(CLI::PositiveNumber);
    app.add_option("--json", jsonFile, "also write the results as JSON");
    CLI11_PARSE(app, argc, argv);
    if (quick) pileSteps = std::min(pileSteps, 30);
    nlohmann::json results;
    results["stack"] = runStack(quick ? 60 : 240);
    results["spheres"] = runSpheres(quick ? 120 : 240);
    if (validate) {
        const bool ok = results["stack"]["within_tolerance"].get<bool>() && results["spheres"]["within_tolerance"].get<bool>();
        std::printf("\nvalidation against Bullet SI and the closed forms: %s\n", ok ? "passed" : "FAILED");
        return ok ? 0 : 1;
    }
    const int boxes = quick ? std::min(pileBoxes, 25) : pileBoxes;
    const double pileBudget = quick ? std::min(budget, 5.0) : budget;
    results["pile_columns"] = runPile("pile (columns: cubes land flat)", scenes::boxPile3Scene(boxes, false, false),
                                      pileSteps, boxes, pileBudget, false);
    results["pile_heap"] = runPile("pile (heap: cubes land on edges and topple)", scenes::boxPile3Scene(boxes, true, false),
                                   pileSteps, boxes, pileBudget, true);
    results["drop_heap"] = runPile("drop heap (tilted cubes dropped from up to 6.4 m, landing on corners)",
                                   scenes::dropHeap3Scene(boxes, false), pileSteps, boxes,
                                   pileBudget, true);
    if (!jsonFile.empty()) std::ofstream(jsonFile) << results.dump(1) << "\n";
    return 0;
}
