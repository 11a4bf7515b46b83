// SPDX-License-Identifier: MIT
/// @file Zoom.h
/// @brief Zoom levels (thesis §3.2.2-3.2.3): the polygonization grid of the region on show
/// and the tool sizes each zoom level offers. Skeleton data never changes with zoom.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Geometry.h"

#include <array>
#include <cstdint>

namespace vsculpt::core {

class ToolLevels;

/// A cubic block of N^3 grid cells. Grid vertices sit at spacing * (integer coordinates) in
/// object space, on the same global lattice for every region of a zoom level, so a zoomed
/// region's cells are exactly cells of the full-resolution grid.
struct GridRegion {
    double spacingMm = 1;
    std::array<int64_t, 3> originCell{0, 0, 0};  ///< global index of the first cell (min corner)
    int n = 128;                                 ///< cells per axis

    Vec3 vertexPos(int64_t gx, int64_t gy, int64_t gz) const {
        return Vec3(double(gx), double(gy), double(gz)) * spacingMm;
    }
    Aabb box() const {
        return Aabb{vertexPos(originCell[0], originCell[1], originCell[2]),
                    vertexPos(originCell[0] + n, originCell[1] + n, originCell[2] + n)};
    }
    friend bool operator==(const GridRegion&, const GridRegion&) = default;
};

/// Grid spacing at zoom level z (1..5): spacing_1 / 2^(z-1), spacing_1 = base * D_6.
double zoomSpacing(const SculptConfig& cfg, const ToolLevels& levels, int zoom);

/// The region shown at zoom level z: N^3 cells centred (to the nearest grid vertex) on
/// `centerMm`. At zoom 1 the centre is the initial sphere's centre: the whole sculpture.
GridRegion zoomRegion(const SculptConfig& cfg, const ToolLevels& levels, int zoom,
                      const Vec3& centerMm);

/// Whether tool level k may be used at zoom level z (configs: zoom.allowed_sizes).
bool toolAllowedAtZoom(const SculptConfig& cfg, int zoom, int level);

}  // namespace vsculpt::core
