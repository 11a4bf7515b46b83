// Log-aesthetic (LA) curves: planar curves whose curvature logarithmic distribution graph is a
// straight line of slope α, and space curves whose torsion graph is also straight (slope β).
// Units: mm, 1/mm, radians.
//
// Law (Miura; normalisation of Yoshida & Saito): with ŝ = s·|κ0| the arc length in units of the
// start radius of curvature, the curvature relative to its start value is
//   κ̂(ŝ) = (Λ·α·ŝ + 1)^(−1/α)  (α ≠ 0),   κ̂(ŝ) = e^(−Λ·ŝ)  (α = 0),
// and the turning angle T̂(ŝ) = ∫₀^ŝ κ̂ has the closed forms
//   ((Λαŝ + 1)^((α−1)/α) − 1) / (Λ(α−1)),   ln(Λŝ + 1)/Λ (α = 1),   (1 − e^(−Λŝ))/Λ (α = 0),
// and T̂ = ŝ for Λ = 0 (a circle, the α = ±∞ member). They are evaluated through log1p/expm1, so
// values near α = 0, α = 1 and Λ = 0 are continuous and accurate. Λ > 0: the radius grows along
// the curve; Λ < 0: it shrinks, and for α·Λ < 0 the curve ends at ŝ = −1/(Λα) where κ → ∞.
// Members: α = −1 clothoid, 0 Nielsen spiral, 1 logarithmic spiral, 2 circle involute.
// Torsion of space curves follows the same law with (β, Ω, τ0): τ(s) = τ0·κ̂_{β,Ω}(s·|τ0|).
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <functional>
#include <vector>

namespace vsculpt::sketch {

// κ̂(ŝ) and T̂(ŝ) above (dimensionless). Outside the domain (Λαŝ + 1 ≤ 0) they return +∞.
double laRelativeCurvature(double alpha, double lambda, double normalizedArcLength);
double laTurningAngle(double alpha, double lambda, double normalizedArcLength);
// Largest normalised length −1/(Λα) for αΛ < 0, else +∞.
double laDomainLength(double alpha, double lambda);
// Λ for which the curvature falls from κ0 to κ0/radiusRatio over normalised length ŝ1 (i.e.
// ρ(end)/ρ(0) = radiusRatio > 0). Always inside the domain.
double laLambdaForRadiusRatio(double alpha, double radiusRatio, double normalizedLength);

struct LaPlanarParams {
    double alpha = 0.0;
    double lambda = 0.0;          // Λ (dimensionless)
    double startCurvature = 0.0;  // κ0, 1/mm, ≠ 0; positive turns counter-clockwise
    double length = 0.0;          // mm, > 0
    glm::dvec2 start{0.0};        // mm
    double startAngle = 0.0;      // tangent direction at the start, radians from +x
};

struct LaPlanarCurve {
    Polyline2 points;                  // mm
    std::vector<double> arcLength;     // mm, equally spaced from 0 to length
    std::vector<double> curvature;     // signed, 1/mm (exact law, not estimated)
    std::vector<double> tangentAngle;  // radians
};

// Samples the curve at `samples` points equally spaced in arc length. The tangent angle is the
// closed form; positions integrate (cos θ, sin θ) by 8-point Gauss–Legendre on pieces bisected
// until each turns by at most 0.1 rad and its curvature changes by less than a factor 1.5
// (relative position error ~1e-13 of the length). Throws std::invalid_argument on non-finite
// parameters, κ0 = 0, length ≤ 0, samples < 2, or a length past the domain end.
LaPlanarCurve laPlanarCurve(const LaPlanarParams& params, int samples);

// A sampled space curve with its Frenet frame; the Frenet frame columns stay orthonormal.
struct SpaceCurveSamples {
    Polyline3 points;
    std::vector<double> arcLength;  // mm
    std::vector<double> curvature;  // 1/mm
    std::vector<double> torsion;    // 1/mm
    std::vector<glm::dvec3> tangent, normal, binormal;
};

struct FrenetStart {
    glm::dvec3 point{0.0};
    glm::dvec3 tangent{1.0, 0.0, 0.0};
    glm::dvec3 normal{0.0, 1.0, 0.0};  // made orthogonal to tangent; binormal = t × n
};

// Integrates the Frenet–Serret equations t′ = κn, n′ = −κt + τb, b′ = −τn from `start` over
// `length` mm. The frame advances by the fourth-order Magnus (Lie-group) step
//   F ← F·exp([h/2(ω1 + ω2) + (√3/12)h²(ω1 × ω2)]×),  ω = (τ, 0, κ) in the body frame,
// (ω1, ω2 at the two Gauss points) with Rodrigues' formula, which keeps F a rotation; rounding
// drift is removed by re-orthonormalising each step. Positions use Simpson's rule on the tangent.
// Output: `samples` points equally spaced in arc length, `substeps` steps between samples.
// Throws std::invalid_argument for a degenerate start frame, length ≤ 0, samples < 2,
// substeps < 1, or non-finite κ or τ values.
SpaceCurveSamples integrateFrenet(const FrenetStart& start, double length,
                                  const std::function<double(double)>& curvature,
                                  const std::function<double(double)>& torsion, int samples,
                                  int substeps = 4);

struct LaSpaceParams {
    double alpha = 0.0;
    double lambda = 0.0;
    double startCurvature = 0.0;  // κ0 > 0, 1/mm
    double beta = 0.0;
    double omega = 0.0;         // Ω, the torsion counterpart of Λ
    double startTorsion = 0.0;  // τ0, 1/mm, signed; 0 gives a planar LA curve
    double length = 0.0;        // mm
    FrenetStart start;
};

// Space LA curve: κ(s) = κ0·κ̂_{α,Λ}(s·κ0), τ(s) = τ0·κ̂_{β,Ω}(s·|τ0|), integrated with
// integrateFrenet. Throws std::invalid_argument as laPlanarCurve, and for κ0 ≤ 0 or a length
// past the torsion law's domain.
SpaceCurveSamples laSpaceCurve(const LaSpaceParams& params, int samples, int substeps = 4);

}  // namespace vsculpt::sketch
