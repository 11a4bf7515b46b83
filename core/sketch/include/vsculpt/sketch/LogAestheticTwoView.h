// Combining a top-view and a side-view stroke into one space curve (paper 002, §2.2), and the
// reverse projection used to compare a generated curve with the strokes (§2.5). Units: mm.
//
// Views: the top view shows the X–Y plane, the side view the Y–Z plane; Y is the shared axis.
// A top stroke is a Polyline2 of (X, Y); a side stroke is a Polyline2 of (Y, Z), i.e. its .x
// holds Y and its .y holds Z.
//
// Matching rule: both strokes must be strictly monotone in Y (either direction), so each Y has
// one X and one Z. Over the overlap of their Y ranges, every top-stroke point keeps its (X, Y)
// and gets Z = Z_side(Y) by piecewise-cubic Hermite interpolation of the side stroke (slopes
// from the three-point non-uniform difference, O(h³) error); the two ends of the overlap are
// added as points too (X interpolated the same way from the top stroke) when they fall between
// top-stroke samples. The result runs in the top stroke's direction.
#pragma once

#include "vsculpt/sketch/Polyline.h"

namespace vsculpt::sketch {

// Throws std::invalid_argument when a stroke has fewer than 3 points or a non-finite
// coordinate, when a stroke is not strictly monotone in Y (naming the stroke and the point), or
// when the Y ranges do not overlap (or overlap in a single point).
Polyline3 combineTwoViews(const Polyline2& top, const Polyline2& side);

// Projections of a space curve: (X, Y) for the top view and (Y, Z) for the side view.
Polyline2 projectTopView(const Polyline3& curve);
Polyline2 projectSideView(const Polyline3& curve);

// Largest distance (mm) from a point of `stroke` to the polyline `reference` (one-sided
// Hausdorff distance), to report how far a projected curve strays from a drawn stroke. Throws
// std::invalid_argument for empty input or fewer than 2 reference points.
double maxDeviation(const Polyline2& stroke, const Polyline2& reference);

}  // namespace vsculpt::sketch
