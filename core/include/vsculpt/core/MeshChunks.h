// SPDX-License-Identifier: MIT
/// @file MeshChunks.h
/// @brief A published, immutable set of chunk meshes: what a renderer draws while the mesher
/// goes on working (AsyncMesher.h). Once published a set is never changed, so any thread may
/// hold and read it; chunk meshes that did not change are shared between successive sets.
#pragma once

#include "vsculpt/core/Mesh.h"
#include "vsculpt/core/Zoom.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace vsculpt::core {

class Polygonizer;

struct MeshChunks {
    GridRegion region;      ///< the grid the chunks cut (object mm)
    int chunksPerAxis = 0;  ///< region.n / Polygonizer::kChunkCells
    /// Per chunk (index(x, y, z)): its version (Polygonizer::chunkVersion, unique in the
    /// process; 0 = never had triangles), its mesh (null: no triangles) and its bounds.
    std::vector<uint64_t> versions;
    std::vector<std::shared_ptr<const Mesh>> meshes;
    std::vector<Aabb> chunkBounds;
    Aabb bounds;  ///< of every triangle (empty when there are none)
    /// Edits included: every edit numbered up to this one (AsyncMesher::post) and none after.
    uint64_t edits = 0;
    /// The chunks equal a full rebuild of the sculpture after `edits` (partial == full). False
    /// for a preview.
    bool complete = false;
    /// A coarse stand-in (half the resolution) shown while a new region is being built.
    bool preview = false;
    /// The chunks around the last edit's focus (AsyncMesher::Focus, the tool) hold `edits`;
    /// others may still show an earlier edit, until the complete set follows. Not complete.
    bool partial = false;

    size_t index(int x, int y, int z) const {
        return (size_t(x) * chunksPerAxis + y) * chunksPerAxis + z;
    }
    size_t triangleCount() const;
    /// Every chunk's triangles in one mesh (vertices are not welded across chunks; the
    /// triangles are those of Polygonizer::mesh(), so canonicalMeshHash agrees).
    Mesh merged() const;
};

/// The polygonizer's chunks as a published set. Chunks whose version equals the one in
/// `previous` (same region) share its mesh; only the others are extracted (on the calling
/// thread: the mesher's, not the frame's). @pre `poly` has no unfinished blocks, or they are
/// listed (sorted) in `stale`: then a chunk whose own blocks or the blocks beyond its far
/// faces (whose edge vertices its triangles use) are among them keeps `previous`'s mesh and
/// version, so the set is consistent but partial (`previous` of the same region required).
std::shared_ptr<const MeshChunks> publishChunks(
    const Polygonizer& poly, const MeshChunks* previous,
    const std::vector<std::array<int, 3>>* stale = nullptr);

}  // namespace vsculpt::core
