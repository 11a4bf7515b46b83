// SPDX-License-Identifier: MIT
/// @file WorkerPool.h
/// @brief Threads of one's own for background work that must never take a core from the
/// frame: helpers run at the operating system's idle priority (Linux SCHED_IDLE).
///
/// Why not oneTBB's workers: they are shared by every arena in the process, and an
/// unprivileged thread cannot return from idle priority (Linux needs RLIMIT_NICE >= 20 or
/// CAP_SYS_NICE), so lowering them would slow sketch solids, exports and stills too, and a
/// task such a worker steals could hold up its joiner (priority inversion). A pool owns its
/// threads: only work handed to it runs at idle priority.
///
/// The calling thread takes part at its own priority, so a parallelFor always progresses at
/// least as fast as a serial loop on the caller; helpers add whatever cores the frame and the
/// rest of the system leave unused. Ranges are handed out in `grain`-sized pieces: a helper
/// that the scheduler starves holds up the caller by at most one piece.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace vsculpt::core {

class WorkerPool {
  public:
    /// Body of a parallel loop: processes indices [begin, end).
    using Body = std::function<void(size_t begin, size_t end)>;

    /// Starts `helpers` threads (0: the caller works alone). `idlePriority`: helpers ask for
    /// SCHED_IDLE; where the system refuses (or is not Linux) they stay at normal priority and
    /// idlePriority() says so.
    WorkerPool(int helpers, bool idlePriority);
    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// Runs body over [0, n) in pieces of at most `grain` indices, on the caller and the
    /// helpers; returns when every piece is done. Rethrows the first exception a piece threw
    /// (the other pieces still run). One loop at a time: a call from inside a body runs
    /// serially on that thread; calls from two outside threads take turns.
    void parallelFor(size_t n, size_t grain, const Body& body);

    int helpers() const { return int(mThreads.size()); }
    /// Whether every helper runs at idle priority.
    bool idlePriority() const { return mIdle; }

  private:
    void helperLoop(bool idlePriority);
    void work();  // takes pieces of the current loop until none is left

    std::mutex mRun;  // one loop at a time
    std::mutex mMutex;
    std::condition_variable mWake, mDone;
    std::vector<std::thread> mThreads;
    bool mIdle = true;
    int mIdleSet = 0;  // helpers that reported their priority (constructor waits for all)
    bool mStop = false;
    uint64_t mLoop = 0;  // number of the current loop (helpers join each loop once)
    const Body* mBody = nullptr;
    size_t mN = 0, mGrain = 1, mNext = 0;
    int mBusy = 0;  // threads inside work() for the current loop
    std::exception_ptr mError;
};

/// Runs body over [0, n) in pieces of at most `grain` indices: on `pool` when one is given,
/// otherwise on oneTBB's workers (in the caller's arena).
void parallelFor(WorkerPool* pool, size_t n, size_t grain, const WorkerPool::Body& body);

}  // namespace vsculpt::core
