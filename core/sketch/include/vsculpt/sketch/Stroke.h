// Pen strokes as the tablet delivers them: timestamped canvas points with optional pressure.
// Units: position in millimetres on the sketch canvas (x right, y up), time in seconds on the
// caller's clock (any origin, non-decreasing within a stroke), pressure normalised to 0..1.
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <glm/vec2.hpp>

#include <vector>

namespace vsculpt::sketch {

struct StrokeSample {
    glm::dvec2 position{0.0};  // mm
    double time = 0.0;         // s
    double pressure = 1.0;     // 0..1; meaningful only when Stroke::hasPressure
};

/// One pen-down..pen-up trace. Plain value type; the clean-up session stores copies.
struct Stroke {
    std::vector<StrokeSample> samples;
    bool hasPressure = false;  // false for mice and pens without pressure
};

/// Throws std::invalid_argument naming the first problem: no samples, a non-finite position or
/// time, time going backwards, or (when hasPressure) a pressure outside [0, 1] or NaN.
void validateStroke(const Stroke& stroke);

/// The sample positions as a polyline (mm).
Polyline2 strokePositions(const Stroke& stroke);

/// Arc length of the stroke (mm).
double strokeLength(const Stroke& stroke);

/// Largest pressure in the stroke; 0 when the stroke has no pressure data.
double peakPressure(const Stroke& stroke);

/// Builds a stroke from positions with times start, start + dt, ... and no pressure (tests,
/// scripted input).
Stroke makeStroke(const Polyline2& points, double startTime = 0.0, double dt = 0.01);

}  // namespace vsculpt::sketch
