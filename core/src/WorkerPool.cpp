// SPDX-License-Identifier: MIT
#include "vsculpt/core/WorkerPool.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <utility>

#if defined(__linux__)
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#endif

namespace vsculpt::core {

namespace {

thread_local bool tInsideBody = false;

}  // namespace

bool lowerThisThreadsPriority(int niceIncrement) {
#if defined(__linux__)
    const id_t tid = id_t(gettid());
    errno = 0;
    const int now = getpriority(PRIO_PROCESS, tid);
    if (errno != 0) return false;
    return setpriority(PRIO_PROCESS, tid, std::min(19, now + niceIncrement)) == 0;
#else
    (void)niceIncrement;
    return false;
#endif
}

WorkerPool::WorkerPool(int helpers, int niceIncrement)
    : mLowered(niceIncrement > 0 && helpers > 0) {
    mThreads.reserve(size_t(std::max(0, helpers)));
    for (int i = 0; i < helpers; ++i)
        mThreads.emplace_back([this, niceIncrement] { helperLoop(niceIncrement); });
    std::unique_lock lock(mMutex);
    mDone.wait(lock, [&] { return mStarted == int(mThreads.size()); });
}

WorkerPool::~WorkerPool() {
    {
        std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    for (std::thread& t : mThreads)
        t.join();
}

void WorkerPool::helperLoop(int niceIncrement) {
    const bool lowered = niceIncrement > 0 && lowerThisThreadsPriority(niceIncrement);
    uint64_t seen = 0;
    std::unique_lock lock(mMutex);
    if (!lowered) mLowered = false;
    ++mStarted;
    mDone.notify_all();
    for (;;) {
        mWake.wait(lock, [&] { return mStop || mLoop != seen; });
        if (mStop) return;
        seen = mLoop;
        if (mNext >= mN) continue;  // finished before this helper woke
        ++mBusy;
        lock.unlock();
        work();
        lock.lock();
        if (--mBusy == 0) mDone.notify_all();
    }
}

void WorkerPool::work() {
    tInsideBody = true;
    for (;;) {
        size_t begin;
        {
            std::lock_guard lock(mMutex);
            if (mNext >= mN) break;
            begin = mNext;
            mNext = std::min(mN, mNext + mGrain);
        }
        const size_t end = std::min(mN, begin + mGrain);
        try {
            (*mBody)(begin, end);
        } catch (...) {
            std::lock_guard lock(mMutex);
            if (!mError) mError = std::current_exception();
        }
    }
    tInsideBody = false;
}

void WorkerPool::parallelFor(size_t n, size_t grain, const Body& body) {
    if (n == 0) return;
    grain = std::max<size_t>(1, grain);
    if (tInsideBody || mThreads.empty() || n <= grain) {
        // Nested, alone or one piece: the caller's own loop is the fastest.
        for (size_t begin = 0; begin < n; begin += grain)
            body(begin, std::min(n, begin + grain));
        return;
    }
    std::lock_guard run(mRun);
    {
        std::lock_guard lock(mMutex);
        mBody = &body;
        mN = n;
        mGrain = grain;
        mNext = 0;
        mError = nullptr;
        ++mLoop;
        ++mBusy;  // the caller
    }
    mWake.notify_all();
    work();
    std::exception_ptr error;
    {
        std::unique_lock lock(mMutex);
        --mBusy;
        // Pieces are all handed out once work() returns; wait for the helpers still in one.
        mDone.wait(lock, [&] { return mBusy == 0; });
        mBody = nullptr;
        error = std::exchange(mError, nullptr);
    }
    if (error) std::rethrow_exception(error);
}

void parallelFor(WorkerPool* pool, size_t n, size_t grain, const WorkerPool::Body& body) {
    if (pool) {
        pool->parallelFor(n, grain, body);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, std::max<size_t>(1, grain)),
                      [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace vsculpt::core
