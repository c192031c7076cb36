// tests/test_budget.cpp — the per-step budget (suite "budget"): the deterministic split of a budget among islands,
// the projected Gauss-Seidel approximation against closed forms and the exact LCP answer, the bound on a step's
// work, the 40-row pyramid standing on 2 ms per step, the per-call override, and snapshots, recordings and the
// command line with a budget.
#include "test_support.h"

#include "make_scenes2d.h"
#include "make_scenes3d.h"
#include "pgs.h"
#include "recording.h"
#include "resolver2d.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "step_budget.h"
#include "world2d.h"
#include "world3d.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <sys/wait.h>
#include <vector>

using namespace unison;

namespace {

/// Checks the budget's promise on one step's statistics.
void checkWorkBound(const StepStats& st) {
    CHECK(st.work <= std::max(st.budget, st.minimumWork) + st.overrun);
    CHECK(st.overrun == 0);
}

/// `count` boxes of 1 m and 1 kg stacked on a static ground, resting exactly (2D resolver inputs).
struct Stack2 {
    std::vector<ResolverBody<Dim2>> bodies;
    std::vector<ContactNode<Dim2>> nodes;
};
Stack2 restingStack(int count, double mu) {
    Stack2 s;
    s.bodies.push_back({});  // the ground, static
    for (int i = 0; i < count; ++i) {
        ResolverBody<Dim2> b;
        b.invMass = 1.0;
        b.invInertia = 6.0;  // 1 / (m (1 + 1) / 12)
        b.position = {0.0, 0.5 + i};
        b.velocity = {0.0, -10.0 / 60.0};  // one step of gravity
        s.bodies.push_back(b);
        for (double x : {-0.5, 0.5})
            s.nodes.push_back(makeContact<Dim2>(i + 1, i, {x, double(i)}, {0.0, 1.0}, 0.0, mu));
    }
    return s;
}

std::string runCli(const std::string& args, int* exitCode) {
    const std::string out = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/unison_budget_out.txt";
    const int status = std::system((std::string(UNISON_CLI_PATH) + " " + args + " >" + out + " 2>/dev/null").c_str());
    *exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(out);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_SUITE("budget") {

TEST_CASE("fair shares: nobody gets more than it asks, the small are served first, the rest split evenly") {
    CHECK(fairShares({}, 100).empty());
    CHECK(fairShares({10, 20, 30}, 100) == std::vector<std::uint64_t>{10, 20, 30});
    CHECK(fairShares({10, 200, 300}, 100) == std::vector<std::uint64_t>{10, 45, 45});
    CHECK(fairShares({300, 10, 200}, 100) == std::vector<std::uint64_t>{45, 10, 45});
    CHECK(fairShares({50, 50, 50}, 90) == std::vector<std::uint64_t>{30, 30, 30});
    CHECK(fairShares({5, 0, 7}, 0) == std::vector<std::uint64_t>{0, 0, 0});
    // Properties on a larger input: within the pool, within each demand, and max-min fair (anyone cut short gets
    // at least as much as anyone else).
    std::vector<std::uint64_t> demand;
    for (std::uint64_t i = 0; i < 200; ++i) demand.push_back((i * 7919u) % 1000u);
    const std::vector<std::uint64_t> s = fairShares(demand, 40000);
    CHECK(std::accumulate(s.begin(), s.end(), std::uint64_t(0)) <= 40000);
    std::uint64_t cutLevel = ~std::uint64_t(0), maxShare = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        CHECK(s[i] <= demand[i]);
        if (s[i] < demand[i]) cutLevel = std::min(cutLevel, s[i]);
        maxShare = std::max(maxShare, s[i]);
    }
    CHECK(cutLevel + 1 >= maxShare);  // (integer division: levels differ by at most one unit)
}

TEST_CASE("milliseconds convert through the one documented constant") {
    CHECK(work::fromMilliseconds(0.0) == 0);
    CHECK(work::fromMilliseconds(-1.0) == 0);
    CHECK(work::fromMilliseconds(2.0) == std::uint64_t(2e6 / work::kNsPerUnit));
    CHECK(work::toMilliseconds(work::fromMilliseconds(4.0)) == doctest::Approx(4.0).epsilon(1e-6));
}

TEST_CASE("PGS: a resting stack converges to its weights, cold, within the Coulomb bound") {
    Stack2 s = restingStack(3, 0.5);
    const PgsResult<Dim2> r = solvePgs(s.bodies, s.nodes, {}, 2000, 1.0);
    // Each pair of corners carries the weight above it over one step: (boxes above + 1) m g dt.
    for (int i = 0; i < 3; ++i) {
        CHECK(r.normal[std::size_t(2 * i)] + r.normal[std::size_t(2 * i + 1)] == doctest::Approx((3 - i) * 10.0 / 60.0).epsilon(1e-6));
    }
    for (std::size_t c = 0; c < s.nodes.size(); ++c) CHECK(std::fabs(r.tangent[c].x) <= 0.5 * r.normal[c] + 1e-15);
    for (int i = 1; i <= 3; ++i) CHECK(std::fabs(s.bodies[std::size_t(i)].velocity.y) < 1e-6);
    CHECK(r.residual < 1e-6);
}

TEST_CASE("PGS: warm-started from the exact LCP answer it stays there") {
    Stack2 exact = restingStack(4, 0.6);
    LemkeSolver solver;
    ResolverOptions opt;
    opt.restitutionThreshold = 1.0;
    opt.frictionDirections = 2;
    const Resolution res = resolveWithFriction(exact.bodies, exact.nodes, opt, solver);
    REQUIRE(res.status == LcpStatus::solved);
    Stack2 s = restingStack(4, 0.6);
    std::vector<PgsWarm<Dim2>> warm(s.nodes.size());
    for (std::size_t c = 0; c < warm.size(); ++c) {
        warm[c].normal = res.impulses[c];
        warm[c].tangent = {res.tangentImpulses[2 * c], res.tangentImpulses[2 * c + 1]};
    }
    const PgsResult<Dim2> r = solvePgs(s.bodies, s.nodes, warm, 3, 1.0);
    for (std::size_t c = 0; c < warm.size(); ++c) CHECK(r.normal[c] == doctest::Approx(res.impulses[c]).epsilon(1e-9));
    for (std::size_t b = 1; b < s.bodies.size(); ++b)
        CHECK(s.bodies[b].velocity.y == doctest::Approx(exact.bodies[b].velocity.y).epsilon(1e-9));
    CHECK(r.residual < 1e-9);
}

TEST_CASE("PGS in 3D: a sliding cube's friction stays on the round cone mu f_n") {
    std::vector<ResolverBody<Dim3>> bodies(2);
    bodies[1].invMass = 1.0;
    bodies[1].invInertia = Mat3::Identity() * 6.0;
    bodies[1].position = Vec3(0, 0.5, 0);
    bodies[1].velocity = Vec3(3.0, -10.0 / 60.0, 1.0);
    std::vector<ContactNode<Dim3>> nodes;
    for (double x : {-0.5, 0.5})
        for (double z : {-0.5, 0.5}) nodes.push_back(makeContact<Dim3>(1, 0, Vec3(x, 0, z), Vec3(0, 1, 0), 0.0, 0.3));
    const PgsResult<Dim3> r = solvePgs(bodies, nodes, {}, 50, 1.0);
    double fn = 0.0;
    for (std::size_t c = 0; c < nodes.size(); ++c) {
        const double ft = std::sqrt(Dim3::dot(r.tangent[c], r.tangent[c]));
        CHECK(ft <= 0.3 * r.normal[c] * (1.0 + 1e-12) + 1e-15);
        fn += r.normal[c];
    }
    CHECK(fn == doctest::Approx(10.0 / 60.0).epsilon(1e-6));
    // Sliding: the friction impulse opposes the slip and has its full size mu f_n (speed 3.16 m/s is not stopped
    // by 0.3 * 10/60 N s).
    const Vec3 v = bodies[1].velocity;
    CHECK(v.x() == doctest::Approx(3.0 - 0.3 * 10.0 / 60.0 * 3.0 / std::sqrt(10.0)).epsilon(1e-6));
}

TEST_CASE("a step's work stays within max(budget, minimum); the approximation takes what the budget cannot solve") {
    SUBCASE("2D: a 16-row pyramid landing") {
        auto loaded = scenes::loadScene2(scenes::pyramidScene(16, 0.5, false), "pyramid16");
        loaded.world->setStepBudget(work::fromMilliseconds(0.4));
        int approx = 0, exact = 0;
        for (int t = 0; t < 90; ++t) {
            loaded.world->step();
            const StepStats& st = loaded.world->stats();
            checkWorkBound(st);
            approx += st.approximateIslands;
            exact += st.exactIslands;
            CHECK(st.unsolvedIslands == 0);
        }
        CHECK(approx > 0);
        CHECK(exact > 0);
    }
    SUBCASE("3D: a toppling box heap") {
        auto loaded = scenes::loadScene3(scenes::boxPile3Scene(40, true, false), "heap");
        loaded.world->setStepBudget(work::fromMilliseconds(0.3));
        int approx = 0;
        for (int t = 0; t < 120; ++t) {
            loaded.world->step();
            checkWorkBound(loaded.world->stats());
            approx += loaded.world->stats().approximateIslands;
        }
        CHECK(approx > 0);
    }
    SUBCASE("unlimited: never approximate") {
        auto loaded = scenes::loadScene2(scenes::manyPyramidsScene(4, 4, false), "pyramids");
        for (int t = 0; t < 60; ++t) {
            loaded.world->step();
            CHECK(loaded.world->stats().approximateIslands == 0);
            CHECK(loaded.world->stats().budget == 0);
            CHECK(loaded.world->stats().work > 0);
        }
    }
}

TEST_CASE("the 40-row pyramid stands 10 s on a budget of 2 ms per step") {
    // bench_world2d's criterion: the top box falls 40 x 0.25 m and lands after sqrt(40 / 20) s; one second later
    // (step 145) it must sit within 0.5 m of its standing height (39.5 m), and for the 10 s after that move less than
    // 5 cm sideways and sink less than 5 cm.
    auto loaded = scenes::loadScene2(scenes::pyramidScene(40, 0.5, false), "pyramid40");
    World2& w = *loaded.world;
    w.setStepBudget(work::fromMilliseconds(2.0));
    const BodyId top = loaded.bodies.back();
    const int settle = 145;
    Vec2 ref;
    double sideways = 0.0, drop = 0.0;
    for (int t = 1; t <= settle + 600; ++t) {
        w.step();
        checkWorkBound(w.stats());
        const Vec2 p = w.state(top)->position;
        if (t == settle) ref = p;
        if (t > settle) {
            sideways = std::max(sideways, std::fabs(p.x - ref.x));
            drop = std::max(drop, ref.y - p.y);
        }
    }
    CHECK(std::fabs(ref.y - 39.5) <= 0.5);
    CHECK(sideways < 0.05);
    CHECK(drop < 0.05);
}

TEST_CASE("step(budget) overrides the world's budget for one call") {
    auto a = scenes::loadScene2(scenes::pyramidScene(8, 0.5, false), "a");
    auto b = scenes::loadScene2(scenes::pyramidScene(8, 0.5, false), "b");
    a.world->setStepBudget(work::fromMilliseconds(0.05));
    for (int t = 0; t < 60; ++t) {
        a.world->step(0);  // unlimited this call
        b.world->step();
    }
    CHECK(a.world->stats().budget == 0);
    a.world->setStepBudget(0);  // the setting is state; the bodies and caches must already agree
    CHECK(a.world->stateHash() == b.world->stateHash());
}

TEST_CASE("a budgeted call after unbudgeted resting steps gives every island its need") {
    // Resting unbudgeted steps keep last step's islands and jobs; a job kept from them carries no predicted need,
    // so a budgeted call must plan its jobs afresh: with a budget far above what the scene needs, every island with
    // contacts is solved exactly, on any thread count.
    for (int threads : {1, 2}) {
        CAPTURE(threads);
        auto loaded = scenes::loadScene2(scenes::manyPyramidsScene(4, 4, false), "pyramids");
        World2& w = *loaded.world;
        REQUIRE(w.setTaskSystem(TaskSystem{threads}));
        for (int t = 0; t < 120; ++t) w.step();
        const int solved = w.stats().exactIslands;  // the pyramids' islands
        REQUIRE(solved > 1);
        for (int round = 0; round < 3; ++round) {
            w.step(work::fromMilliseconds(1000.0));
            CHECK(w.stats().approximateIslands == 0);
            CHECK(w.stats().exactIslands == solved);
            w.step();
            CHECK(w.stats().exactIslands == solved);
        }
    }
}

TEST_CASE("a budgeted scene records and verifies, and its recording matches a threaded run") {
    nlohmann::json scene = scenes::pyramidScene(10, 0.5, false);
    scene["step_budget"] = work::fromMilliseconds(0.1);
    const replay::Recording rec = replay::record(scene, replay::InputScript{}, 90, 30);
    CHECK(replay::verify(rec).match);
    auto loaded = scenes::loadScene2(scene, "threaded");
    CHECK(loaded.world->def().stepBudget == work::fromMilliseconds(0.1));
    REQUIRE(loaded.world->setTaskSystem(TaskSystem{2}));
    std::vector<std::uint64_t> hashes{loaded.world->stateHash()};
    for (int t = 0; t < 90; ++t) {
        loaded.world->step();
        hashes.push_back(loaded.world->stateHash());
    }
    CHECK(hashes == rec.hashes);
}

TEST_CASE("3D snapshot and restore mid-run with a budget continue bit for bit") {
    auto a = scenes::loadScene3(scenes::boxPile3Scene(30, true, false), "heap");
    a.world->setStepBudget(work::fromMilliseconds(0.2));
    REQUIRE(a.world->setTaskSystem(TaskSystem{2}));
    for (int t = 0; t < 50; ++t) a.world->step();
    const std::vector<std::uint8_t> snap = a.world->snapshot();
    World3 b;
    REQUIRE(b.restore(snap.data(), snap.size()));
    CHECK(b.stateHash() == a.world->stateHash());
    for (int t = 0; t < 40; ++t) {
        a.world->step();
        b.step();
    }
    CHECK(b.stateHash() == a.world->stateHash());
}

TEST_CASE("unison run: --threads leaves the hash lines as they are; --budget and --budget-ms") {
    const std::string scene = std::string(UNISON_SOURCE_DIR) + "/scenes/pyramid20.json";
    int c1 = 0, c2 = 0, c3 = 0;
    const std::string one = runCli("run " + scene + " --steps 40 --hash-every 10 --budget-ms 0.3", &c1);
    const std::string two = runCli("run " + scene + " --steps 40 --hash-every 10 --budget-ms 0.3 --threads 2", &c2);
    REQUIRE(c1 == 0);
    REQUIRE(c2 == 0);
    auto hashLines = [](const std::string& out) { return out.substr(0, out.rfind("{\"bodies\"")); };
    CHECK(hashLines(one) == hashLines(two));
    CHECK(hashLines(one).size() > 100);
    const nlohmann::json last = nlohmann::json::parse(one.substr(one.rfind("{\"bodies\"")));
    for (const char* key : {"worst_step_ms", "mean_step_ms", "max_step_work", "approximate_islands"})
        CHECK(last["stats"].contains(key));
    CHECK(last["stats"]["approximate_islands"].get<int>() > 0);
    const std::string units = runCli("run " + scene + " --steps 40 --hash-every 10 --budget " +
                                         std::to_string(work::fromMilliseconds(0.3)), &c3);
    CHECK(hashLines(units) == hashLines(one));
    runCli("run " + scene + " --steps 5 --budget 100 --budget-ms 1", &c3);
    CHECK(c3 == 2);
    runCli("run " + scene + " --steps 5 --threads 0", &c3);
    CHECK(c3 == 2);
}

}  // TEST_SUITE
