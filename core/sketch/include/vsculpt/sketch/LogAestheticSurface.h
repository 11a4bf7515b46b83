// Log-aesthetic surface from one guide line and two base lines (paper 002, §3; Hagihara et al.).
// Units: mm, 1/mm.
//
// Construction: the guide line C_g(u), u ∈ [0, 1] by normalised arc length, carries a frame
// (t_g, n_g, b_g). For each u a section C_u(v) starts at C_g(u) with tangent b_g(u) and normal
// n_g(u) (the paper's frame conditions: base line 1 is C_0, base line 2 is C_1). The section's
// curvature and torsion move from base line 1's to base line 2's (at the same normalised arc
// length v) along the curvature–torsion distribution control line CLDCT (the iso-v line) by the
// log-aesthetic law with slope γ:
//   ρ_u(v)^γ = (1 − w)·ρ_1(v)^γ + w·ρ_2(v)^γ   (γ ≠ 0),   ρ_u = ρ_1^(1−w)·ρ_2^w   (γ = 0),
// ρ = 1/κ (γ = γ_c) or 1/|τ| (γ = γ_t), with w = u. So κ_u along the CLDCT has a straight γ
// graph of slope γ whenever arc length along the CLDCT is proportional to u (the paper's S(v) ∝
// |C_b1(v) − C_b2(v)| normalisation cancels then); it is exactly so for a straight guide with
// congruent ends. Where the two values differ in sign or one is zero the law has no meaning and
// linear interpolation is used instead (counted in fallbackSamples). The section length goes
// linearly from base line 1's to base line 2's (the paper gives both the same length). Each
// section is integrated with integrateFrenet; base-line curvature and torsion are read between
// their samples by Catmull–Rom interpolation.
#pragma once

#include "vsculpt/sketch/LogAestheticCurve.h"
#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <glm/vec3.hpp>

#include <vector>

namespace vsculpt::sketch {

// Curvature and torsion of a curve at equally spaced arc length (first at 0, last at length).
struct IntrinsicCurve {
    double length = 0.0;            // mm
    std::vector<double> curvature;  // 1/mm
    std::vector<double> torsion;    // 1/mm, same size
};

// From generated samples (laSpaceCurve / integrateFrenet output, equally spaced by design).
IntrinsicCurve intrinsicCurve(const SpaceCurveSamples& curve);
// From a drawn or fitted polyline: resampled at `samples` points, estimated by
// curveDifferential(·, halfWindow). Throws std::invalid_argument as those do.
IntrinsicCurve intrinsicCurve(const Polyline3& curve, int samples, int halfWindow = 2);

// The γ law above for one pair of values a (at w = 0) and b (at w = 1), signed curvatures or
// torsions. Sets *usedFallback when linear interpolation had to be used.
double laInterpolate(double a, double b, double w, double gamma, bool* usedFallback = nullptr);

struct LaSurfaceParams {
    double gammaCurvature = 1.0;  // γ_c
    double gammaTorsion = 1.0;    // γ_t
    int uSamples = 21;            // sections along the guide line, ≥ 2
    int vSamples = 41;            // points along each section, ≥ 2
    // The guide's Frenet normal is undefined where it is straight (the paper's guide lines are
    // nearly straight). With useReferenceNormal, n_g is referenceNormal made orthogonal to t_g
    // instead, and b_g = t_g × n_g.
    bool useReferenceNormal = false;
    glm::dvec3 referenceNormal{0.0, 0.0, 1.0};
    int halfWindow = 2;  // for the guide line's frame estimate
};

struct LaSurface {
    // uSamples × vSamples vertices, (i, j) at index i·vSamples + j, i along the guide; quads
    // (i, j), (i+1, j), (i+1, j+1), (i, j+1), so each face normal is along ∂C/∂u × ∂C/∂v.
    PolyMesh mesh;
    std::vector<SpaceCurveSamples> sections;  // C_u for each u_i, with frames, κ and τ
    std::vector<glm::dvec3> guideTangent, guideNormal, guideBinormal;  // frame at each u_i
    int fallbackSamples = 0;  // grid samples where the γ law fell back to linear interpolation
};

// Throws std::invalid_argument when the guide line is bad (see curveDifferential), a base line
// has fewer than 2 samples, mismatched or non-finite values or length ≤ 0, γ is not finite,
// sample counts are < 2, the reference normal is parallel to the guide, or (without a reference
// normal) the guide line is straight or inflects somewhere (its Frenet normal vanishes or flips).
LaSurface laSurface(const Polyline3& guide, const IntrinsicCurve& base1,
                    const IntrinsicCurve& base2, const LaSurfaceParams& params = {});

}  // namespace vsculpt::sketch
