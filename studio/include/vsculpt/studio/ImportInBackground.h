// SPDX-License-Identifier: MIT
/// @file ImportInBackground.h
/// @brief A mesh file read, cleaned and placed as clay on a thread of its own (the windows:
/// a large scan takes seconds to read and place, and the frame must go on). The placement
/// runs on a copy of the sculpture (Sculpture::clone), so nothing the frame or the sculptor
/// does waits for it or races with it; Studio::pollImport commits the copy's after-states as
/// one step (Session::addPlacedSolid) when the sculpture is still the one copied, and has the
/// mesh placed again on a fresh copy when it is not (docs/import.md, "In the windows").
///
/// Threads: the owner (the frame thread) constructs, polls and destroys; the work runs on
/// one thread at nice +10 with oneTBB helpers of low arena priority. That thread keeps the
/// mesh (for placing again) and frees it itself: a large mesh takes milliseconds to free.
/// Units: object mm.
#pragma once

#include "vsculpt/core/ImportMesh.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/core/PlaceStroke.h"  // SkeletonChange
#include "vsculpt/core/Sculpture.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace vsculpt::studio {

class ImportInBackground {
  public:
    /// What a placement made: the level and the copy's changes (after-states), or why the
    /// import failed.
    struct Result {
        std::string error;  ///< empty: it worked; else the reason, naming the file
        core::ImportReport report;
        int level = 0;
        std::vector<core::SkeletonChange> changes;
        /// The copy's SkeletonStore::writeCount() before placing: the sculpture is still the
        /// one placed on exactly when its own count is this.
        uint64_t placedOnWrites = 0;
        double seconds = 0;  ///< from the start to the end of this placement, wall time
    };
    enum class Phase { Reading, Placing, Done };

    /// Reads `file` (core::importMesh with `options`) and places it on `copy` at `level`
    /// (0: core::importLevelFor).
    ImportInBackground(std::filesystem::path file, core::ImportOptions options, int level,
                       std::unique_ptr<core::Sculpture> copy);
    /// Ends the thread (after the phase under way) and waits for it.
    ~ImportInBackground();
    ImportInBackground(const ImportInBackground&) = delete;
    ImportInBackground& operator=(const ImportInBackground&) = delete;

    const std::filesystem::path& file() const { return mFile; }
    Phase phase() const { return mPhase.load(std::memory_order_acquire); }
    bool done() const { return phase() == Phase::Done; }
    /// Waits until done().
    void waitDone() const;
    /// Since the import began.
    double secondsSinceStart() const;
    /// Once done(): the placement's result (the changes are moved out).
    Result take();
    /// Once done(): places the mesh, already read, again on `copy` (the sculpture changed
    /// while the first placement ran); done() again when that is through.
    void placeAgain(std::unique_ptr<core::Sculpture> copy);
    /// Lets the thread go: it stops a placement under way (core::placeSolid's stop flag, within
    /// a slab of lattice vertices) or skips one after reading, frees the mesh and ends.
    /// Returns at once; ended() tells when the thread is through. Reading is not interrupted.
    void finish();
    bool ended() const { return mEnded.load(std::memory_order_acquire); }

  private:
    void run(core::ImportOptions options, int level);

    std::filesystem::path mFile;
    std::chrono::steady_clock::time_point mStart;
    mutable std::mutex mMutex;
    mutable std::condition_variable mChanged;
    std::unique_ptr<core::Sculpture> mCopy;  // guarded: the next placement's copy
    bool mFinish = false;                    // guarded
    Result mResult;                          // the thread's until done(), then the owner's
    std::atomic<Phase> mPhase{Phase::Reading};
    std::atomic<bool> mEnded{false};
    std::atomic<bool> mStop{false};  // finish() asks a placement under way to stop
    std::thread mThread;
};

}  // namespace vsculpt::studio
