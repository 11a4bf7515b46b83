// Interpolating cubic splines through sketch points (natural ends when open, periodic when
// closed). Used to draw cleaned-up strokes through their feature points and to close sections.
// Units follow the input (millimetres on the canvas or in model space).
#pragma once

#include "vsculpt/sketch/Polyline.h"

namespace vsculpt::sketch {

/// Interpolating cubic spline through `points` with chord-length parameters: natural end
/// conditions when open, periodic when closed. Returns the curve sampled with
/// `samplesPerSpan` points per span, starting at each knot (the last knot appended when open).
/// Throws std::invalid_argument for fewer than 2 points (3 when closed) or samplesPerSpan < 1.
///
/// Chord-length parameters need distinct consecutive knots, so consecutive coincident points
/// (distance <= 1e-12 mm times the extent of the points) are merged first, and when closed a last
/// point equal to the first is dropped; the span count is that of the merged knots. Non-finite
/// coordinates throw std::invalid_argument. Collinear knots in monotone order give the exact
/// straight line (the second derivatives vanish).
Polyline2 sampleNaturalSpline(const Polyline2& points, bool closed, int samplesPerSpan);
Polyline3 sampleNaturalSpline(const Polyline3& points, bool closed, int samplesPerSpan);

}  // namespace vsculpt::sketch
