// SPDX-License-Identifier: MIT
#include "vsculpt/core/AsyncMesher.h"

#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

namespace vsculpt::core {

namespace {

int64_t floorDiv2(int64_t v) {
    return v >= 0 ? v / 2 : -((-v + 1) / 2);
}

/// The same box at twice the spacing: an eighth of the blocks, for a quick first look.
GridRegion previewRegion(const GridRegion& r) {
    GridRegion p;
    p.spacingMm = 2 * r.spacingMm;
    for (int a = 0; a < 3; ++a)
        p.originCell[a] = floorDiv2(r.originCell[a]);
    const int cells = r.n / 2 + 1;  // +1: the rounded-down origin shifts the box by a cell
    p.n = (cells + Polygonizer::kChunkCells - 1) / Polygonizer::kChunkCells *
          Polygonizer::kChunkCells;
    return p;
}

}  // namespace

AsyncMesher::AsyncMesher(const Sculpture& sculpture, const GridRegion& region, double relTolerance,
                         Options options)
    : mRelTolerance(relTolerance),
      mOptions(options),
      mReplica(sculpture.clone()),
      mTargetRegion(region) {
    mPoly = std::make_unique<Polygonizer>(*mReplica, region, relTolerance);
    mPoly->rebuildAll(mOptions.threaded);
    auto first = std::const_pointer_cast<MeshChunks>(publishChunks(*mPoly, nullptr));
    first->complete = true;
    mPublished = std::move(first);
    if (mOptions.threaded) {
        // The mesher's own thread (normal priority) and helpers for the other cores at a lower
        // priority: a waking frame thread takes a core from them at once, and a rebuild still
        // uses every core the frame leaves.
        const int threads =
            mOptions.threads > 0 ? mOptions.threads : tbb::info::default_concurrency();
        mWorkers = std::make_unique<WorkerPool>(threads - 1, mOptions.helperNice);
        mPoly->useWorkers(mWorkers.get());
    }
    mThread = std::thread([this] { run(); });
}

AsyncMesher::~AsyncMesher() {
    {
        std::lock_guard lock(mMutex);
        mStop = true;
        mCancel.store(true);
    }
    mWake.notify_all();
    mThread.join();
}

uint64_t AsyncMesher::enqueue(Job job) {
    uint64_t edit = 0;
    {
        std::lock_guard lock(mMutex);
        if (mError) std::rethrow_exception(mError);
        edit = job.edit = ++mPostedEdits;
        job.posted = Clock::now();
        if (job.region) {
            mTargetRegion = *job.region;
            mCancel.store(true);  // the running rebuild is for a region no longer wanted
        } else {
            mInFlight.emplace_back(edit, job.posted);
        }
        mQueue.push_back(std::move(job));
    }
    mWake.notify_one();
    return edit;
}

uint64_t AsyncMesher::post(std::vector<SkeletonWrite> writes, std::vector<Vec3> points,
                           double radius) {
    Job j;
    j.writes = std::move(writes);
    j.points = std::move(points);
    j.radius = radius;
    return enqueue(std::move(j));
}

uint64_t AsyncMesher::post(std::vector<SkeletonWrite> writes, const Aabb& changed) {
    Job j;
    j.writes = std::move(writes);
    j.box = changed;
    return enqueue(std::move(j));
}

uint64_t AsyncMesher::setRegion(const GridRegion& region) {
    Job j;
    j.region = region;
    return enqueue(std::move(j));
}

GridRegion AsyncMesher::targetRegion() const {
    std::lock_guard lock(mMutex);
    return mTargetRegion;
}

std::shared_ptr<const MeshChunks> AsyncMesher::published() const {
    std::lock_guard lock(mMutex);
    return mPublished;
}

uint64_t AsyncMesher::lastPosted() const {
    std::lock_guard lock(mMutex);
    return mPostedEdits;
}

size_t AsyncMesher::passes() const {
    std::lock_guard lock(mMutex);
    return mPasses;
}

size_t AsyncMesher::cancelledPasses() const {
    std::lock_guard lock(mMutex);
    return mCancelled;
}

bool AsyncMesher::idleLocked() const {
    return mPublished->complete && mPublished->edits == mPostedEdits && mCallbacksRunning == 0;
}

void AsyncMesher::waitIdle() {
    std::unique_lock lock(mMutex);
    mIdle.wait(lock, [&] { return mError || idleLocked(); });
    if (mError) std::rethrow_exception(mError);
}

std::string AsyncMesher::verifyAgainstFullRebuild() {
    // Holding the lock keeps the mesher thread from taking new jobs (it drains the queue
    // under this lock), and after waitIdle it has nothing in hand: the replica and the
    // polygonizer are at rest.
    std::unique_lock lock(mMutex);
    mIdle.wait(lock, [&] { return mError || idleLocked(); });
    if (mError) std::rethrow_exception(mError);
    return mPoly->verifyAgainstFullRebuild();
}

std::vector<double> AsyncMesher::takePublishDelaysMs() {
    std::lock_guard lock(mMutex);
    return std::exchange(mDelaysMs, {});
}

void AsyncMesher::hold(bool held) {
    {
        std::lock_guard lock(mMutex);
        mHeld = held;
    }
    mWake.notify_one();
}

void AsyncMesher::publish(std::shared_ptr<const MeshChunks> set) {
    const std::shared_ptr<const MeshChunks> keep = set;
    {
        std::lock_guard lock(mMutex);
        mPublished = std::move(set);
        if (mOptions.onPublish) ++mCallbacksRunning;
        if (mPublished->complete) {
            const auto now = Clock::now();
            auto it = mInFlight.begin();
            for (; it != mInFlight.end() && it->first <= mPublished->edits; ++it) {
                // A host that never takes them (a session of hours) must not grow: the older
                // half goes when the list is full.
                if (mDelaysMs.size() >= std::max<size_t>(1, mOptions.maxKeptDelays))
                    mDelaysMs.erase(mDelaysMs.begin(),
                                    mDelaysMs.begin() + std::ptrdiff_t(mDelaysMs.size() / 2 + 1));
                mDelaysMs.push_back(
                    std::chrono::duration<double, std::milli>(now - it->second).count());
            }
            mInFlight.erase(mInFlight.begin(), it);
        }
    }
    mIdle.notify_all();
    if (!mOptions.onPublish) return;
    mOptions.onPublish(*keep);
    // waitIdle() returns only after the observer has seen the set it waited for.
    {
        std::lock_guard lock(mMutex);
        --mCallbacksRunning;
    }
    mIdle.notify_all();
}

void AsyncMesher::run() {
    // Every parallel loop of a rebuild runs on mWorkers; anything else that reaches for oneTBB
    // stays on this thread instead of taking the shared workers from the frame's cores.
    tbb::task_arena arena(1);
    arena.execute([&] { loop(); });
}

void AsyncMesher::loop() {
    for (;;) {
        std::vector<Job> jobs;
        {
            std::unique_lock lock(mMutex);
            mWake.wait(lock, [&] { return mStop || (!mHeld && !mQueue.empty()); });
            if (mStop) return;
            jobs.swap(mQueue);
            // Cleared with the queue taken: a region change posted from now on cancels the
            // pass that follows.
            mCancel.store(false);
            ++mPasses;
        }
        try {
            // The replica passes through the caller's states in order; dirty blocks are
            // collected for the jobs after the last region change (a new region is built
            // whole).
            std::optional<GridRegion> newRegion;
            std::vector<const Job*> dirty;
            std::vector<SkeletonWrite> noted;
            for (const Job& j : jobs) {
                mReplica->store().apply(j.writes);
                if (!newRegion) noted.insert(noted.end(), j.writes.begin(), j.writes.end());
                if (j.region) {
                    newRegion = j.region;
                    dirty.clear();
                } else {
                    dirty.push_back(&j);
                }
            }
            // Keeps the polygonizer's grid sums current (no grid evaluations to rebuild the
            // blocks the writes reach), all the jobs' writes at once so that a skeleton several
            // samples rewrote is updated once; a region change starts afresh anyway.
            if (mPoly && !newRegion) mPoly->noteWrites(noted);
            const uint64_t lastEdit = jobs.back().edit;
            if (newRegion) {
                if (mOptions.preview) {
                    Polygonizer coarse(*mReplica, previewRegion(*newRegion), mRelTolerance);
                    coarse.useWorkers(mWorkers.get());
                    if (!coarse.rebuildAll(mOptions.threaded, &mCancel).unfinished.empty()) {
                        std::lock_guard lock(mMutex);
                        ++mCancelled;
                        continue;  // superseded already: the next pass takes the queue
                    }
                    auto set = std::const_pointer_cast<MeshChunks>(publishChunks(coarse, nullptr));
                    set->edits = lastEdit;
                    set->preview = true;
                    publish(std::move(set));
                }
                mPoly = std::make_unique<Polygonizer>(*mReplica, *newRegion, mRelTolerance);
                mPoly->useWorkers(mWorkers.get());
                mPending = mPoly->rebuildAll(mOptions.threaded, &mCancel).unfinished;
            } else {
                for (const Job* j : dirty)
                    Polygonizer::mergeBlocks(
                        mPending, j->points.empty() ? mPoly->blocksTouching(j->box)
                                                    : mPoly->blocksNear(j->points, j->radius));
                mPending = mPoly->rebuildBlocks(mPending, mOptions.threaded, &mCancel).unfinished;
            }
            if (!mPending.empty()) {
                std::lock_guard lock(mMutex);
                ++mCancelled;
                continue;
            }
            // The published set may be of another region (a preview): nothing to share then.
            const std::shared_ptr<const MeshChunks> before = mPublished;  // written only here
            auto set = std::const_pointer_cast<MeshChunks>(publishChunks(*mPoly, before.get()));
            set->edits = lastEdit;
            set->complete = true;
            publish(std::move(set));
        } catch (...) {
            {
                std::lock_guard lock(mMutex);
                mError = std::current_exception();
            }
            mIdle.notify_all();
            return;
        }
    }
}

}  // namespace vsculpt::core
