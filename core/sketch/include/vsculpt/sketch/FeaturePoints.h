// Feature points of a stroke for curve clean-up (seed 000 section 5.3 (1)): both endpoints and
// the point farthest from the chord, which keeps the rough shape of a simple overdrawn stroke.
#pragma once

#include "vsculpt/sketch/Polyline.h"

namespace vsculpt::sketch {

/// {first point, farthest point from the endpoint chord, last point}, in drawing order (mm).
/// When the endpoints coincide (a loop) the middle point is the one farthest from the first.
///
/// maxChordRatio > 0 (not in the seed) refines this for strokes that bend a lot: any piece
/// between consecutive feature points whose farthest point lies more than maxChordRatio times
/// its chord length off the chord is split there again, so a long arc drawn in one stroke is
/// not reduced to three points. 0 gives the seed's three points.
/// Throws std::invalid_argument for fewer than 2 points, non-finite points or a negative ratio.
Polyline2 strokeFeaturePoints(const Polyline2& stroke, double maxChordRatio = 0.0);

}  // namespace vsculpt::sketch
