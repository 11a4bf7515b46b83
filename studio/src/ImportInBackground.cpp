// SPDX-License-Identifier: MIT
#include "vsculpt/studio/ImportInBackground.h"

#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/WorkerPool.h"

#include <tbb/task_arena.h>

#include <exception>
#include <utility>

namespace vsculpt::studio {

namespace {
// As an export: below the mesher's helpers (AsyncMesher::kHelperNice, +5), so the mesh on
// show and the frame come first.
constexpr int kImportNice = 10;
}  // namespace

ImportInBackground::ImportInBackground(std::filesystem::path file, core::ImportOptions options,
                                       int level, std::unique_ptr<core::Sculpture> copy)
    : mFile(std::move(file)), mStart(std::chrono::steady_clock::now()), mCopy(std::move(copy)) {
    mThread = std::thread(
        [this, options = std::move(options), level]() mutable { run(std::move(options), level); });
}

ImportInBackground::~ImportInBackground() {
    finish();
    if (mThread.joinable()) mThread.join();
}

void ImportInBackground::waitDone() const {
    std::unique_lock lock(mMutex);
    mChanged.wait(lock, [&] { return done(); });
}

double ImportInBackground::secondsSinceStart() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
}

ImportInBackground::Result ImportInBackground::take() {
    waitDone();
    Result r = std::move(mResult);
    mResult.report = r.report;  // kept for a placement again
    return r;
}

void ImportInBackground::placeAgain(std::unique_ptr<core::Sculpture> copy) {
    waitDone();
    std::lock_guard lock(mMutex);
    mCopy = std::move(copy);
    mPhase.store(Phase::Placing, std::memory_order_release);
    mChanged.notify_all();
}

void ImportInBackground::finish() {
    mStop.store(true, std::memory_order_relaxed);
    std::lock_guard lock(mMutex);
    mFinish = true;
    mChanged.notify_all();
}

void ImportInBackground::run(core::ImportOptions options, int level) {
    core::lowerThisThreadsPriority(kImportNice);
    // oneTBB's workers are shared with the frame and the mesher's passes; a low-priority
    // arena lets them take this work only when those have none.
    tbb::task_arena arena(tbb::task_arena::automatic, 1, tbb::task_arena::priority::low);
    core::Mesh mesh;  // this thread's: read once, placed as often as asked, freed here
    auto fail = [&](const std::exception& e) {
        // importMesh names the file; a placement refusal (too fine a level) does not.
        const std::string what = e.what(), name = mFile.string();
        mResult.error = what.rfind(name, 0) == 0 ? what : name + ": " + what;
    };
    try {
        arena.execute([&] { mesh = core::importMesh(mFile, options, &mResult.report); });
    } catch (const std::exception& e) {
        fail(e);
    }
    for (;;) {
        std::unique_ptr<core::Sculpture> copy;
        {
            std::lock_guard lock(mMutex);
            if (mFinish) break;
            copy = std::move(mCopy);
        }
        if (copy && mResult.error.empty()) {
            mPhase.store(Phase::Placing, std::memory_order_release);
            try {
                mResult.placedOnWrites = copy->store().writeCount();
                const int use = level != 0 ? level : core::importLevelFor(copy->levels(), mesh);
                level = use;  // placed again on the same level
                core::SolidPlacement placed;
                arena.execute([&] { placed = core::placeSolid(*copy, mesh, use, &mStop); });
                mResult.level = placed.level;
                mResult.changes = std::move(placed.changes);
            } catch (const core::PlacementStopped&) {
                // finish() came: nobody waits for this result.
            } catch (const std::exception& e) {
                fail(e);
            }
            copy.reset();  // the copy's memory goes as soon as it has served
        }
        std::unique_lock lock(mMutex);
        mResult.seconds = secondsSinceStart();
        mPhase.store(Phase::Done, std::memory_order_release);
        mChanged.notify_all();
        mChanged.wait(lock, [&] { return mFinish || mCopy; });
    }
    mesh = core::Mesh{};
    mEnded.store(true, std::memory_order_release);
}

}  // namespace vsculpt::studio
