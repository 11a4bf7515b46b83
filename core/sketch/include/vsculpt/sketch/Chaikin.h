// Chaikin corner cutting on closed polygons: every edge PᵢPᵢ₊₁ is replaced by its ¼ and ¾
// points, so each level doubles the vertex count. The limit is the closed uniform quadratic
// B-spline of the polygon, which touches every edge at its midpoint, tangent to the edge.
// Units are those of the input (mm); the operation is affine-invariant.
#pragma once

#include "vsculpt/sketch/Polyline.h"

namespace vsculpt::sketch {

// `levels` corner-cutting steps on the closed polygon (the last point joins the first).
// Output has polygon.size()·2^levels points; output point 2i of one step is ¾Pᵢ + ¼Pᵢ₊₁ and
// point 2i+1 is ¼Pᵢ + ¾Pᵢ₊₁. Throws std::invalid_argument for fewer than 3 points, a
// non-finite coordinate, or levels outside [0, 20].
Polyline2 chaikin(const Polyline2& polygon, int levels);
Polyline3 chaikin(const Polyline3& polygon, int levels);

// Point of the limit curve (closed uniform quadratic B-spline) of the control polygon at
// parameter u ∈ [0, n): span i = floor(u) blends Pᵢ, Pᵢ₊₁, Pᵢ₊₂ and passes the midpoint of
// PᵢPᵢ₊₁ at u = i, the midpoint of Pᵢ₊₁Pᵢ₊₂ at u = i + 1. u is taken modulo n.
glm::dvec2 chaikinLimitPoint(const Polyline2& polygon, double u);

// The limit curve sampled with `samplesPerEdge` points per control-polygon edge (≥ 1),
// starting at the midpoint of edge P₀P₁.
Polyline2 chaikinLimit(const Polyline2& polygon, int samplesPerEdge);

}  // namespace vsculpt::sketch
