// Self-intersections of a stroke polyline (loops, crossings of a figure eight).
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <cstddef>
#include <vector>

namespace vsculpt::sketch {

struct SelfIntersection {
    std::size_t segmentA = 0;  // segment i joins point i and i + 1 (the closing segment is n-1)
    std::size_t segmentB = 0;  // segmentA < segmentB
    double tA = 0.0;           // parameter along segment A, 0..1
    double tB = 0.0;
    glm::dvec2 point{0.0};  // mm
};

/// Default bound on the crossings returned: a stroke overdrawn back and forth on itself has
/// crossings quadratic in its points (a 4000-point zigzag, millions), none of them useful.
inline constexpr std::size_t kMaxSelfIntersections = 10'000;

/// Crossings between non-adjacent segments, ordered by (segmentA, segmentB): the first
/// maxCount of them (when the result has maxCount entries there may be more). When `closed`
/// the segment from the last point back to the first is included and it is adjacent to segment
/// 0. Collinear overlaps report one intersection at the start of the shared part. Zero-length
/// segments are skipped. O(n^2) time with bounding-box rejection, memory O(n + maxCount):
/// meant for single strokes (a few thousand points). Throws std::invalid_argument for
/// non-finite points.
std::vector<SelfIntersection> findSelfIntersections(const Polyline2& line, bool closed,
                                                    std::size_t maxCount = kMaxSelfIntersections);

/// True when findSelfIntersections would return anything (stops at the first crossing).
bool hasSelfIntersection(const Polyline2& line, bool closed);

}  // namespace vsculpt::sketch
