// SPDX-License-Identifier: MIT
/// @file WorkerPool.h
/// @brief Threads of one's own for background work that should yield to the frame: helpers
/// run at a lower priority (a higher nice value, Linux per-thread nice).
///
/// Why not oneTBB's workers: they are shared by every arena in the process, and an
/// unprivileged thread cannot raise its priority again (Linux needs RLIMIT_NICE or
/// CAP_SYS_NICE), so lowering them would slow sketch solids, exports and stills too. A pool
/// owns its threads: only work handed to it runs at the lower priority.
///
/// Why a nice value and not SCHED_IDLE: a helper preempted in the middle of a piece holds up
/// the caller until it runs again (priority inversion). At SCHED_IDLE, with every core busy
/// at normal priority (a software-rendered window, a build beside it), that took seconds:
/// the mesh trailed the tool by 1.4 s (p50) instead of 49 ms. Nice +5 keeps a quarter of a
/// contended core's share, so the wait stays a few pieces long, while a waking frame thread
/// still preempts a helper at once (docs/benchmarks.md, stop 22).
///
/// The calling thread takes part at its own priority, so a parallelFor always progresses at
/// least as fast as a serial loop on the caller; helpers add whatever cores the frame and the
/// rest of the system leave unused. Ranges are handed out in `grain`-sized pieces: a helper
/// holds up the caller by at most the piece it is in.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace vsculpt::core {

/// Lowers the calling thread's priority by `niceIncrement` nice steps (Linux: nice is per
/// thread; capped at nice 19). Threads it creates afterwards start at the lowered priority.
/// Always allowed (only raising priority needs privileges); false where the system refuses or
/// is not Linux.
bool lowerThisThreadsPriority(int niceIncrement);

class WorkerPool {
  public:
    /// Body of a parallel loop: processes indices [begin, end).
    using Body = std::function<void(size_t begin, size_t end)>;

    /// Starts `helpers` threads (0: the caller works alone), each `niceIncrement` nice steps
    /// below the creating thread (0: the same priority; capped at nice 19). Where the system
    /// refuses (or is not Linux) they stay at the creator's priority and lowered() says so.
    WorkerPool(int helpers, int niceIncrement);
    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// Runs body over [0, n) in pieces of at most `grain` indices, on the caller and the
    /// helpers; returns when every piece is done. Rethrows the first exception a piece threw
    /// (the other pieces still run). One loop at a time: a call from inside a body runs
    /// serially on that thread; calls from two outside threads take turns.
    void parallelFor(size_t n, size_t grain, const Body& body);

    int helpers() const { return int(mThreads.size()); }
    /// Whether every helper runs at the lowered priority (false when none was asked for).
    bool lowered() const { return mLowered; }

  private:
    void helperLoop(int niceIncrement);
    void work();  // takes pieces of the current loop until none is left

    std::mutex mRun;  // one loop at a time
    std::mutex mMutex;
    std::condition_variable mWake, mDone;
    std::vector<std::thread> mThreads;
    bool mLowered = true;
    int mStarted = 0;  // helpers that set their priority (the constructor waits for all)
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
