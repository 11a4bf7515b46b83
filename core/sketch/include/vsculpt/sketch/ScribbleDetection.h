// Scribble detection: a stroke that goes back and forth many times over a small area (hatching,
// an erase gesture) is not a line to clean up. The UI decides what a scribble means.
#pragma once

#include "vsculpt/sketch/Polyline.h"
#include "vsculpt/sketch/Stroke.h"

#include <cstddef>

namespace vsculpt::sketch {

struct ScribbleParams {
    /// Arc-length resampling step before measuring turns (mm); hides tablet jitter.
    double spacing = 1.0;
    /// A turn of at least this much (rad) within `reversalWindow` of arc counts as a reversal.
    double reversalAngle = 2.5;
    double reversalWindow = 6.0;  // mm
    /// Scribble when there are at least this many reversals ...
    int minReversals = 4;
    /// ... and the ink length is at least this multiple of the bounding-box diagonal.
    double minInkRatio = 3.0;
    /// Most resampled points examined (>= 4): a stroke longer than about maxPoints * spacing
    /// is resampled at a wider step, so the cost stays bounded (4 m of ink at 1 mm).
    std::size_t maxPoints = 4096;
};

/// Number of direction reversals as defined by ScribbleParams.
int countReversals(const Polyline2& line, const ScribbleParams& params = {});

/// True for back-and-forth strokes (see ScribbleParams). Throws std::invalid_argument for
/// non-finite points or non-positive parameters.
bool isScribble(const Polyline2& line, const ScribbleParams& params = {});
bool isScribble(const Stroke& stroke, const ScribbleParams& params = {});

}  // namespace vsculpt::sketch
