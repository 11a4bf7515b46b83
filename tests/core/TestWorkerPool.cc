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
#include <pthread.h>
#include <sched.h>
#endif

using vsculpt::core::WorkerPool;

namespace {

int policyOfThisThread() {
#if defined(__linux__)
    int policy = -1;
    sched_param p{};
    pthread_getschedparam(pthread_self(), &policy, &p);
    return policy;
#else
    return -1;
#endif
}

/// Runs a loop whose first piece on the calling thread waits until a helper has run a piece:
/// proves that helpers take part (the loop would hang, and fail after 30 s, otherwise).
/// Returns the scheduling policy each helper piece ran under.
std::vector<int> helperPolicies(WorkerPool& pool) {
    const auto caller = std::this_thread::get_id();
    std::mutex m;
    std::condition_variable cv;
    bool helped = false, timedOut = false;
    std::vector<int> policies;
    pool.parallelFor(64, 1, [&](size_t, size_t) {
        std::unique_lock lock(m);
        if (std::this_thread::get_id() != caller) {
            policies.push_back(policyOfThisThread());
            helped = true;
            cv.notify_all();
        } else if (!helped) {
            timedOut = !cv.wait_for(lock, std::chrono::seconds(30), [&] { return helped; });
        }
    });
    EXPECT_FALSE(timedOut) << "no helper ran a piece";
    return policies;
}

}  // namespace

TEST(WorkerPool, EveryIndexRunsExactlyOnceInPiecesOfAtMostTheGrain) {
    for (int helpers : {0, 1, 3})
        for (size_t n : {size_t(0), size_t(1), size_t(7), size_t(1000)})
            for (size_t grain : {size_t(1), size_t(3), size_t(64)}) {
                WorkerPool pool(helpers, true);
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
    WorkerPool pool(3, true);
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

TEST(WorkerPool, HelpersRunAtIdlePriorityAndTheCallerKeepsItsOwn) {
    const int before = policyOfThisThread();
    WorkerPool pool(2, true);
    const std::vector<int> policies = helperPolicies(pool);
    ASSERT_FALSE(policies.empty());
#if defined(__linux__) && defined(SCHED_IDLE)
    ASSERT_TRUE(pool.idlePriority());
    for (int p : policies)
        EXPECT_EQ(p, SCHED_IDLE);
#endif
    EXPECT_EQ(policyOfThisThread(), before);
}

TEST(WorkerPool, HelpersAtNormalPriorityWhenAskedTo) {
    WorkerPool pool(2, false);
    EXPECT_FALSE(pool.idlePriority());
    const int mine = policyOfThisThread();
    for (int p : helperPolicies(pool))
        EXPECT_EQ(p, mine);
}

TEST(WorkerPool, AnExceptionReachesTheCallerAndEveryOtherPieceStillRuns) {
    WorkerPool pool(2, true);
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
    WorkerPool pool(2, true);
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
