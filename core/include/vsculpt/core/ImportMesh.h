// SPDX-License-Identifier: MIT
/// @file ImportMesh.h
/// @brief Reads a triangle mesh from another tool (OBJ, STL, PLY, glTF 2.0 .gltf/.glb,
/// through Assimp) into object space (mm, Z up) as a closed, outward-oriented solid that
/// placeSolid() accepts, so a scanned or modelled shape becomes clay to sculpt on
/// (issue #16, docs/import.md).
///
/// Axes and units: a file is read in the frame ExportMesh.h writes that format in, unless
/// ImportOptions says otherwise, so export -> import with the defaults gives back the
/// sculpture's own coordinates for every format vsculpt writes:
///
///   format         up   units  (the file's frame, turned back to Z up mm)
///   .glb / .gltf   +Y   m      glTF 2.0 is always +Y up in metres
///   .obj           +Y   mm     what exportMesh writes and OBJ readers assume
///   .stl / .ply    +Z   mm     slicers, CAD, scanners
///
/// Y up is undone by (x, y, z) -> (x, -z, y), the inverse of the export's turn (a rotation,
/// so winding and volume keep their sign). Then the file units are scaled to mm, then
/// `fitMm` scales about the origin, then `centreAt` moves the box centre.
///
/// Cleaning: every node transform of the scene is applied (mirroring ones flip the winding
/// back), all meshes are merged, points and lines are dropped, polygons are triangulated,
/// vertices at the same position are welded (exact equality of the file's coordinates),
/// triangles that use a vertex twice are dropped, a triangle given twice is kept once and a
/// back-to-back pair (the same corners, opposite windings: a sheet of no thickness) goes. Each
/// connected piece is then wound consistently and turned outward (a piece inside another, such as a
/// cavity, inward). What is still open or non-manifold after that is rebuilt closed through OpenVDB
/// level sets (a morphological closing: thicken the surface, fill what the outside cannot reach,
/// shrink back; ImportOptions::repair, on by default, with a warning in ImportReport::notes) or
/// refused.
#pragma once

#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/Mesh.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vsculpt::core {

class ToolLevels;

/// A file that cannot be imported; the message starts with the file's path and says what is
/// wrong (unreadable, not a mesh, empty, non-finite, too large, open). An std::invalid_argument
/// because it is bad input, as a bad script line is (`vsculpt play` exits 2 for it).
class ImportError : public std::invalid_argument {
  public:
    using std::invalid_argument::invalid_argument;
};

struct ImportOptions {
    std::optional<UpAxis> up;         ///< the file's up axis; unset: the format's (table above)
    std::optional<double> mmPerUnit;  ///< mm per file unit (> 0); unset: the format's
    std::optional<double> fitMm;      ///< scale (about the origin) so the largest extent is this
    std::optional<Vec3> centreAt;     ///< move the bounding box's centre here (object mm)
    /// Rebuild a mesh that stays open or non-manifold after welding and orienting through a
    /// level set (closed by construction); false: refuse it (ImportError).
    bool repair = true;
    /// Voxel size of the repair's level sets in object mm; 0: the largest extent / 128, or
    /// a quarter of the gap when that is larger.
    double repairVoxelMm = 0;
    /// The repair's closing radius in object mm: holes up to about twice this wide are
    /// sealed, concave creases are rounded to about this radius; 0: the largest extent / 32.
    /// At least two voxels.
    double repairGapMm = 0;
};

/// What importMesh did, for the user: counts and notes (a repair, flipped pieces).
struct ImportReport {
    size_t fileTriangles = 0;        ///< triangles after triangulation, before cleaning
    size_t vertices = 0;             ///< after welding
    size_t triangles = 0;            ///< of the mesh returned
    size_t droppedDegenerate = 0;    ///< triangles using a vertex twice
    size_t droppedDuplicate = 0;     ///< repeats of a triangle, and back-to-back pairs
    size_t flippedTriangles = 0;     ///< rewound to agree with their neighbours or point outward
    size_t openEdges = 0;            ///< boundary edges before any repair
    size_t nonManifoldEdges = 0;     ///< edges of more than two triangles before any repair
    bool repaired = false;           ///< rebuilt through a level set
    double repairVoxelMm = 0;        ///< the level sets' voxel size when repaired
    double repairGapMm = 0;          ///< the closing radius when repaired
    std::vector<std::string> notes;  ///< one line each, naming the file; each a warning (the caller says so)
};

/// Extensions importMesh() reads, with the dot: ".obj", ".stl", ".ply", ".gltf", ".glb".
const std::vector<std::string>& importExtensions();

/// "mm", "cm", "m" or "in" (any case), or a positive number of mm per unit; std::invalid_argument
/// naming the accepted values otherwise.
double parseImportUnit(std::string_view text);

/// Reads the file and returns a closed, outward-oriented triangle mesh in object space (mm,
/// Z up; no normals) that validateSolidMesh() accepts. Throws ImportError naming the file for
/// an extension not in importExtensions(), a file that cannot be read, is not a mesh, holds
/// no triangles, non-finite coordinates or more than 20 million triangles, lies beyond 1e6 mm
/// after the frame and options, or stays open (with the edge counts) when `options.repair` is
/// false or the repair leaves nothing. std::invalid_argument for bad options.
/// @param report filled when given (counts, notes); may be null.
Mesh importMesh(const std::filesystem::path& path, const ImportOptions& options = {},
                ImportReport* report = nullptr);

/// The checks importMesh() makes before it reads the file (extension, options, a folder, an
/// unreadable, empty or too large file, a damaged PLY header), with the same errors: quick,
/// so a dialog can refuse a mistyped path at once before the import runs on a thread.
void checkImportFile(const std::filesystem::path& path, const ImportOptions& options = {});

/// The tool level an imported solid is placed on when none is given: the coarsest level
/// whose lattice spacing is at most half the solid's mean thickness (volume / surface area:
/// a quarter of a tube's radius, a sixth of a ball's), so its thinner parts keep their
/// volume (docs/import.md has the measurements); coarser when that level would put more
/// than 1.5 million lattice vertices inside the solid (one edit holds at most 3 million).
/// solidLevelFor() (PlaceSolid.h) looks only at the bounding box, which suits sketched
/// solids but loses the thin parts of sculpted or scanned ones.
int importLevelFor(const ToolLevels& levels, const Mesh& solid);

/// The cleaning steps of importMesh() on a mesh already in object space (mm): weld equal
/// positions, drop triangles using a vertex twice, wind each piece consistently and outward,
/// repair or refuse what stays open. `name` starts every message (a file path). Exposed for
/// meshes from other sources and for tests.
Mesh makeSolidMesh(const Mesh& mesh, const std::string& name, const ImportOptions& options = {},
                   ImportReport* report = nullptr);

}  // namespace vsculpt::core
