// SPDX-License-Identifier: MIT
/// @file AsyncMesher.h
/// @brief Polygonizes a sculpture on its own thread, so the frame never waits for the mesher
/// (docs/async-mesher.md).
///
/// The caller's thread (the frame/input thread) keeps editing its sculpture: placement stays
/// on the input path. After each edit it posts the skeleton writes the edit made
/// (SkeletonStore::logWritesTo) and where the field may have changed. The mesher thread owns
/// a replica of the sculpture (a clone taken at construction): it replays the writes in order,
/// so the replica passes through exactly the caller's states, rebuilds the dirty blocks of
/// its own Polygonizer and publishes an immutable MeshChunks. A renderer draws
/// `published()` and never blocks on a rebuild.
///
/// - Coalescing: edits posted while a rebuild runs are applied together and their dirty
///   blocks rebuilt in one pass.
/// - Superseding: a region change (zoom) cancels the running rebuild between blocks (an
///   OpenVDB-style interrupter); the last published set stays on show, then a coarse preview
///   of the new region, then the new region at full resolution.
/// - Exactness: a set is published `complete` only when no dirty block is left; it then
///   equals a full rebuild of the sculpture after `edits` (partial == full).
/// - The tool first (Options::focusFirst, off by default): an edit posted with a Focus (where
///   the tool is) has the dirty blocks around it rebuilt first and published as a `partial`
///   set (the chunks there current, the others as before); the rest follows, and a newer edit
///   may interrupt it (its blocks stay dirty and are rebuilt after the newer edit's own; never
///   two passes in a row, so the rest trails by at most a pass).
///
/// Threads: post(), setRegion(), published(), waitIdle() and verify() may be called from any
/// one thread (the one editing the sculpture). The mesher thread touches only its replica.
#pragma once

#include "vsculpt/core/MeshChunks.h"
#include "vsculpt/core/SkeletonStore.h"
#include "vsculpt/core/Zoom.h"

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace vsculpt::core {

class Polygonizer;
class Sculpture;
class WorkerPool;

class AsyncMesher {
  public:
    /// Nice steps of the mesher's helpers below the frame (measured, docs/benchmarks.md stop
    /// 22: +5 keeps the frame's wall time near what SCHED_IDLE gave without its inversion).
    static constexpr int kHelperNice = 5;
    struct Options {
        bool threaded = true;  ///< spread each rebuild over the mesher's own worker threads
        /// How many, the mesher thread included: 0 = one per core.
        int threads = 0;
        /// Helpers (every thread but the mesher's) run this many nice steps below the thread
        /// that creates the mesher (WorkerPool.h): a waking frame thread preempts them at once,
        /// and they still get a share of a core when every core is busy. 0: the same priority.
        int helperNice = kHelperNice;
        /// How many publish delays are kept for takePublishDelaysMs (memory stays bounded in
        /// a session that never takes them).
        size_t maxKeptDelays = size_t(1) << 16;
        bool preview = true;  ///< publish a half-resolution preview of a new region first
        /// Rebuild and publish the blocks around a posted Focus first (see above). Off by
        /// default: measured, the surface under the tool came 20 % sooner and the whole mesh
        /// 25-30 % later, and partial sets can show seams (docs/async-mesher.md, stop 30).
        bool focusFirst = false;
        /// Called on the mesher thread with every set it publishes, after publishing (tests;
        /// a host that wants to wake its frame loop); waitIdle() also waits for it. Must not
        /// call into the mesher.
        std::function<void(const MeshChunks&)> onPublish;
    };

    /// Clones `sculpture` (on the calling thread) and polygonizes `region` before returning,
    /// so published() holds a complete set from the start; then starts the mesher thread.
    AsyncMesher(const Sculpture& sculpture, const GridRegion& region, double relTolerance,
                Options options);
    AsyncMesher(const Sculpture& sculpture, const GridRegion& region, double relTolerance)
        : AsyncMesher(sculpture, region, relTolerance, Options{}) {}
    /// Cancels the rebuild in progress and joins the thread.
    ~AsyncMesher();
    AsyncMesher(const AsyncMesher&) = delete;
    AsyncMesher& operator=(const AsyncMesher&) = delete;

    /// Where the sculptor looks as an edit is made: the tool's centre (object mm) and how far
    /// around it the surface is wanted first.
    struct Focus {
        Vec3 centre{0.0};
        double radiusMm = 0;
    };
    /// An edit of the caller's sculpture: its writes in the order made, and where f may have
    /// changed (within `radiusMm` of the points, or the box). Takes a lock only to queue.
    /// Returns the edit's number (1, 2, ...). Rethrows an error the mesher thread hit.
    uint64_t post(std::vector<SkeletonWrite> writes, std::vector<Vec3> changedPoints,
                  double radiusMm, std::optional<Focus> focus = std::nullopt);
    uint64_t post(std::vector<SkeletonWrite> writes, const Aabb& changedRegion);
    /// The view moves to `region` (a zoom change); cancels a rebuild in progress.
    uint64_t setRegion(const GridRegion& region);
    /// The region the mesher is building towards (the last one set).
    GridRegion targetRegion() const;

    /// The last set published (never null). Cheap: a lock and a shared_ptr copy.
    std::shared_ptr<const MeshChunks> published() const;
    /// The number of the last edit posted.
    uint64_t lastPosted() const;
    /// Waits until a complete set holding every edit posted so far is published (exports,
    /// `--check`, tests). Rethrows an error the mesher thread hit.
    void waitIdle();
    /// waitIdle(), then the mesher's Polygonizer::verifyAgainstFullRebuild on its replica.
    std::string verifyAgainstFullRebuild();

    /// Milliseconds from each edit's post() to the first complete set that holds it, for the
    /// edits published since the last call (benchmarks, `--stats`): at most
    /// Options::maxKeptDelays, the latest (when the list is full its older half is dropped).
    std::vector<double> takePublishDelaysMs();
    /// The same, to the first set that shows the surface around the edit's focus current: a
    /// partial set, or the complete one when none came first (edits posted with a Focus).
    std::vector<double> takeFocusDelaysMs();
    /// While held, posted jobs wait in the queue and are taken together on release (a host
    /// batching a burst of edits; tests of coalescing). waitIdle() must not be called while
    /// held with jobs queued.
    void hold(bool held);

    /// Rebuild passes run and passes cancelled so far.
    size_t passes() const;
    size_t cancelledPasses() const;

  private:
    using Clock = std::chrono::steady_clock;
    struct Job {
        uint64_t edit = 0;
        Clock::time_point posted;
        std::vector<SkeletonWrite> writes;
        std::vector<Vec3> points;
        double radius = 0;
        Aabb box;                          ///< used when points is empty
        std::optional<GridRegion> region;  ///< a region change
        std::optional<Focus> focus;
    };
    uint64_t enqueue(Job job);
    void run();
    void loop();
    void publish(std::shared_ptr<const MeshChunks> set);
    /// Rebuilds the dirty blocks around the focuses and publishes them as a partial set, when
    /// they are not all of mPending; returns whether it did.
    bool rebuildAroundFocus(const std::vector<Focus>& focuses, uint64_t lastEdit);
    void rethrowWorkerError();

    double mRelTolerance;
    Options mOptions;
    std::unique_ptr<Sculpture> mReplica;       // mesher thread only (after construction)
    std::unique_ptr<Polygonizer> mPoly;        // mesher thread only
    std::vector<std::array<int, 3>> mPending;  // dirty blocks of mPoly, mesher thread only
    bool mRestInterrupted = false;             // the last pass's rest was (mesher thread)

    mutable std::mutex mMutex;
    std::condition_variable mWake;  // jobs queued or stop
    std::condition_variable mIdle;  // a set published or an error
    std::vector<Job> mQueue;
    bool mStop = false;
    bool mHeld = false;
    uint64_t mPostedEdits = 0;
    int mCallbacksRunning = 0;  // onPublish calls under way (waitIdle waits for them)
    /// Everything posted is published complete and every observer has seen it. Under mMutex.
    bool idleLocked() const;
    GridRegion mTargetRegion;
    std::shared_ptr<const MeshChunks> mPublished;
    std::vector<std::pair<uint64_t, Clock::time_point>> mInFlight;  // edits not yet published
    std::vector<double> mDelaysMs;
    // Edits with a focus whose surroundings are not yet published, and their delays.
    std::vector<std::pair<uint64_t, Clock::time_point>> mFocusInFlight;
    std::vector<double> mFocusDelaysMs;
    size_t mPasses = 0, mCancelled = 0;
    std::exception_ptr mError;
    std::atomic<bool> mCancel{false};      // a region change or stop is queued
    std::atomic<bool> mNewer{false};       // any job is queued (interrupts the blocks left)
    std::unique_ptr<WorkerPool> mWorkers;  // rebuild loops of mPoly (null: serial)
    std::thread mThread;
};

}  // namespace vsculpt::core
