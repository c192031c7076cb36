// tests/soak.cpp — the soak run: a 2D and a 3D world stepped side by side for 100,000 steps (default) with inputs that
// keep them moving (a kick every 300 steps, a body destroyed and a new one dropped every 1,500), checked as it goes:
// no fault (every number finite and in range), no body lost (the body count is what the inputs make it, and no
// dynamic body falls through the ground), bounded memory (resident size after the warm-up may not grow by more than
// 64 MB), and the same chain hash twice: the second run is restored from the first run's snapshot at half time.
// Both worlds step with a per-step budget (part of their state, so the snapshot carries it) small enough that
// islands get the bounded approximation; the first run steps on --threads worker threads, the second on one, so the
// equal chain hashes also show that the thread count changes nothing.
//
// Usage: unison_soak [--steps N] [--quick] [--budget-ms X] [--threads T]
//   --quick: 1,000 steps (the ctest entry soak_quick); --budget-ms: default 0.05 (0 = unlimited); --threads: 2
// Prints one JSON line; exits 0 when every check held, 1 otherwise (with the reason on stderr).
#include "scene_dir.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "state_io.h"
#include "step_budget.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

using namespace unison;

namespace {

/// Resident set size of this process (kB), from /proc/self/status (0 where there is none).
long residentKb() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return 0;
}

/// A deterministic pseudo-random sequence (64-bit LCG), so both runs see the same inputs.
struct Lcg {
    std::uint64_t s = 12345;
    double next() {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return double(s >> 11) * (1.0 / 9007199254740992.0);
    }
};

struct Failure {
    std::string why;
};

/// Both worlds and what the soak knows about them.
struct Pair {
    std::unique_ptr<World2> w2;
    std::unique_ptr<World3> w3;
    int bodies2 = 0, bodies3 = 0;  // expected body counts
};

struct Settings {
    std::uint64_t budget = 0;  // work units per step
    int threads = 1;           // of the first run
};

Pair load(const Settings& settings, int threads) {
    const std::string dir = scenes::sceneDir();
    Pair p;
    p.w2 = scenes::loadScene2(scenes::readSceneFile(dir + "/mixed_pile.json"), "mixed_pile").world;
    p.w3 = scenes::loadScene3(scenes::readSceneFile(dir + "/mixed3d.json"), "mixed3d", dir).world;
    p.w2->setStepBudget(settings.budget);
    p.w3->setStepBudget(settings.budget);
    if (!p.w2->setTaskSystem(TaskSystem{threads}) || !p.w3->setTaskSystem(TaskSystem{threads}))
        throw Failure{"--threads must be >= 1"};
    p.bodies2 = p.w2->bodyCount();
    p.bodies3 = p.w3->bodyCount();
    return p;
}

/// The dynamic body ids of a world, in dense order.
template <class World>
std::vector<BodyId> dynamicBodies(const World& w) {
    std::vector<BodyId> out;
    for (BodyId id : w.bodyIds())
        if (w.info(id)->type == decltype(w.info(id)->type)::dynamicBody) out.push_back(id);
    return out;
}

/// The inputs of step `s` (before it), the same in every run.
void inputs(Pair& p, int s, Lcg& rng) {
    if (s % 300 == 0) {
        const std::vector<BodyId> d2 = dynamicBodies(*p.w2), d3 = dynamicBodies(*p.w3);
        const BodyId a = d2[std::size_t(rng.next() * double(d2.size()))];
        p.w2->applyImpulse(a, {rng.next() * 2.0 - 1.0, 1.0 + rng.next() * 2.0}, p.w2->state(a)->center);
        const BodyId b = d3[std::size_t(rng.next() * double(d3.size()))];
        p.w3->applyImpulse(b, Vec3(rng.next() - 0.5, 1.0 + rng.next(), rng.next() - 0.5), p.w3->state(b)->center);
    }
    if (s % 1500 == 0) {
        const std::vector<BodyId> d2 = dynamicBodies(*p.w2), d3 = dynamicBodies(*p.w3);
        p.w2->destroyBody(d2[std::size_t(rng.next() * double(d2.size()))]);
        p.w3->destroyBody(d3[std::size_t(rng.next() * double(d3.size()))]);
        std::vector<Shape2> circle(1);
        makeCircle({0.0, 0.0}, 0.3, &circle[0].circle);
        BodyDef2 def2;
        def2.position = {rng.next() * 4.0 - 2.0, 12.0};
        if (p.w2->createBody(def2, circle).isNull()) throw Failure{"2D createBody failed"};
        std::vector<Shape3> sphere(1);
        makeSphere(Vec3::Zero(), 0.2, &sphere[0]);
        BodyDef3 def3;
        def3.position = Vec3(rng.next() - 0.5, 4.0, rng.next() - 0.5);
        if (p.w3->createBody(def3, sphere).isNull()) throw Failure{"3D createBody failed"};
    }
}

double height(const BodyState2& s) { return s.center.y; }
double height(const BodyState3& s) { return s.center.y(); }

/// Every check of one step.
template <class World>
void check(const World& w, int expected, int s, double floorY, const char* name) {
    if (!w.fault().empty()) throw Failure{std::string(name) + ": " + w.fault()};
    if (w.bodyCount() != expected) throw Failure{std::string(name) + ": body count changed at step " + std::to_string(s)};
    for (BodyId id : dynamicBodies(w)) {
        if (!(height(*w.state(id)) > floorY)) throw Failure{std::string(name) + ": a body fell through the ground at step " + std::to_string(s)};
    }
}

struct RunResult {
    std::uint64_t chain2 = 0, chain3 = 0;
    long approximateIslands = 0;  // summed over the steps of both worlds
    long rssGrowthKb = 0;
    double seconds = 0.0;
};

/// One run of `steps`. At step `restoreAt` the first run (restore false) stores its snapshots in *snap2 and *snap3;
/// the second (restore true) replaces its worlds by fresh ones restored from them.
RunResult run(const Settings& settings, int steps, int restoreAt, bool restore, std::vector<std::uint8_t>* snap2,
               std::vector<std::uint8_t>* snap3) {
    const auto t0 = std::chrono::steady_clock::now();
    const int threads = restore ? 1 : settings.threads;
    Pair p = load(settings, threads);
    RunResult r;
    Lcg rng;
    ByteWriter chain2, chain3;
    long rssAfterWarmup = 0, rssMax = 0;
    for (int s = 1; s <= steps; ++s) {
        if (s == restoreAt) {
            if (restore) {
                auto w2 = std::make_unique<World2>();
                auto w3 = std::make_unique<World3>();
                w2->setTaskSystem(TaskSystem{threads});
                w3->setTaskSystem(TaskSystem{threads});
                std::string error;
                if (!w2->restore(snap2->data(), snap2->size(), &error) || !w3->restore(snap3->data(), snap3->size(), &error))
                    throw Failure{"restore at half time refused: " + error};
                p.w2 = std::move(w2);
                p.w3 = std::move(w3);
            } else {
                *snap2 = p.w2->snapshot();
                *snap3 = p.w3->snapshot();
            }
        }
        inputs(p, s, rng);
        p.w2->step();
        p.w3->step();
        check(*p.w2, p.bodies2, s, -1.0, "2D");
        check(*p.w3, p.bodies3, s, -1.0, "3D");
        r.approximateIslands += p.w2->stats().approximateIslands + p.w3->stats().approximateIslands;
        if (s % 100 == 0) {
            chain2.u64(p.w2->stateHash());
            chain3.u64(p.w3->stateHash());
        }
        if (s == std::min(steps, 2000)) rssAfterWarmup = residentKb();
        if (s % 1000 == 0) rssMax = std::max(rssMax, residentKb());
    }
    r.chain2 = hash64(chain2.data().data(), chain2.data().size());
    r.chain3 = hash64(chain3.data().data(), chain3.data().size());
    r.rssGrowthKb = std::max(0L, rssMax - rssAfterWarmup);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    int steps = 100000;
    double budgetMs = 0.05;
    Settings settings;
    settings.threads = 2;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) steps = 1000;
        if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc) steps = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--budget-ms") == 0 && i + 1 < argc) budgetMs = std::atof(argv[++i]);
        if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) settings.threads = std::atoi(argv[++i]);
    }
    settings.budget = work::fromMilliseconds(budgetMs);
    if (steps < 2) steps = 2;
    try {
        std::vector<std::uint8_t> snap2, snap3;
        const RunResult first = run(settings, steps, steps / 2, false, &snap2, &snap3);
        const RunResult second = run(settings, steps, steps / 2, true, &snap2, &snap3);
        const bool same = first.chain2 == second.chain2 && first.chain3 == second.chain3;
        const long growth = std::max(first.rssGrowthKb, second.rssGrowthKb);
        std::printf("{\"steps\": %d, \"chain2d\": \"%016llx\", \"chain3d\": \"%016llx\", \"same_hash_twice\": %s, "
                    "\"rss_growth_kb\": %ld, \"seconds\": [%.1f, %.1f], \"budget_units\": %llu, \"threads\": [%d, 1], "
                    "\"approximate_islands\": %ld}\n",
                    steps, (unsigned long long)first.chain2, (unsigned long long)first.chain3, same ? "true" : "false", growth,
                    first.seconds, second.seconds, (unsigned long long)settings.budget, settings.threads,
                    first.approximateIslands);
        if (!same) throw Failure{"the two runs disagree"};
        if (settings.budget > 0 && first.approximateIslands == 0)
            throw Failure{"the budget never left an island to the approximation: take a smaller --budget-ms"};
        if (growth > 64 * 1024) throw Failure{"resident memory grew by " + std::to_string(growth / 1024) + " MB"};
    } catch (const Failure& f) {
        std::fprintf(stderr, "soak failed: %s\n", f.why.c_str());
        return 1;
    } catch (const jsonio::JsonError& e) {
        std::fprintf(stderr, "soak failed: %s\n", e.what());
        return 1;
    }
    return 0;
}
