// Inverse Chaikin: from a clean closed curve to a control polygon whose Chaikin subdivision
// reproduces it. The Chaikin limit touches every control-polygon edge at its midpoint, tangent
// to the edge, so the polygon is built from tangent lines of the curve (seed 000 §6.2.2, seed
// 001 §3.1): tangent points at the x and y extrema and at the inflections, one extra tangent
// per corner placed so that its point is the middle of its new edge, then the d/l correction
// that pulls every tangent point towards the middle of its edge. A least-squares fit of the
// closed quadratic B-spline is the quality baseline. Units: those of the input (mm).
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <glm/vec2.hpp>

#include <vector>

namespace vsculpt::sketch {

struct InverseChaikinOptions {
    // Edges whose tangent point is off-centre by d/l ≥ this (d = |l₁ − l₂|, l = l₁ + l₂, lᵢ the
    // distances to the edge's two vertices) are corrected; 0.1 is the seed's value.
    double imbalanceThreshold = 0.1;
    int maxCorrectionRounds = 30;
    // The curve is resampled to this many points at equal arc length before analysis.
    int resampleCount = 1024;
    // Add a tangent between two tangent points when their tangents turn by more than this
    // (radians); the seed adds one per quadrant, i.e. between axis extrema 90° apart.
    double splitTurn = 0.5;
};

struct InverseChaikinResult {
    // Control polygon, same orientation as the curve; edge i runs polygon[i] → polygon[i+1].
    Polyline2 polygon;
    // tangentPoints[i] is where the curve touches edge i (on the resampled curve).
    std::vector<glm::dvec2> tangentPoints;
    // Largest d/l over the edges after correction. Edges touching at an inflection are not
    // corrected (their point must stay on the inflection; the seed skips them too) and are
    // not counted.
    double maxImbalance = 0.0;
    // Number of inflection points found on the curve (each one is a tangent point).
    int inflections = 0;
};

// Tangent-line control polygon of a closed curve (last point joins the first; at least 8
// points, no repeated consecutive points needed). Extrema are taken in the canvas axes, so a
// curve symmetric about an axis gets a symmetric polygon. Throws std::invalid_argument for
// fewer than 8 points, non-finite coordinates or zero length or area.
InverseChaikinResult inverseChaikin(const Polyline2& curve,
                                    const InverseChaikinOptions& options = {});

// A tangent line: a point on the curve and the curve's direction there (any length > 0).
struct TangentLine {
    glm::dvec2 point;
    glm::dvec2 direction;
};

// Closed polygon whose vertex i is the intersection of tangent lines i and i+1. Throws
// std::invalid_argument for fewer than 3 lines or two consecutive parallel lines.
Polyline2 polygonFromTangentLines(const std::vector<TangentLine>& lines);

// Least-squares control polygon with `vertexCount` vertices of the closed uniform quadratic
// B-spline (the Chaikin limit, see chaikinLimitPoint) through `points` at the given spline
// parameters u ∈ [0, vertexCount). Exact when the points lie on such a spline at those
// parameters. Throws std::invalid_argument for mismatched sizes, fewer points than vertices,
// vertexCount < 3 or a singular system.
Polyline2 fitChaikinControlPolygon(const Polyline2& points, const std::vector<double>& parameters,
                                   int vertexCount);

// Least-squares inverse Chaikin without known parameters: chord-length parameters, then
// `iterations` Gauss–Newton steps on control points and parameters together (parameters
// eliminated, so each point's error counts along the curve normal). Recovers a polygon exactly
// (to rounding) when the curve is a densely sampled Chaikin limit with that many vertices;
// otherwise it is the quality baseline for inverseChaikin. Point 0 of the curve starts at
// u = 0, i.e. near the midpoint of the first edge. Throws std::invalid_argument for fewer than 8
// points, non-finite values, vertexCount < 3 or more than half the point count.
Polyline2 inverseChaikinLeastSquares(const Polyline2& curve, int vertexCount, int iterations = 20);

// The seed's shape error D/S×100 (percent): D is the area of the symmetric difference of the
// two closed polygons, S the area of their union (even-odd interiors). Computed exactly on
// `scanlines` horizontal lines (midpoint rule in y), so it is exact for shapes whose interval
// lengths are linear in y between lines. Throws std::invalid_argument for polygons with fewer
// than 3 points, non-finite values, or scanlines < 1.
double differentialAreaError(const Polyline2& a, const Polyline2& b, int scanlines = 4000);

// Number of curvature sign changes around the closed curve, after resampling to
// `resampleCount` points and ignoring wiggles whose turning stays below a small threshold.
int countInflections(const Polyline2& curve, int resampleCount = 1024);

}  // namespace vsculpt::sketch
