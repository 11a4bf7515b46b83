// SPDX-License-Identifier: MIT
/// @file ExportMesh.h
/// @brief Writes a sculpture's mesh for other tools: OBJ, binary STL, binary PLY (with
/// normals), glTF 2.0 binary (.glb, via tinygltf), DXF (3DFACE entities, for CAD) and an
/// OpenVDB level set (.vdb, via OpenVDB's meshToLevelSet).
///
/// Files are written to a temporary name and renamed into place, so a failed export never
/// leaves a half-written file where a good one was. Units: millimetres (glTF's metres are
/// not applied: the values are mm, stated in the asset's extras).
#pragma once

#include "vsculpt/core/Mesh.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace vsculpt::core {

class ExportError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct ExportOptions {
    double voxelSizeMm = 1.0;     ///< .vdb: voxel size of the level set
    double narrowBandVoxels = 3;  ///< .vdb: half-width of the narrow band
};

/// Extensions exportMesh() understands, with the dot: ".obj", ".stl", ...
const std::vector<std::string>& exportExtensions();

/// Chooses the format from the file extension (case-insensitive). Throws ExportError naming
/// the path for an unknown extension, an empty mesh or a write failure.
void exportMesh(const Mesh& mesh, const std::filesystem::path& path,
                const ExportOptions& options = {});

}  // namespace vsculpt::core
