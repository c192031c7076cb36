// tests/test_threads.cpp — worker threads (suite "threads"): the built-in pool and an embedding job system's
// callbacks hand every item out exactly once with a valid worker index, and the worlds step to the same bits for
// 1, 2 and 4 threads on the golden scenes, with and without a budget. scripts/tsan.sh runs this suite under
// ThreadSanitizer.
#include "test_support.h"

#include "golden.h"
#include "make_scenes2d.h"
#include "make_scenes3d.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "step_budget.h"
#include "task_system.h"
#include "world2d.h"
#include "world3d.h"

#include <atomic>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

using namespace unison;

namespace {

/// A stand-in for a server's job system: each enqueued task gets one std::thread per worker, which take ranges of
/// `minRange` items from a shared counter; finish joins them.
struct ToyJobSystem {
    int workers = 3;
    struct Job {
        TaskCallback* task;
        void* context;
        int count, range;
        std::atomic<int> next{0};
        std::vector<std::thread> threads;
    };
    int enqueued = 0;

    static void* enqueue(TaskCallback* task, int itemCount, int minRange, void* taskContext, void* user) {
        ToyJobSystem& self = *static_cast<ToyJobSystem*>(user);
        ++self.enqueued;
        auto* job = new Job{task, taskContext, itemCount, minRange < 1 ? 1 : minRange, {}, {}};
        for (int w = 0; w < self.workers; ++w) {
            job->threads.emplace_back([job, w] {
                for (;;) {
                    const int begin = job->next.fetch_add(job->range);
                    if (begin >= job->count) return;
                    job->task(begin, std::min(job->count, begin + job->range), w, job->context);
                }
            });
        }
        return job;
    }
    static void finish(void* handle, void*) {
        Job* job = static_cast<Job*>(handle);
        for (std::thread& t : job->threads) t.join();
        delete job;
    }
};

/// The state hash after every tick of `scene` (a golden scene's JSON) stepped `steps` times on `tasks`.
std::vector<std::uint64_t> hashes(const nlohmann::json& scene, int steps, const TaskSystem& tasks, std::uint64_t budget) {
    std::vector<std::uint64_t> out;
    auto run = [&](auto& world) {
        REQUIRE(world.setTaskSystem(tasks));
        world.setStepBudget(budget);
        out.push_back(world.stateHash());
        for (int t = 0; t < steps; ++t) {
            world.step();
            out.push_back(world.stateHash());
        }
    };
    if (scene["dimension"] == 3) {
        auto loaded = scenes::loadScene3(scene, "scene");
        run(*loaded.world);
    } else {
        auto loaded = scenes::loadScene2(scene, "scene");
        run(*loaded.world);
    }
    return out;
}

}  // namespace

TEST_SUITE("threads") {

TEST_CASE("the built-in pool hands out every item exactly once, to workers in range") {
    for (int workers : {1, 2, 4}) {
        CAPTURE(workers);
        ThreadPool pool(workers);
        const TaskSystem tasks{workers};
        for (int count : {0, 1, 5, 1000, 4099}) {
            CAPTURE(count);
            std::vector<std::atomic<int>> hits(static_cast<std::size_t>(count));
            std::atomic<int> badWorker{0}, ranges{0};
            parallelFor(tasks, &pool, count, 7, [&](int begin, int end, int worker) {
                ranges.fetch_add(1);
                if (worker < 0 || worker >= workers || begin >= end) badWorker.fetch_add(1);
                for (int i = begin; i < end; ++i) hits[std::size_t(i)].fetch_add(1);
            });
            int wrong = 0;
            for (auto& h : hits) wrong += h.load() == 1 ? 0 : 1;
            CHECK(wrong == 0);
            CHECK(badWorker.load() == 0);
            if (count > 7 && workers > 1) CHECK(ranges.load() > 1);  // split, so other threads could take part
        }
    }
}

TEST_CASE("two tasks enqueued before either is finished both complete") {
    ThreadPool pool(3);
    std::vector<std::atomic<int>> a(500), b(300);
    struct Ctx {
        std::vector<std::atomic<int>>* v;
    };
    Ctx ca{&a}, cb{&b};
    TaskCallback* body = [](int begin, int end, int, void* ctx) {
        for (int i = begin; i < end; ++i) (*static_cast<Ctx*>(ctx)->v)[std::size_t(i)].fetch_add(1);
    };
    void* ha = ThreadPool::enqueue(body, 500, 10, &ca, &pool);
    void* hb = ThreadPool::enqueue(body, 300, 10, &cb, &pool);
    ThreadPool::finish(hb, &pool);
    ThreadPool::finish(ha, &pool);
    int wrong = 0;
    for (auto& h : a) wrong += h.load() == 1 ? 0 : 1;
    for (auto& h : b) wrong += h.load() == 1 ? 0 : 1;
    CHECK(wrong == 0);
}

TEST_CASE("a world rejects a task system it cannot use and keeps its own") {
    World2 w;
    CHECK_FALSE(w.setTaskSystem(TaskSystem{0}));
    CHECK_FALSE(w.setTaskSystem(TaskSystem{2, &ToyJobSystem::enqueue, nullptr, nullptr}));
    CHECK(w.def().workerCount == 1);
    CHECK(w.setTaskSystem(TaskSystem{2}));
    CHECK(w.def().workerCount == 2);
}

TEST_CASE("golden scenes: the same hash every tick for 1, 2 and 4 threads, with and without a budget") {
    for (const replay::GoldenScene& g : replay::goldenScenes()) {
        CAPTURE(g.name);
        // The golden scene's own budget (its hashes are in the golden table), and a tight one of 0.3 ms that
        // leaves some islands approximate (checked in test_budget.cpp).
        for (std::uint64_t budget : {g.budget, work::fromMilliseconds(0.3)}) {
            CAPTURE(budget);
            const int steps = std::min(g.steps, std::getenv("UNISON_THREADS_QUICK") ? 30 : 120);  // (scripts/tsan.sh)
            const std::vector<std::uint64_t> one = hashes(g.scene, steps, TaskSystem{1}, budget);
            if (budget == g.budget && g.threads == 1) {
                const std::vector<std::uint64_t> golden = replay::goldenHashes(g);
                CHECK(one == std::vector<std::uint64_t>(golden.begin(), golden.begin() + steps + 1));
            }
            for (int threads : {2, 4}) {
                CAPTURE(threads);
                CHECK(hashes(g.scene, steps, TaskSystem{threads}, budget) == one);
            }
        }
    }
}

TEST_CASE("an embedding job system through enqueue/finish callbacks gives the same bits") {
    ToyJobSystem jobs;
    const nlohmann::json scene = scenes::manyPyramidsScene(6, 4, false);
    const std::uint64_t budget = work::fromMilliseconds(0.2);
    const std::vector<std::uint64_t> one = hashes(scene, 90, TaskSystem{1}, budget);
    CHECK(hashes(scene, 90, TaskSystem{jobs.workers, &ToyJobSystem::enqueue, &ToyJobSystem::finish, &jobs}, budget) == one);
    CHECK(jobs.enqueued > 90);  // narrowphase, islands and integration went through it every step
    const nlohmann::json heap = scenes::boxPile3Scene(30, true, false);
    CHECK(hashes(heap, 60, TaskSystem{jobs.workers, &ToyJobSystem::enqueue, &ToyJobSystem::finish, &jobs}, 0) ==
          hashes(heap, 60, TaskSystem{1}, 0));
}

TEST_CASE("a threaded world keeps its threads across a restore, and continues bit for bit") {
    auto a = scenes::loadScene2(scenes::pyramidScene(12, 0.5, false), "pyramid12");
    REQUIRE(a.world->setTaskSystem(TaskSystem{2}));
    a.world->setStepBudget(work::fromMilliseconds(0.5));
    for (int t = 0; t < 40; ++t) a.world->step();
    const std::vector<std::uint8_t> snap = a.world->snapshot();
    std::vector<std::uint64_t> expected;
    for (int t = 0; t < 40; ++t) {
        a.world->step();
        expected.push_back(a.world->stateHash());
    }
    auto b = scenes::loadScene2(scenes::pyramidScene(3, 0.5, false), "other");
    REQUIRE(b.world->setTaskSystem(TaskSystem{4}));
    REQUIRE(b.world->restore(snap.data(), snap.size()));
    CHECK(b.world->def().workerCount == 4);  // not state: the live world's setting stays
    CHECK(b.world->def().stepBudget == work::fromMilliseconds(0.5));  // state: the snapshot's
    std::vector<std::uint64_t> got;
    for (int t = 0; t < 40; ++t) {
        b.world->step();
        got.push_back(b.world->stateHash());
    }
    CHECK(got == expected);
}

}  // TEST_SUITE
