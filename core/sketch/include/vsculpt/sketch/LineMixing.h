// Straight-line extraction for the incremental clean-up (seed 000 section 5.2, "line-segment
// mixing"): overdrawn straight strokes that agree in angle and position become one segment whose
// angle is a running mean in drawing order, so later strokes weigh more.
// Units: millimetres, angles in radians.
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <glm/vec2.hpp>

namespace vsculpt::sketch {

struct Segment2 {
    glm::dvec2 a{0.0};
    glm::dvec2 b{0.0};
};

struct LineMixParams {
    /// Strokes are the same line when their directions differ by less than this (rad, modulo pi).
    /// The seed gives no value; 12 degrees.
    double maxAngle = 0.21;
    /// ... and the midpoint of one lies within this distance (mm) of the other segment.
    double maxDistance = 4.0;
    /// Weight of the newer segment's direction in the mix. Seed: 0.5 (mean of the two angles).
    double angleWeight = 0.5;
    /// How far the mixed line moves from the older line towards the newer segment's midpoint.
    /// Seed: 1 (the result passes through the newer midpoint); below 1 averages out hand jitter.
    double offsetWeight = 1.0;
};

/// Total-least-squares line through the points, trimmed to the extent of their projections and
/// oriented from the first point towards the last. Throws std::invalid_argument for fewer than
/// 2 distinct points or non-finite points.
Segment2 fitSegment(const Polyline2& points);

/// Direction difference of two segments modulo pi, in [0, pi/2] (rad).
double angleBetween(const Segment2& s, const Segment2& t);

/// Seed rule: angle difference below maxAngle and the midpoint of either segment within
/// maxDistance of the other segment.
bool isSameLine(const Segment2& s, const Segment2& t, const LineMixParams& params = {});

/// Mixes an older (already cleaned) segment with a newer one: direction is the weighted mean
/// (angleWeight on the newer, sign-aligned so opposite drawing directions agree), the line
/// passes through the newer midpoint moved back towards the older line by (1 - offsetWeight),
/// and the extent covers the projections of all four endpoints (overdrawing can lengthen a
/// line, never shorten it). Oriented like the older segment. Throws std::invalid_argument for
/// degenerate segments.
Segment2 mixSegments(const Segment2& older, const Segment2& newer,
                     const LineMixParams& params = {});

}  // namespace vsculpt::sketch
