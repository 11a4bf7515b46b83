// Fitting a planar log-aesthetic curve to a drawn stroke (paper 002, §2.4: replace the drawn
// curve by an LA curve with matching start point and direction). Units: mm, radians.
//
// Method: the stroke is resampled at N points equally spaced in arc length. The LA curve is
// parameterised by (α, ln|κ0|, ln|κ1|, θ0, start x, start y, ln length), κ0 and κ1 the start and
// end curvature (Λ follows from laLambdaForRadiusRatio, so every candidate is a valid curve);
// the turning direction is the sign of the stroke's total turning. Nelder–Mead minimises the
// mean squared distance between the i-th resampled stroke point and the LA point at the same
// fraction of arc length. Start values: start point and direction of the stroke, end curvatures
// from curveDifferential, α from the stroke's curvature graph. One restart from the optimum
// guards against a collapsed simplex. A single LA segment has monotone curvature and no
// inflection: strokes with an inflection get a poor fit, which maxError reports.
#pragma once

#include "vsculpt/sketch/LogAestheticCurve.h"
#include "vsculpt/sketch/Polyline.h"

namespace vsculpt::sketch {

struct LaFitOptions {
    int samples = 100;         // N
    int halfWindow = 0;        // curvature window for the start values; 0: max(2, N/20)
    int maxIterations = 3000;  // per Nelder–Mead run
};

struct LaFitResult {
    LaPlanarParams params;
    double rmsError = 0.0;    // mm, between arc-length-corresponding points
    double maxError = 0.0;    // mm, largest distance of a resampled stroke point to the LA curve
    double graphAlpha = 0.0;  // α read from the stroke's curvature graph (NaN if degenerate)
    int evaluations = 0;
};

// Throws std::invalid_argument for fewer than 3 points, a non-finite coordinate, zero length,
// or options out of range (samples < 8, maxIterations < 1, halfWindow < 0).
LaFitResult fitLaPlanarCurve(const Polyline2& drawn, const LaFitOptions& options = {});

struct LaSpaceFitResult {
    LaSpaceParams params;
    double rmsError = 0.0;    // mm, between arc-length-corresponding points
    double maxError = 0.0;    // mm, largest distance of a resampled input point to the LA curve
    double graphAlpha = 0.0;  // from the curve's CLDG (NaN if degenerate)
    double graphBeta = 0.0;   // from the curve's TLDG (NaN if degenerate, e.g. a planar curve)
    int evaluations = 0;
};

// Space version (paper 002, §2.4: the combined curve replaced by an LA space curve). Same method
// over 13 parameters: α, ln κ0, ln κ1, β, ln|τ0|, ln|τ1| (torsion sign from the curve's total
// torsion), start point, a rotation vector applied to the estimated start Frenet frame, and
// ln length. Curvature and torsion must each be monotone (one LA segment). Throws as
// fitLaPlanarCurve.
LaSpaceFitResult fitLaSpaceCurve(const Polyline3& curve, const LaFitOptions& options = {});

}  // namespace vsculpt::sketch
