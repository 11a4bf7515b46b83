// Arc-length resampling of strokes: tablets report points at a fixed rate, so raw spacing
// follows pen speed; the clean-up and detectors want spacing that follows the geometry.
#pragma once

#include "vsculpt/sketch/Stroke.h"

namespace vsculpt::sketch {

/// Resamples at arc-length steps of `spacing` mm starting at the first sample; the last input
/// sample is always kept, so the final step may be shorter. Time and pressure are interpolated
/// linearly along each input segment. A stroke of zero length gives its first sample only.
/// Throws std::invalid_argument for an invalid stroke (see validateStroke) or spacing that is
/// not a positive finite number.
Stroke resampleByArcLength(const Stroke& stroke, double spacing);

/// Same for a bare polyline (mm). Throws for an empty polyline, non-finite points or spacing.
Polyline2 resampleByArcLength(const Polyline2& line, double spacing);

}  // namespace vsculpt::sketch
