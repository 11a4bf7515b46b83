// SPDX-License-Identifier: MIT
/// @file ExportMesh.h
/// @brief Writes a sculpture's mesh for other tools: OBJ, binary STL, binary PLY (with
/// normals), glTF 2.0 binary (.glb, via tinygltf), DXF (3DFACE entities, for CAD) and an
/// OpenVDB level set (.vdb, via OpenVDB's meshToLevelSet).
///
/// Each file is rendered in memory, then written with writeFileAtomically (not durable), so a
/// failed export never leaves a half-written file where a good one was, no library opens the
/// output path itself, and a symlink at the output path is replaced, not written through.
/// Units: millimetres (in .glb the values are mm under a node that scales them to glTF's
/// metres).
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
/// the path for an unknown extension, an empty mesh or a write failure (with the OS reason).
/// To fail early, before a long session whose result goes to `path`: ensureWritable(path)
/// (WriteFileAtomically.h).
void exportMesh(const Mesh& mesh, const std::filesystem::path& path,
                const ExportOptions& options = {});

}  // namespace vsculpt::core
