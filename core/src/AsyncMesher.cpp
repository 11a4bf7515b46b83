// SPDX-License-Identifier: MIT
#include "vsculpt/core/AsyncMesher.h"

#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
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
        mNewer.store(true);
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
            if (job.focus) mFocusInFlight.emplace_back(edit, job.posted);
        }
        mNewer.store(true);
        mQueue.push_back(std::move(job));
    }
    mWake.notify_one();
    return edit;
}

uint64_t AsyncMesher::post(std::vector<SkeletonWrite> writes, std::vector<Vec3> points,
                           double radius, std::optional<Focus> focus) {
    Job j;
    j.writes = std::move(writes);
    j.points = std::move(points);
    j.radius = radius;
    j.focus = focus;
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

std::vector<double> AsyncMesher::takeFocusDelaysMs() {
    std::lock_guard lock(mMutex);
    return std::exchange(mFocusDelaysMs, {});
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
        // A partial set shows the surroundings of every focus up to its edit (a pass rebuilds
        // around all of its edits' focuses; earlier edits' were shown by earlier sets).
        const auto now = Clock::now();
        auto takeDelays = [&](std::vector<std::pair<uint64_t, Clock::time_point>>& inFlight,
                              std::vector<double>& delays) {
            auto it = inFlight.begin();
            for (; it != inFlight.end() && it->first <= mPublished->edits; ++it) {
                // A host that never takes them (a session of hours) must not grow: the older
                // half goes when the list is full.
                if (delays.size() >= std::max<size_t>(1, mOptions.maxKeptDelays))
                    delays.erase(delays.begin(),
                                 delays.begin() + std::ptrdiff_t(delays.size() / 2 + 1));
                delays.push_back(
                    std::chrono::duration<double, std::milli>(now - it->second).count());
            }
            inFlight.erase(inFlight.begin(), it);
        };
        if (mPublished->complete || mPublished->partial) takeDelays(mFocusInFlight, mFocusDelaysMs);
        if (mPublished->complete) takeDelays(mInFlight, mDelaysMs);
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

bool AsyncMesher::rebuildAroundFocus(const std::vector<Focus>& focuses, uint64_t lastEdit) {
    // A set can be published only on top of one of this region.
    const std::shared_ptr<const MeshChunks> before = mPublished;  // written only here
    if (before->region != mPoly->region() || before->preview) return false;
    // Chunks touching a focus ball read blocks up to a chunk and a block beyond it
    // (publishChunks): those must be rebuilt for the chunks to be published now.
    const double margin = (Polygonizer::kChunkCells + Polygonizer::kBlockCells) *
                          mPoly->region().spacingMm * std::sqrt(3.0);
    std::vector<Vec3> centres;
    double radius = 0;
    for (const Focus& f : focuses) {
        centres.push_back(f.centre);
        radius = std::max(radius, f.radiusMm);
    }
    const Polygonizer::BlockList around = mPoly->blocksNear(centres, radius + margin);
    Polygonizer::BlockList near, rest;
    std::set_intersection(mPending.begin(), mPending.end(), around.begin(), around.end(),
                          std::back_inserter(near));
    if (near.empty() || near.size() == mPending.size()) return false;  // one pass does it all
    std::set_difference(mPending.begin(), mPending.end(), near.begin(), near.end(),
                        std::back_inserter(rest));
    Polygonizer::BlockList unfinished =
        mPoly->rebuildBlocks(near, mOptions.threaded, &mCancel).unfinished;
    const bool done = unfinished.empty();  // else a region change stopped it
    Polygonizer::mergeBlocks(rest, std::move(unfinished));
    if (done) {
        auto set = std::const_pointer_cast<MeshChunks>(publishChunks(*mPoly, before.get(), &rest));
        set->edits = lastEdit;
        publish(std::move(set));
    }
    mPending = std::move(rest);
    return done;
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
            // pass that follows, and any job interrupts the blocks left after the focus.
            mCancel.store(false);
            mNewer.store(false);
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
                std::vector<Focus> focuses;  // of the pass's edits
                for (const Job* j : dirty) {
                    Polygonizer::mergeBlocks(
                        mPending, j->points.empty() ? mPoly->blocksTouching(j->box)
                                                    : mPoly->blocksNear(j->points, j->radius));
                    if (j->focus) focuses.push_back(*j->focus);
                }
                const bool shown = mOptions.focusFirst && !focuses.empty() &&
                                   rebuildAroundFocus(focuses, lastEdit);
                // Once the tool's surroundings are shown, a newer edit interrupts the rest:
                // its own surroundings come before these blocks, which stay pending. Not twice
                // in a row, so the rest trails by at most a pass (measured: interrupted every
                // time, the whole mesh fell 200-400 ms behind in a stroke at zoom 5;
                // docs/benchmarks.md, stop 30).
                const bool interruptible = shown && !mRestInterrupted;
                mPending = mPoly
                               ->rebuildBlocks(mPending, mOptions.threaded,
                                               interruptible ? &mNewer : &mCancel)
                               .unfinished;
                mRestInterrupted = interruptible && !mPending.empty() && !mCancel.load();
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
