// Curvature and torsion of sampled curves (pen strokes, generated log-aesthetic curves).
// Units: positions in mm, arc length in mm, curvature and torsion in 1/mm.
//
// Discretisation: at every sample i a polynomial of degree min(3, window − 1) is fitted by least
// squares to each coordinate over the 2·halfWindow + 1 neighbouring samples (the window is
// shifted inwards at the ends so it always holds that many points), parameterised by cumulative
// chord length centred on sample i. Its derivatives at sample i give
//   κ = |r′ × r″| / |r′|³,   τ = (r′ × r″) · r‴ / |r′ × r″|²,
// which do not depend on the parameterisation, so chord length (≈ arc length) is enough. On
// exact samples the error is O(h²) in the spacing h; a wider window smooths noisy strokes at the
// price of bias on sharply bending parts. A three-point polyline gets a quadratic fit (τ = 0).
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <glm/vec3.hpp>

#include <vector>

namespace vsculpt::sketch {

// Per-sample differential geometry of a sampled curve. All vectors have one entry per input
// point. For 2D input, curvature is signed (positive turning counter-clockwise) and torsion is 0.
// For 3D input curvature is ≥ 0; tangent/normal/binormal form the Frenet frame (normal and
// binormal are zero where κ is below 1e-12·(1/length)).
struct CurveDifferential {
    std::vector<double> arcLength;  // cumulative chord length from the first point (mm)
    std::vector<double> curvature;  // 1/mm
    std::vector<double> torsion;    // 1/mm
    std::vector<glm::dvec3> tangent;
    std::vector<glm::dvec3> normal;
    std::vector<glm::dvec3> binormal;
};

// Throws std::invalid_argument for fewer than 3 points, a non-finite coordinate, a repeated
// consecutive point (zero-length segment) or halfWindow < 1.
CurveDifferential curveDifferential(const Polyline2& line, int halfWindow = 2);
CurveDifferential curveDifferential(const Polyline3& line, int halfWindow = 2);

// Resampling a polyline at a number of points: resampleByCount in Polyline.h.

}  // namespace vsculpt::sketch
