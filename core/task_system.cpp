// core/task_system.cpp — the built-in thread pool (see task_system.h).
#include "task_system.h"

namespace unison {

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
    const int r = task.next.fetch_add(1, std::memory_order_relaxed);
    if (r >= task.rangeCount) return false;
    const int begin = r * task.rangeSize;
    const int end = begin + task.rangeSize < task.itemCount ? begin + task.rangeSize : task.itemCount;
    task.callback(begin, end, worker, task.context);
    return true;
}

void* ThreadPool::enqueue(TaskCallback* callback, int itemCount, int minRange, void* taskContext, void* poolPtr) {
    ThreadPool& pool = *static_cast<ThreadPool*>(poolPtr);
    auto task = std::make_unique<Task>();
    task->callback = callback;
    task->context = taskContext;
    task->itemCount = itemCount;
    // About 8 ranges per worker, so that uneven items (one big island among small ones) still balance.
    const int want = (itemCount + 8 * pool.mWorkerCount - 1) / (8 * pool.mWorkerCount);
    task->rangeSize = want > minRange ? want : minRange;
    task->rangeCount = (itemCount + task->rangeSize - 1) / task->rangeSize;
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
        // A step enqueues its tasks a fraction of a millisecond apart, and a sleeping thread can take longer than that
        // to wake: watch for the next task for a while (about 50 us) before sleeping.
        for (int spin = 0; spin < 2000 && mEnqueued.load(std::memory_order_acquire) == seen; ++spin)
            std::this_thread::yield();
        Task* task = nullptr;
        {
            std::unique_lock<std::mutex> lock(mMutex);
            for (;;) {
                if (mStop) return;
                seen = mEnqueued.load(std::memory_order_relaxed);
                for (auto& t : mTasks) {
                    if (t->next.load(std::memory_order_relaxed) < t->rangeCount) {
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
