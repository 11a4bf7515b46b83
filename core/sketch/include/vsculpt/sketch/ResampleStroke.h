// Arc-length resampling of strokes: tablets report points at a fixed rate, so raw spacing
// follows pen speed; the clean-up and detectors want spacing that follows the geometry.
#pragma once

#include "vsculpt/sketch/Stroke.h"

#include <cstddef>

namespace vsculpt::sketch {

/// Default bound on the points one resampling may produce (32 MB of samples). A caller that
/// must not fail on long input picks its step with boundedSpacing instead of relying on it.

/// Resamples at arc-length steps of `spacing` mm starting at the first sample; the last input
/// sample is always kept, so the final step may be shorter. Time and pressure are interpolated
/// linearly along each input segment. A stroke of zero length gives its first sample only.
/// Throws std::invalid_argument for an invalid stroke (see validateStroke), spacing that is
/// not a positive finite number, or a result that would have more than maxPoints points
/// (checked before anything is allocated).
Stroke resampleBySpacing(const Stroke& stroke, double spacing,
                         std::size_t maxPoints = kMaxResampledPoints);

// The same for a bare polyline: resampleBySpacing in Polyline.h.

/// `spacing`, or the wider step that keeps resampling a line of `length` mm within maxPoints
/// points (>= 4). Throws std::invalid_argument for a non-finite or negative length, spacing
/// that is not positive and finite, or maxPoints < 4.
double boundedSpacing(double length, double spacing, std::size_t maxPoints);

}  // namespace vsculpt::sketch
