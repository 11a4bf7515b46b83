// SPDX-License-Identifier: MIT
/// @file ExportMesh.h
/// @brief Writes a sculpture's mesh for other tools: OBJ, binary STL, binary PLY (with
/// normals), glTF 2.0 binary (.glb, via tinygltf), DXF (3DFACE entities, for CAD) and an
/// OpenVDB level set (.vdb, via OpenVDB's meshToLevelSet).
///
/// Each file is rendered in memory, then written with writeFileAtomically (not durable), so a
/// failed export never leaves a half-written file where a good one was, no library opens the
/// output path itself, and a symlink at the output path is replaced, not written through.
///
/// Axes and units (issue #16): the sculpture is Z-up in millimetres; each file is written in
/// an ExportFrame, the format's default unless ExportOptions says otherwise:
///
///   format  up   units  why
///   .glb    +Y   m      required by glTF 2.0; anything else is refused
///   .obj    +Y   mm     OBJ readers (Blender, Maya, MeshLab) take +Y as up; no unit field,
///                       mm is what earlier exports wrote and what slicers and CAD assume
///   .stl    +Z   mm     slicers and CAD are Z-up in mm (Blender's STL importer is Z-up too)
///   .ply    +Z   mm     Blender's PLY importer is Z-up; scanning tools have no convention
///   .dxf    +Z   mm     CAD's world frame is Z-up; the unit goes into $INSUNITS
///   .vdb    +Z   mm     grids are axis-agnostic; "up" and "units" are stored as metadata
///
/// Y-up is the rotation (x, y, z) -> (x, z, -y): a proper rotation, so triangle winding and
/// outward normals stay valid. Meshes are rotated first, then scaled.
#pragma once

#include "vsculpt/core/Mesh.h"

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vsculpt::core {

class ExportError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// The axis of the file that points up, where the sculpture's +Z goes.
enum class UpAxis { Z, Y };
/// The length unit of a file's coordinates.
enum class LengthUnit { Millimetre, Centimetre, Metre };

/// "y" or "z" and "mm", "cm" or "m" (any case); std::invalid_argument naming the accepted
/// values otherwise.
UpAxis parseUpAxis(std::string_view text);
LengthUnit parseLengthUnit(std::string_view text);
const char* toString(UpAxis up);        ///< "y", "z"
const char* toString(LengthUnit unit);  ///< "mm", "cm", "m"
double mmPerUnit(LengthUnit unit);      ///< 1, 10, 1000

/// The axes and unit of a file's coordinates.
struct ExportFrame {
    UpAxis up = UpAxis::Z;
    LengthUnit units = LengthUnit::Millimetre;

    /// An object-space point (mm, Z-up) in this frame: rotated, then scaled.
    Vec3 point(const Vec3& objectMm) const;
    /// An object-space direction (a normal) in this frame: rotated only, so unit stays unit.
    Vec3 direction(const Vec3& object) const;
    /// True when the frame is object space itself (Z-up, mm).
    bool identity() const { return up == UpAxis::Z && units == LengthUnit::Millimetre; }
};

struct ExportOptions {
    std::optional<UpAxis> up;         ///< unset: the format's default (table above)
    std::optional<LengthUnit> units;  ///< unset: the format's default (table above)
    double voxelSizeMm = 1.0;         ///< .vdb: voxel size of the level set, in object mm
    double narrowBandVoxels = 3;      ///< .vdb: half-width of the narrow band
};

/// Extensions exportMesh() understands, with the dot: ".obj", ".stl", ...
const std::vector<std::string>& exportExtensions();

/// The frame a file at `path` is written in: the options where set, the format's default
/// otherwise. Throws ExportError naming the path for an unknown extension, or for a .glb asked
/// to be anything but Y-up in metres (the glTF 2.0 specification allows nothing else, and a
/// file that breaks it is what every glTF reader would show lying on its back).
ExportFrame exportFrame(const std::filesystem::path& path, const ExportOptions& options);

/// True when the format of `path` has one frame only (.glb), so ExportOptions::up and ::units
/// must stay unset for it.
bool formatFixesFrame(const std::filesystem::path& path);

/// Chooses the format from the file extension (case-insensitive) and writes the mesh in
/// exportFrame(path, options). Throws ExportError naming the path for an unknown extension,
/// a frame the format refuses, an empty mesh or a write failure (with the OS reason).
/// To fail early, before a long session whose result goes to `path`: ensureWritable(path)
/// (WriteFileAtomically.h).
void exportMesh(const Mesh& mesh, const std::filesystem::path& path,
                const ExportOptions& options = {});

}  // namespace vsculpt::core
