// SPDX-License-Identifier: MIT
#include "vsculpt/core/WorkerPool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#if defined(__linux__)
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#endif

using vsculpt::core::WorkerPool;

namespace {

/// The calling thread's nice value (Linux: per thread); 0 elsewhere.
int niceOfThisThread() {
#if defined(__linux__)
    errno = 0;
    const int n = getpriority(PRIO_PROCESS, id_t(gettid()));
    EXPECT_EQ(errno, 0);
    return n;
#else
    return 0;
#endif
}

/// Runs a loop whose first piece on the calling thread waits until a helper has run a piece:
/// proves that helpers take part (the loop would hang, and fail after 30 s, otherwise).
/// Returns the nice value each helper piece ran at.
std::vector<int> helperNices(WorkerPool& pool) {
    const auto caller = std::this_thread::get_id();
    std::mutex m;
    std::condition_variable cv;
    bool helped = false, timedOut = false;
    std::vector<int> nices;
    pool.parallelFor(64, 1, [&](size_t, size_t) {
        std::unique_lock lock(m);
        if (std::this_thread::get_id() != caller) {
            nices.push_back(niceOfThisThread());
            helped = true;
            cv.notify_all();
        } else if (!helped) {
            timedOut = !cv.wait_for(lock, std::chrono::seconds(30), [&] { return helped; });
        }
    });
    EXPECT_FALSE(timedOut) << "no helper ran a piece";
    return nices;
}

}  // namespace

TEST(WorkerPool, EveryIndexRunsExactlyOnceInPiecesOfAtMostTheGrain) {
    for (int helpers : {0, 1, 3})
        for (size_t n : {size_t(0), size_t(1), size_t(7), size_t(1000)})
            for (size_t grain : {size_t(1), size_t(3), size_t(64)}) {
                WorkerPool pool(helpers, 5);
                std::vector<std::atomic<int>> runs(n);
                std::atomic<bool> tooBig{false};
                pool.parallelFor(n, grain, [&](size_t b, size_t e) {
                    if (e <= b || e - b > grain) tooBig = true;
                    for (size_t i = b; i < e; ++i)
                        runs[i].fetch_add(1);
                });
                EXPECT_FALSE(tooBig) << helpers << " helpers, n " << n << ", grain " << grain;
                for (size_t i = 0; i < n; ++i)
                    ASSERT_EQ(runs[i].load(), 1) << "index " << i << " of " << n << ", grain "
                                                 << grain << ", " << helpers << " helpers";
            }
}

TEST(WorkerPool, ManyLoopsInARowEachCoverTheirRange) {
    // Helpers that wake late for one loop must not run pieces of it after it returned.
    WorkerPool pool(3, 5);
    for (int loop = 0; loop < 2000; ++loop) {
        const size_t n = size_t(1 + loop % 37);
        std::vector<int> runs(n, 0);
        pool.parallelFor(n, 1, [&](size_t b, size_t e) {
            for (size_t i = b; i < e; ++i)
                ++runs[i];  // one piece per index: no two threads write one element
        });
        for (size_t i = 0; i < n; ++i)
            ASSERT_EQ(runs[i], 1) << "loop " << loop << ", index " << i;
    }
}

TEST(WorkerPool, HelpersRunBelowTheCallersPriorityAndTheCallerKeepsItsOwn) {
    const int before = niceOfThisThread();
    WorkerPool pool(2, 5);
    const std::vector<int> nices = helperNices(pool);
    ASSERT_FALSE(nices.empty());
#if defined(__linux__)
    ASSERT_TRUE(pool.lowered());
    for (int n : nices)
        EXPECT_EQ(n, std::min(19, before + 5));
#endif
    EXPECT_EQ(niceOfThisThread(), before);
}

TEST(WorkerPool, HelpersAtTheCallersPriorityWhenAskedTo) {
    WorkerPool pool(2, 0);
    EXPECT_FALSE(pool.lowered());
    const int mine = niceOfThisThread();
    for (int n : helperNices(pool))
        EXPECT_EQ(n, mine);
}

TEST(WorkerPool, AnExceptionReachesTheCallerAndEveryOtherPieceStillRuns) {
    WorkerPool pool(2, 5);
    std::vector<std::atomic<int>> runs(100);
    EXPECT_THROW(pool.parallelFor(100, 1,
                                  [&](size_t b, size_t) {
                                      runs[b].fetch_add(1);
                                      if (b == 37) throw std::runtime_error("piece 37");
                                  }),
                 std::runtime_error);
    for (size_t i = 0; i < runs.size(); ++i)
        EXPECT_EQ(runs[i].load(), 1) << i;
    // Still usable afterwards, and the error does not come back.
    std::atomic<size_t> sum{0};
    pool.parallelFor(10, 1, [&](size_t b, size_t) { sum += b; });
    EXPECT_EQ(sum.load(), 45u);
}

TEST(WorkerPool, ALoopInsideABodyRunsWholeOnItsThread) {
    WorkerPool pool(2, 5);
    std::vector<std::atomic<int>> inner(8 * 16);
    std::atomic<bool> moved{false};
    pool.parallelFor(8, 1, [&](size_t b, size_t) {
        const auto me = std::this_thread::get_id();
        pool.parallelFor(16, 1, [&](size_t ib, size_t ie) {
            if (std::this_thread::get_id() != me) moved = true;
            for (size_t i = ib; i < ie; ++i)
                inner[b * 16 + i].fetch_add(1);
        });
    });
    EXPECT_FALSE(moved);
    for (size_t i = 0; i < inner.size(); ++i)
        EXPECT_EQ(inner[i].load(), 1) << i;
}

TEST(WorkerPool, TheTbbFallbackCoversTheRangeToo) {
    std::vector<std::atomic<int>> runs(500);
    vsculpt::core::parallelFor(nullptr, runs.size(), 7, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
            runs[i].fetch_add(1);
    });
    for (size_t i = 0; i < runs.size(); ++i)
        ASSERT_EQ(runs[i].load(), 1) << i;
}
