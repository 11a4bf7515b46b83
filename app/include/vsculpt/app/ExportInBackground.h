// SPDX-License-Identifier: MIT
/// @file ExportInBackground.h
/// @brief A whole-sculpture export meshed and written on its own thread, so that a window's
/// frame never waits for it (docs/window.md).
#pragma once

#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/Sculpture.h"

#include <atomic>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace vsculpt::app {

/// Writes the sculpture's mesh to `path` as `vsculpt play --out` and the windows' export do:
/// core::exportMesh, except a .dxf with sketch `curves` (object space, mm), which gets both,
/// the mesh as 3DFACEs on layer "sculpture" and the curves as 3D polylines on layer "sketch".
void writeSculptureFile(const core::Mesh& mesh, const std::filesystem::path& path,
                        const core::ExportOptions& options,
                        const std::vector<std::vector<core::Vec3>>& curves);

/// One export in flight. The thread owns its snapshot of the sculpture (edits made meanwhile
/// are not in the file: it holds the clay as it was when the export was asked for).
class ExportInBackground {
  public:
    /// Starts meshing `snapshot` at `spacingMm` (Session's wholeMeshOf) and writing it to
    /// `path` (core::exportMesh with `options`; its voxel size set to the spacing).
    /// `curves`: the sketch's, for a .dxf (writeSculptureFile).
    ExportInBackground(std::unique_ptr<const core::Sculpture> snapshot, double spacingMm,
                       std::filesystem::path path, core::ExportOptions options,
                       std::vector<std::vector<core::Vec3>> curves = {});
    /// Waits for the file: an export asked for is never dropped.
    ~ExportInBackground();
    ExportInBackground(const ExportInBackground&) = delete;
    ExportInBackground& operator=(const ExportInBackground&) = delete;

    const std::filesystem::path& path() const { return mPath; }
    /// True once the file is written or the export has failed.
    bool done() const { return mDone.load(std::memory_order_acquire); }
    /// Waits for the export; what happened, for the user: "exported PATH (N triangles)", or
    /// "export to PATH failed: why". `failed` tells which.
    std::string wait(bool* failed = nullptr);

  private:
    std::filesystem::path mPath;
    std::string mOutcome;
    bool mFailed = false;
    std::atomic<bool> mDone{false};
    std::thread mThread;  // last: started once the members it writes exist
};

}  // namespace vsculpt::app
