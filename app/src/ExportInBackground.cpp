// SPDX-License-Identifier: MIT
#include "vsculpt/app/ExportInBackground.h"

#include "vsculpt/studio/Session.h"

#include <exception>
#include <utility>

namespace vsculpt::app {

ExportInBackground::ExportInBackground(std::unique_ptr<const core::Sculpture> snapshot,
                                       double spacingMm, std::filesystem::path path,
                                       core::ExportOptions options)
    : mPath(std::move(path)) {
    mThread = std::thread(
        [this, snapshot = std::move(snapshot), spacingMm, options = std::move(options)]() mutable {
            try {
                const core::Mesh mesh = studio::wholeMeshOf(*snapshot, spacingMm);
                snapshot.reset();  // the copy is not needed while the file is written
                options.voxelSizeMm = spacingMm;
                core::exportMesh(mesh, mPath, options);
                mOutcome = "exported " + mPath.string() + " (" +
                           std::to_string(mesh.triangleCount()) + " triangles)";
            } catch (const std::exception& e) {
                // Errors reach the user as the outcome; a broken invariant is one too here, since
                // nothing on this thread can be rethrown to the frame loop.
                mOutcome = "export to " + mPath.string() + " failed: " + e.what();
                mFailed = true;
            }
            mDone.store(true, std::memory_order_release);
        });
}

ExportInBackground::~ExportInBackground() {
    if (mThread.joinable()) mThread.join();
}

std::string ExportInBackground::wait(bool* failed) {
    if (mThread.joinable()) mThread.join();
    if (failed) *failed = mFailed;
    return mOutcome;
}

}  // namespace vsculpt::app
