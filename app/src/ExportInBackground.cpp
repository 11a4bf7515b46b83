// SPDX-License-Identifier: MIT
#include "vsculpt/app/ExportInBackground.h"

#include "vsculpt/core/ExportDxf.h"
#include "vsculpt/core/WorkerPool.h"
#include "vsculpt/studio/Session.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <exception>
#include <utility>

namespace vsculpt::app {

void writeSculptureFile(const core::Mesh& mesh, const std::filesystem::path& path,
                        const core::ExportOptions& options,
                        const std::vector<std::vector<core::Vec3>>& curves) {
    if (path.extension() == ".dxf" && !curves.empty()) {
        // CAD gets the sketch too: the sculpture as 3DFACEs, the curves as polylines. A curve
        // that ends where it began is a closed polyline (found by QA: every loop came out
        // open), written without the repeated point.
        core::DxfOptions d;
        d.surfaceLayer = "sculpture";
        d.curveLayer = "sketch";
        d.frame = core::exportFrame(path, options);
        std::vector<std::vector<core::Vec3>> written = curves;
        for (std::vector<core::Vec3>& c : written) {
            const bool closed = c.size() >= 4 && c.front() == c.back();
            if (closed) c.pop_back();
            d.closedCurves.push_back(closed);
        }
        core::writeDxf(path, std::span<const core::Mesh>(&mesh, 1), written, d);
    } else {
        core::exportMesh(mesh, path, options);
    }
}

namespace {
// Below the mesher's helpers (AsyncMesher::kHelperNice, +5): the mesh on show comes first.
constexpr int kExportNice = 10;
}  // namespace

ExportInBackground::ExportInBackground(std::unique_ptr<const core::Sculpture> snapshot,
                                       double spacingMm, std::filesystem::path path,
                                       core::ExportOptions options,
                                       std::vector<std::vector<core::Vec3>> curves)
    : mPath(std::move(path)) {
    mThread = std::thread([this, snapshot = std::move(snapshot), spacingMm,
                           options = std::move(options), curves = std::move(curves)]() mutable {
        try {
            // Beside the frame and the mesher, never ahead of them: this thread and helpers
            // of its own for the other cores run at a lower priority (WorkerPool.h), and
            // any other oneTBB loop stays on this thread, off the shared workers the frame
            // may call on.
            core::lowerThisThreadsPriority(kExportNice);
            core::WorkerPool workers(std::max(1, int(std::thread::hardware_concurrency())) - 1, 0);
            core::Mesh mesh;
            tbb::task_arena(1).execute(
                [&] { mesh = studio::wholeMeshOf(*snapshot, spacingMm, &workers); });
            snapshot.reset();  // the copy is not needed while the file is written
            options.voxelSizeMm = spacingMm;
            writeSculptureFile(mesh, mPath, options, curves);
            mOutcome = "exported " + mPath.string() + " (" + std::to_string(mesh.triangleCount()) +
                       " triangles)";
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
