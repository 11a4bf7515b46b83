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

/// Largest |x| or |y| of a stroke sample (mm): 1 km, the bound the sculpture's points have too
/// (core::isUsablePoint). Far beyond any drawing, and small enough that lengths and differences
/// of canvas points never overflow.
inline constexpr double kMaxStrokeCoordinate = 1.0e6;
/// Largest |time| of a stroke sample (s): 317 years, so seconds since the Unix epoch fit.
inline constexpr double kMaxStrokeTime = 1.0e10;

/// Throws std::invalid_argument naming the first problem: no samples, a position or time that
/// is not finite or beyond kMaxStrokeCoordinate / kMaxStrokeTime, time going backwards, or
/// (when hasPressure) a pressure outside [0, 1] or NaN.
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
