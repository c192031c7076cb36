// core/task_system.cpp — the built-in thread pool (see task_system.h).
#include "task_system.h"

#include <chrono>

namespace unison {

namespace {

// A spin-wait hint to the CPU. A yield to the scheduler in the loop instead (a system call each time) made the other
// thread's serial work of a step up to 4x slower on a 2-CPU virtual machine: 2000 resting circles stepped in
// 0.9-1.25 ms on 2 threads against 0.85 on one; with the hint, 0.62-0.67.
inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

/// How long a thread watches for work (or for a task's end) before it sleeps. Not part of any result.
constexpr std::chrono::microseconds kSpinTime{50};

/// Calls done() until it is true or kSpinTime has passed, with a CPU pause in between; true when done() was.
template <class Done>
bool spinUntil(Done done) {
    const auto deadline = std::chrono::steady_clock::now() + kSpinTime;
    for (int i = 1;; ++i) {
        if (done()) return true;
        if (i % 32 == 0 && std::chrono::steady_clock::now() >= deadline) return false;
        cpuRelax();
    }
}

}  // namespace

ThreadPool::ThreadPool(int workerCount) : mWorkerCount(workerCount < 1 ? 1 : workerCount) {
    for (int w = 1; w < mWorkerCount; ++w) mThreads.emplace_back([this, w] { workerLoop(w); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard<std::mutex> lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    for (std::thread& t : mThreads) t.join();
}

bool ThreadPool::runOne(Task& task, int worker) {
    // The worker's own block first, then the others' in turn: consecutive parallel sections of a step give each
    // worker about the same items (bodies, their pairs, their islands), which are then still in its cache.
    for (int k = 0; k < task.blockCount; ++k) {
        Block& block = task.blocks[std::size_t((worker + k) % task.blockCount)];
        if (block.next.load(std::memory_order_relaxed) >= block.end) continue;
        const int r = block.next.fetch_add(1, std::memory_order_relaxed);
        if (r >= block.end) continue;
        const int begin = r * task.rangeSize;
        const int end = begin + task.rangeSize < task.itemCount ? begin + task.rangeSize : task.itemCount;
        task.callback(begin, end, worker, task.context);
        return true;
    }
    return false;
}

bool ThreadPool::hasRanges(const Task& task) {
    for (int k = 0; k < task.blockCount; ++k)
        if (task.blocks[std::size_t(k)].next.load(std::memory_order_relaxed) < task.blocks[std::size_t(k)].end) return true;
    return false;
}

void* ThreadPool::enqueue(TaskCallback* callback, int itemCount, int minRange, void* taskContext, void* poolPtr) {
    ThreadPool& pool = *static_cast<ThreadPool*>(poolPtr);
    auto task = std::make_unique<Task>();
    task->callback = callback;
    task->context = taskContext;
    task->itemCount = itemCount;
    // About 16 ranges per worker, so that uneven items (one big island among small ones) still balance, and the
    // last range of a section, which one thread runs while the other may wait, is short (8 per worker left
    // 2000 one-contact islands on 2 threads about 10 us per step slower).
    const int want = (itemCount + 16 * pool.mWorkerCount - 1) / (16 * pool.mWorkerCount);
    task->rangeSize = want > minRange ? want : minRange;
    task->rangeCount = (itemCount + task->rangeSize - 1) / task->rangeSize;
    task->blockCount = pool.mWorkerCount;
    task->blocks.reset(new Block[std::size_t(task->blockCount)]);
    for (int w = 0; w < task->blockCount; ++w) {
        task->blocks[std::size_t(w)].next.store(int(std::int64_t(task->rangeCount) * w / task->blockCount), std::memory_order_relaxed);
        task->blocks[std::size_t(w)].end = int(std::int64_t(task->rangeCount) * (w + 1) / task->blockCount);
    }
    Task* handle = task.get();
    {
        std::lock_guard<std::mutex> lock(pool.mMutex);
        pool.mTasks.push_back(std::move(task));
        pool.mEnqueued.fetch_add(1, std::memory_order_release);
    }
    pool.mWake.notify_all();
    return handle;
}

void ThreadPool::finish(void* handle, void* poolPtr) {
    ThreadPool& pool = *static_cast<ThreadPool*>(poolPtr);
    Task& task = *static_cast<Task*>(handle);
    while (runOne(task, 0)) task.done.fetch_add(1, std::memory_order_acq_rel);
    // The other threads' last ranges usually end within microseconds; a wake-up from the condition variable costs
    // tens of them, on the path of every parallel section: watch for the end first.
    spinUntil([&] {
        return task.done.load(std::memory_order_acquire) == task.rangeCount && task.users.load(std::memory_order_acquire) == 0;
    });
    {
        std::unique_lock<std::mutex> lock(pool.mMutex);
        // Every range done, and no pool thread still holds the task (it may not have seen yet that none is left).
        pool.mFinished.wait(lock, [&] { return task.done.load(std::memory_order_acquire) == task.rangeCount && task.users == 0; });
        for (auto it = pool.mTasks.begin(); it != pool.mTasks.end(); ++it) {
            if (it->get() == &task) {
                pool.mTasks.erase(it);
                break;
            }
        }
    }
}

void ThreadPool::workerLoop(int worker) {
    std::uint64_t seen = 0;
    for (;;) {
        // A step enqueues its tasks a fraction of a millisecond apart (the serial parts of a step between them), and
        // a sleeping thread can take longer than that to wake: watch for the next task for a while before sleeping.
        spinUntil([&] { return mEnqueued.load(std::memory_order_acquire) != seen; });
        Task* task = nullptr;
        {
            std::unique_lock<std::mutex> lock(mMutex);
            for (;;) {
                if (mStop) return;
                seen = mEnqueued.load(std::memory_order_relaxed);
                for (auto& t : mTasks) {
                    if (hasRanges(*t)) {
                        task = t.get();
                        ++task->users;
                        break;
                    }
                }
                if (task) break;
                mWake.wait(lock);
            }
        }
        // finish() keeps the task alive while users > 0, so it is used here without the lock.
        while (runOne(*task, worker)) task->done.fetch_add(1, std::memory_order_acq_rel);
        {
            std::lock_guard<std::mutex> lock(mMutex);
            --task->users;  // the last use of the task by this thread
        }
        mFinished.notify_all();
    }
}

}  // namespace unison
