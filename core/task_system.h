// core/task_system.h — how a world step runs work on several threads: the callback interface an embedding server
// plugs its own job system into (enqueue a task over a range of items, later wait for it), the small built-in
// std::thread pool used when it does not, and parallelFor(), the one way the step calls either.
//
// Owns: ThreadPool and parallelFor(); the callback types and TaskSystem are public (unison/types.h).
// Invariants: a task's callback gets disjoint item ranges [begin, end) that together cover [0, itemCount) exactly
// once, and a worker index in [0, workerCount); the caller of parallelFor() is worker 0 of the built-in pool. How
// the items are split into ranges and which worker runs which range is free: the step only hands out work whose
// result does not depend on it (each item writes only its own outputs; per-worker data is scratch), which is what
// keeps every answer identical for any thread count.
#pragma once

#include <unison/types.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace unison {

// TaskCallback, EnqueueTaskCallback, FinishTaskCallback and TaskSystem are public (unison/types.h).

/// Sets a world definition's threads (fields workerCount, enqueueTask, finishTask, userTaskContext) from `tasks`.
/// False, and nothing changes, for workerCount < 1 or only one of the two callbacks.
template <class Def>
bool setTaskFields(Def& def, const TaskSystem& tasks) {
    if (tasks.workerCount < 1 || (tasks.enqueueTask == nullptr) != (tasks.finishTask == nullptr)) return false;
    def.workerCount = tasks.workerCount;
    def.enqueueTask = tasks.enqueueTask;
    def.finishTask = tasks.finishTask;
    def.userTaskContext = tasks.userContext;
    return true;
}

/// The threads of a world definition (see setTaskFields).
template <class Def>
TaskSystem taskFieldsOf(const Def& def) {
    return {def.workerCount < 1 ? 1 : def.workerCount, def.enqueueTask, def.finishTask, def.userTaskContext};
}

/// A fixed set of workerCount - 1 std::threads; the thread that finishes a task works on it too, as worker 0.
/// Tasks are taken first-in first-out in ranges; one thread at a time enqueues and finishes (the world's step).
/// A task's ranges are split into one contiguous block per worker; each worker takes its own block's ranges in
/// order, then takes the ranges left in the other blocks.
class ThreadPool {
public:
    /// Starts workerCount - 1 threads (none for workerCount <= 1).
    explicit ThreadPool(int workerCount);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int workerCount() const { return mWorkerCount; }
    /// EnqueueTaskCallback with userContext = this pool.
    static void* enqueue(TaskCallback* task, int itemCount, int minRange, void* taskContext, void* pool);
    /// FinishTaskCallback with userContext = this pool.
    static void finish(void* handle, void* pool);

private:
    /// A worker's own share of a task's ranges: a contiguous block of them, up to `end`, handed out from the front to
    /// its worker first and to the others once their own blocks are empty. Each on its own cache line.
    struct alignas(64) Block {
        std::atomic<int> next{0};  // next range of the block to hand out
        int end = 0;
    };
    struct Task {
        TaskCallback* callback = nullptr;
        void* context = nullptr;
        int itemCount = 0, rangeSize = 1, rangeCount = 0;
        std::unique_ptr<Block[]> blocks;  // one per worker
        int blockCount = 0;
        std::atomic<int> done{0};  // ranges finished
        std::atomic<int> users{0};  // pool threads working on it (changed under the pool's mutex, read by finish())
    };
    /// Runs one range of `task` on `worker`; false when it had none left.
    static bool runOne(Task& task, int worker);
    /// Some range of `task` is not handed out yet.
    static bool hasRanges(const Task& task);
    void workerLoop(int worker);

    int mWorkerCount = 1;
    std::vector<std::thread> mThreads;
    std::mutex mMutex;
    std::condition_variable mWake;      // workers: a task was enqueued, or stop
    std::condition_variable mFinished;  // finish(): a range of some task completed
    std::deque<std::unique_ptr<Task>> mTasks;  // enqueued and not yet finished, oldest first
    std::atomic<std::uint64_t> mEnqueued{0};   // tasks enqueued so far (idle workers watch it before sleeping)
    bool mStop = false;
};

/// Runs body(begin, end, worker) over [0, itemCount) through `tasks` (`pool` when it has no callbacks of its own;
/// either may be absent: then everything runs here as worker 0) and returns when every item is done.
template <class Body>
void parallelFor(const TaskSystem& tasks, ThreadPool* pool, int itemCount, int minRange, Body&& body) {
    if (itemCount <= 0) return;
    using Fn = std::remove_reference_t<Body>;
    auto trampoline = [](int begin, int end, int worker, void* context) {
        (*static_cast<Fn*>(context))(begin, end, worker);
    };
    EnqueueTaskCallback* enqueue = tasks.enqueueTask;
    FinishTaskCallback* finish = tasks.finishTask;
    void* user = tasks.userContext;
    if (!enqueue && pool && pool->workerCount() > 1) {
        enqueue = &ThreadPool::enqueue;
        finish = &ThreadPool::finish;
        user = pool;
    }
    if (tasks.workerCount <= 1 || !enqueue || !finish || itemCount <= minRange) {
        body(0, itemCount, 0);
        return;
    }
    void* handle = enqueue(+trampoline, itemCount, minRange < 1 ? 1 : minRange, const_cast<void*>(static_cast<const void*>(&body)), user);
    if (handle) finish(handle, user);
}

}  // namespace unison
