// Feature points of a stroke for curve clean-up (seed 000 section 5.3 (1)): both endpoints and
// the point farthest from the chord, which keeps the rough shape of a simple overdrawn stroke.
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <cstddef>

namespace vsculpt::sketch {

/// Default bound on the feature points of one stroke: a stroke that needs more is a scribble
/// or noise, not a shape (a 2 m spiral at featureChordRatio 0.05 needs about 40).
inline constexpr std::size_t kMaxFeaturePoints = 64;

/// {first point, farthest point from the endpoint chord, last point}, in drawing order (mm).
/// When the endpoints coincide (a loop) the middle point is the one farthest from the first.
///
/// maxChordRatio > 0 (not in the seed) refines this for strokes that bend a lot: any piece
/// between consecutive feature points whose farthest point lies more than maxChordRatio times
/// its chord length off the chord is split there again, so a long arc drawn in one stroke is
/// not reduced to three points. 0 gives the seed's three points. At most maxPoints (>= 3)
/// are returned: when more pieces qualify, those whose farthest point lies farthest off their
/// chord (mm) are split first, so a stroke under the cap gets exactly the uncapped result.
/// Throws std::invalid_argument for fewer than 2 points, non-finite points, a negative ratio or
/// maxPoints < 3.
Polyline2 strokeFeaturePoints(const Polyline2& stroke, double maxChordRatio = 0.0,
                              std::size_t maxPoints = kMaxFeaturePoints);

}  // namespace vsculpt::sketch
