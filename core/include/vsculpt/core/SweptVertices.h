// SPDX-License-Identifier: MIT
/// @file SweptVertices.h
/// @brief The lattice vertices a spherical tool passes over between two samples.
#pragma once

#include "vsculpt/core/Geometry.h"

#include <vector>

namespace vsculpt::core {

struct SweptVertex {
    LatticeCoord coord;
    double lateralMm = 0;  ///< distance from the vertex to the swept segment, <= radius
};

/// Every vertex of the lattice {spacing * (i, j, k)} inside the capsule of `radius` around the
/// segment a-b (a sphere when a == b), sorted by coordinate, each once. A vertex exactly on
/// the capsule's surface counts as inside (with a relative tolerance of 1e-9), so results do
/// not depend on rounding for the lattice-aligned strokes calibration uses. Long segments
/// are split so the work follows the capsule's volume, not its bounding box.
/// Units: mm. @pre spacing > 0, radius >= 0, a and b pass isUsablePoint().
std::vector<SweptVertex> sweptVertices(double spacing, const Vec3& a, const Vec3& b, double radius);

/// Distance from p to the segment a-b.
double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b);

}  // namespace vsculpt::core
