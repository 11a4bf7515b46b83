// Whether a stroke was meant as a closed loop. Designers close loops loosely: they stop short
// of the start or overshoot past it, so the test looks for the end near the start region, not
// for coincident endpoints.
#pragma once

#include "vsculpt/sketch/Polyline.h"
#include "vsculpt/sketch/Stroke.h"

namespace vsculpt::sketch {

struct ClosednessParams {
    /// Largest allowed end-to-start gap as a fraction of the stroke length.
    double maxGapRatio = 0.1;
    /// Fraction of the length, at each end, in which the other end may land (overshoot).
    double endRegionRatio = 0.25;
};

/// True when the last point lies within maxGapRatio * length of the first endRegionRatio of the
/// curve (by arc length) or the first point lies that close to the last endRegionRatio.
/// Lines shorter than 3 points or of zero length are open. Throws std::invalid_argument for
/// non-finite points or ratios outside (0, 1].
bool isClosedStroke(const Polyline2& line, const ClosednessParams& params = {});
bool isClosedStroke(const Stroke& stroke, const ClosednessParams& params = {});

}  // namespace vsculpt::sketch
