// 2D and 3D polylines shared by the sketch geometry. Units: millimetres on the sketch canvas
// (tablet or window space scaled to mm); canvas x to the right, y up.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace vsculpt::sketch {

using Polyline2 = std::vector<glm::dvec2>;
using Polyline3 = std::vector<glm::dvec3>;

// Signed area of a closed polygon (last point joins the first); positive counter-clockwise.
double signedArea(const Polyline2& polygon);
// Centroid of the area a closed polygon encloses. @pre signedArea(polygon) != 0.
glm::dvec2 areaCentroid(const Polyline2& polygon);

// Length of the polyline; closed adds the segment from the last point back to the first.
double length(const Polyline2& line, bool closed);
double length(const Polyline3& line, bool closed);

// Resampling, one pair with distinct names: a spacing and a count were overloads once, and
// `resample(line, 10)` meant 10 points while `resample(line, 10.0)` meant 10 mm steps.

/// The most points a spacing-based resampling may produce (checked before allocating).
inline constexpr std::size_t kMaxResampledPoints = 1'000'000;

/// At arc-length steps of `spacingMm` from the first point; the last point is always kept, so
/// the final step may be shorter. Throws std::invalid_argument for an empty polyline, points
/// that are not finite or beyond kMaxStrokeCoordinate (Stroke.h), a spacing that is not
/// positive and finite, or more than maxPoints points. (ResampleStroke.cpp)
Polyline2 resampleBySpacing(const Polyline2& line, double spacingMm,
                            std::size_t maxPoints = kMaxResampledPoints);

/// At `count` points equally spaced in chord length (first and last kept). Throws
/// std::invalid_argument for fewer than two distinct points, non-finite points or count < 2.
/// (CurveCurvature.cpp)
Polyline2 resampleByCount(const Polyline2& line, int count);
Polyline3 resampleByCount(const Polyline3& line, int count);

}  // namespace vsculpt::sketch
