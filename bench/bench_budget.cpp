// bench/bench_budget.cpp — per-step budgets and worker threads: Unison's step times on the scenes at budgets
// unlimited / 4 ms / 2 ms / 1 ms and on 1 and 2 threads, beside the peers' step times on the same scene JSON in
// the same run (Box2D 2.4.1 for 2D scenes, Bullet 3.24 sequential impulses for 3D ones).
//
// Scenes (sleeping off, so every engine does the full work every step):
//   pyramid40       the Box2D testbed pyramid, 40 rows (820 boxes): stands 10 s after it settles? (bench_world2d's
//                   criterion: top box within 0.5 m of its standing height 1 s after landing, then < 5 cm sideways,
//                   < 5 cm down)
//   pyramids40x5    40 separate 5-row pyramids (600 boxes, 40 islands)
//   circles2000     2000 circles dropped side by side (2000 one-contact islands)
//   circlepile2000  2000 circles falling into a container (one pile)
//   heap3d          100 cubes landing on edges and toppling into one heap (scenes::boxPile3Scene(100, true))
//   columns3d       100 cubes landing flat in 25 columns (scenes::boxPile3Scene(100, false))
//   drop3d          100 cubes tilted 0.3 rad dropped from up to 6.4 m, landing on corners (scenes::dropHeap3Scene)
// Per run: p50 / p99 / worst step time (steady_clock around each step), the share of exact islands (islands with
// contacts solved by their LCP, the rest got the bounded approximation), whether the stack stood or the heap
// settled (deepest penetration <= 2 cm and every cube slower than 0.1 m/s at the end), the work units and the
// measured ns per work unit beside the documented constant work::kNsPerUnit (target: within 2x; wall clock, and
// for 1 thread also the thread's CPU time, which other processes on a shared machine disturb less), and the final
// state hash, which must be the same for 1 and 2 threads. A run stops after --seconds of stepping (the unlimited
// budget needs seconds per step on the big landings); its row then says how many steps it ran.
// Benchmarks report; the exit code is 0 unless something threw.
//
// Usage: bench_budget [--quick] [--filter SUBSTRING] [--seconds S] [--budgets LIST] [--threads LIST]
//                     [--trace] [--json FILE]
#include "box2d_peer.h"
#include "bullet_peer.h"
#include "make_scenes2d.h"
#include "make_scenes3d.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "step_budget.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace unison;
using Clock = std::chrono::steady_clock;

struct SceneSpec {
    std::string name;
    nlohmann::json scene;
    int steps = 300;
    int pyramidRows = 0;  // > 0: judge "stands" on the last body
};

/// CPU time of the calling thread (ms).
double threadCpuMs() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// Step times of one run (ms) and their order statistics.
struct Times {
    std::vector<double> ms;
    double quantile(double q) const {
        if (ms.empty()) return 0.0;
        std::vector<double> s = ms;
        std::sort(s.begin(), s.end());
        return s[std::min(s.size() - 1, std::size_t(q * double(s.size())))];
    }
    double worst() const { return ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end()); }
    double total() const {
        double t = 0.0;
        for (double m : ms) t += m;
        return t;
    }
};

/// One Unison run of a scene at a budget and thread count.
struct UnisonRun {
    Times times;
    double cpuMs = 0.0;        // thread CPU time of the steps (1 thread: the step's own work, whatever else runs)
    bool stopped = false;
    std::uint64_t work = 0, maxWork = 0, maxMinimum = 0, overrun = 0;
    long exact = 0, approximate = 0;
    double maxPenetration = 0.0, maxApproxResidual = 0.0;
    std::string verdict;       // stands / fell / settled / not settled / n/a
    std::uint64_t finalHash = 0;
    double nsPerUnit() const { return work > 0 ? times.total() * 1e6 / double(work) : 0.0; }
    double cpuNsPerUnit() const { return work > 0 ? cpuMs * 1e6 / double(work) : 0.0; }
};

/// Stand verdict of a pyramid's top box (positions after each step), as bench_world2d judges it.
std::string standVerdict(const std::vector<Vec2>& top, int rows) {
    const int settle = int(std::lround((std::sqrt(2.0 * 0.25 * rows / 10.0) + 1.0) * 60.0));
    if (int(top.size()) < settle + 600) return "n/a (" + std::to_string(top.size()) + " steps)";
    const Vec2 ref = top[std::size_t(settle - 1)];
    double side = 0.0, drop = 0.0;
    for (std::size_t k = std::size_t(settle); k < top.size(); ++k) {
        side = std::max(side, std::fabs(top[k].x - ref.x));
        drop = std::max(drop, ref.y - top[k].y);
    }
    const bool up = std::fabs(ref.y - (rows - 0.5)) <= 0.5;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s (side %.1f cm, drop %.1f cm)", up && side < 0.05 && drop < 0.05 ? "stands" : "FELL",
                  100 * side, 100 * drop);
    return buf;
}

template <class World>
void record(UnisonRun& run, const World& w, double ms) {
    const StepStats& st = w.stats();
    run.times.ms.push_back(ms);
    run.work += st.work;
    run.maxWork = std::max(run.maxWork, st.work);
    run.maxMinimum = std::max(run.maxMinimum, st.minimumWork);
    run.overrun += st.overrun;
    run.exact += st.exactIslands;
    run.approximate += st.approximateIslands;
    run.maxPenetration = std::max(run.maxPenetration, st.maxPenetration);
    run.maxApproxResidual = std::max(run.maxApproxResidual, st.maxApproximateResidual);
}

UnisonRun runUnison(const SceneSpec& spec, std::uint64_t budget, int threads, double seconds, bool trace) {
    UnisonRun run;
    auto loop = [&](auto& world, auto&& afterStep) {
        world.setStepBudget(budget);
        world.setTaskSystem(TaskSystem{threads});
        double used = 0.0;
        for (int s = 0; s < spec.steps; ++s) {
            const double cpu0 = threadCpuMs();
            const auto t0 = Clock::now();
            world.step();
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            run.cpuMs += threadCpuMs() - cpu0;
            record(run, world, ms);
            afterStep();
            if (trace) {
                const StepStats& st = world.stats();
                std::printf("    step %4d %8.3f ms work %9llu min %9llu overrun %7llu exact %4d approx %3d pivots %6d "
                            "contacts %5d pen %.4f\n", s + 1, ms, (unsigned long long)st.work,
                            (unsigned long long)st.minimumWork, (unsigned long long)st.overrun, st.exactIslands,
                            st.approximateIslands, st.pivots, st.contacts, st.maxPenetration);
            }
            used += ms;
            if (used > 1e3 * seconds && s + 1 < spec.steps) {
                run.stopped = true;
                break;
            }
        }
        run.finalHash = world.stateHash();
    };
    if (spec.scene["dimension"] == 3) {
        auto loaded = scenes::loadScene3(spec.scene, spec.name);
        World3& w = *loaded.world;
        loop(w, [] {});
        double fastest = 0.0;
        for (BodyId id : loaded.bodies) fastest = std::max(fastest, std::sqrt(Dim3::dot(w.state(id)->velocity, w.state(id)->velocity)));
        const bool settled = run.maxPenetration <= 0.02 && fastest < 0.1;
        char buf[96];
        std::snprintf(buf, sizeof buf, "%s (pen %.1f cm, v %.2f)", run.stopped ? "n/a" : settled ? "settled" : "NOT SETTLED",
                      100 * run.maxPenetration, fastest);
        run.verdict = buf;
    } else {
        auto loaded = scenes::loadScene2(spec.scene, spec.name);
        World2& w = *loaded.world;
        std::vector<Vec2> top;
        const BodyId last = loaded.bodies.back();
        loop(w, [&] { top.push_back(w.state(last)->position); });
        run.verdict = spec.pyramidRows > 0 ? standVerdict(top, spec.pyramidRows) : "-";
    }
    return run;
}

/// The peer's step times on the same scene (Box2D 2.4.1 for 2D, Bullet SI for 3D).
Times runPeer(const SceneSpec& spec, double seconds) {
    Times t;
    std::function<void()> step;
    std::unique_ptr<bench::Box2dPeer> b2;
    std::unique_ptr<bench::BulletPeer> bullet;
    if (spec.scene["dimension"] == 3) {
        bullet = std::make_unique<bench::BulletPeer>(spec.scene, bench::BulletSolver::sequentialImpulse);
        step = [&] { bullet->step(); };
    } else {
        b2 = std::make_unique<bench::Box2dPeer>(spec.scene, spec.name);
        step = [&] { b2->step(); };
    }
    double used = 0.0;
    for (int s = 0; s < spec.steps && used < 1e3 * seconds; ++s) {
        const auto t0 = Clock::now();
        step();
        t.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        used += t.ms.back();
    }
    return t;
}

std::vector<double> parseList(const std::string& text) {
    std::vector<double> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(item == "unlimited" ? 0.0 : std::stod(item));
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_budget: Unison's step times under a per-step budget and on worker threads, beside Box2D "
                 "2.4.1 and Bullet 3.24"};
    bool quick = false, trace = false;
    std::string filter, jsonFile, budgetList = "unlimited,4,2,1", threadList = "1,2";
    double seconds = 30.0;
    app.add_flag("--quick", quick, "small scenes, few steps (ctest's smoke run)");
    app.add_option("--filter", filter, "run only scenes whose name contains this");
    app.add_option("--seconds", seconds, "stop a run after this much stepping time (default 30)");
    app.add_option("--budgets", budgetList, "budgets in ms, comma-separated; 'unlimited' or 0 for none");
    app.add_option("--threads", threadList, "thread counts, comma-separated (default 1,2)");
    app.add_flag("--trace", trace, "print every step's time and counts");
    app.add_option("--json", jsonFile, "also write the results as JSON");
    CLI11_PARSE(app, argc, argv);

    std::vector<SceneSpec> specs;
    if (quick) {
        specs = {{"pyramid12", scenes::pyramidScene(12, 0.5, false), 60, 0},
                 {"pyramids8x4", scenes::manyPyramidsScene(8, 4, false), 60, 0},
                 {"heap3d_30", scenes::boxPile3Scene(30, true, false), 60, 0}};
        seconds = std::min(seconds, 5.0);
    } else {
        specs = {{"pyramid40", scenes::pyramidScene(40, 0.5, false), 745, 40},
                 {"pyramids40x5", scenes::manyPyramidsScene(40, 5, false), 300, 0},
                 {"circles2000", scenes::scatteredCirclesScene(2000, false), 300, 0},
                 {"circlepile2000", scenes::fallingCirclesScene(2000, false), 300, 0},
                 {"heap3d", scenes::boxPile3Scene(100, true, false), 300, 0},
                 {"columns3d", scenes::boxPile3Scene(100, false, false), 300, 0},
                 {"drop3d", scenes::dropHeap3Scene(100, false), 300, 0}};
    }
    const std::vector<double> budgets = parseList(budgetList);
    std::vector<int> threads;
    for (double t : parseList(threadList)) threads.push_back(std::max(1, int(t)));
    nlohmann::json out = nlohmann::json::array();
    std::printf("work::kNsPerUnit = %.3f ns per work unit (the documented conversion)\n", work::kNsPerUnit);
    for (const SceneSpec& spec : specs) {
        if (!filter.empty() && spec.name.find(filter) == std::string::npos) continue;
        const Times peer = runPeer(spec, seconds);
        const char* peerName = spec.scene["dimension"] == 3 ? "Bullet 3.24 SI" : "Box2D 2.4.1";
        std::printf("\n%s (%d steps): %s p50 %.3f ms, p99 %.3f ms, worst %.3f ms\n", spec.name.c_str(), spec.steps,
                    peerName, peer.quantile(0.5), peer.quantile(0.99), peer.worst());
        std::printf("  %-9s %3s %6s %8s %8s %9s %6s %8s %8s %10s %10s %7s %s\n", "budget", "thr", "steps", "p50 ms",
                    "p99 ms", "worst ms", "exact", "ns/unit", "cpu ns/u", "max work", "min work", "speedup", "verdict");
        nlohmann::json sceneJson = {{"scene", spec.name}, {"peer", peerName}, {"peer_p50_ms", peer.quantile(0.5)},
                                    {"peer_p99_ms", peer.quantile(0.99)}, {"peer_worst_ms", peer.worst()},
                                    {"runs", nlohmann::json::array()}};
        for (double ms : budgets) {
            const std::uint64_t budget = work::fromMilliseconds(ms);
            double oneThreadMs = 0.0;
            std::uint64_t oneThreadHash = 0;
            for (int t : threads) {
                const UnisonRun r = runUnison(spec, budget, t, seconds, trace);
                const double share = r.exact + r.approximate > 0 ? double(r.exact) / double(r.exact + r.approximate) : 1.0;
                const double mean = r.times.total() / double(std::max<std::size_t>(1, r.times.ms.size()));
                if (t == threads.front()) {
                    oneThreadMs = mean;
                    oneThreadHash = r.finalHash;
                }
                const bool sameHash = r.stopped || r.finalHash == oneThreadHash;
                char budgetText[32];
                std::snprintf(budgetText, sizeof budgetText, ms > 0.0 ? "%.2g ms" : "unlimited", ms);
                std::printf("  %-9s %3d %5zu%s %8.3f %8.3f %9.3f %5.0f%% %8.3f %8.3f %10llu %10llu %6.2fx %s%s\n", budgetText,
                            t, r.times.ms.size(), r.stopped ? "*" : " ", r.times.quantile(0.5), r.times.quantile(0.99),
                            r.times.worst(), 100 * share, r.nsPerUnit(), t == 1 ? r.cpuNsPerUnit() : 0.0,
                            (unsigned long long)r.maxWork,
                            (unsigned long long)r.maxMinimum, oneThreadMs / std::max(1e-9, mean), r.verdict.c_str(),
                            sameHash ? "" : "  HASH DIFFERS FROM 1 THREAD");
                sceneJson["runs"].push_back({{"budget_ms", ms}, {"budget_units", budget}, {"threads", t},
                                             {"steps", r.times.ms.size()}, {"stopped", r.stopped},
                                             {"p50_ms", r.times.quantile(0.5)}, {"p99_ms", r.times.quantile(0.99)},
                                             {"worst_ms", r.times.worst()}, {"mean_ms", mean}, {"exact_share", share},
                                             {"ns_per_unit", r.nsPerUnit()}, {"cpu_ns_per_unit", r.cpuNsPerUnit()},
                                             {"max_step_work", r.maxWork},
                                             {"max_minimum_work", r.maxMinimum}, {"overrun", r.overrun},
                                             {"max_penetration", r.maxPenetration},
                                             {"max_approximate_residual", r.maxApproxResidual},
                                             {"verdict", r.verdict}, {"same_hash_as_1_thread", sameHash}});
            }
        }
        out.push_back(sceneJson);
    }
    std::printf("\n(* stopped after --seconds; speedup = mean step time of the first thread count / this one's)\n");
    if (!jsonFile.empty()) std::ofstream(jsonFile) << out.dump(2) << "\n";
    return 0;
}
