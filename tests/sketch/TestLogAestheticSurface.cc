#include "vsculpt/sketch/LogAestheticCurve.h"
#include "vsculpt/sketch/LogAestheticGraph.h"
#include "vsculpt/sketch/LogAestheticSurface.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

constexpr double kHelixA = 200.0, kHelixB = 40.0;
constexpr double kHelixT = 0.5;  // parameter range of the guide helix

Polyline3 guideHelix(int n) {
    Polyline3 pts;
    for (int i = 0; i < n; ++i) {
        const double t = kHelixT * i / (n - 1);
        pts.push_back({kHelixA * std::cos(t), kHelixA * std::sin(t), kHelixB * t});
    }
    return pts;
}

LaSpaceParams baseParams(double alpha, double k0, double ratio, double beta, double t0) {
    LaSpaceParams p;
    p.alpha = alpha;
    p.startCurvature = k0;
    p.length = 80.0;
    p.lambda = laLambdaForRadiusRatio(alpha, ratio, p.length * k0);
    p.beta = beta;
    p.startTorsion = t0;
    if (t0 != 0.0) p.omega = laLambdaForRadiusRatio(beta, 2.0, p.length * std::abs(t0));
    return p;
}

TEST(LaSurface, ReproducesBaseLinesAndFrameConditions) {
    LaSpaceParams p1 = baseParams(0.5, 0.02, 3.0, 1.0, 0.005);
    LaSpaceParams p2 = baseParams(-1.0, 0.03, 2.0, 0.5, 0.008);
    const IntrinsicCurve b1 = intrinsicCurve(laSpaceCurve(p1, 401));
    const IntrinsicCurve b2 = intrinsicCurve(laSpaceCurve(p2, 401));
    LaSurfaceParams sp;
    sp.uSamples = 11;
    sp.vSamples = 41;
    const LaSurface s = laSurface(guideHelix(2001), b1, b2, sp);
    ASSERT_EQ(s.mesh.vertices.size(), 11u * 41u);
    ASSERT_EQ(s.mesh.faces.size(), 10u * 40u);

    const double c = std::hypot(kHelixA, kHelixB);
    for (int i = 0; i < sp.uSamples; ++i) {
        // Analytic Frenet frame of the guide helix at this u: the section must leave along the
        // guide's binormal with the guide's normal (paper 002, Fig. 4 conditions).
        const double t = kHelixT * i / (sp.uSamples - 1);
        const glm::dvec3 n(-std::cos(t), -std::sin(t), 0.0);
        const glm::dvec3 b(kHelixB * std::sin(t) / c, -kHelixB * std::cos(t) / c, kHelixA / c);
        const SpaceCurveSamples& sec = s.sections[std::size_t(i)];
        EXPECT_NEAR(glm::dot(sec.tangent[0], b), 1.0, 1e-9) << i;
        EXPECT_NEAR(glm::dot(sec.normal[0], n), 1.0, 1e-9) << i;
        EXPECT_LT(glm::distance(sec.points[0], glm::dvec3(kHelixA * std::cos(t),
                                                          kHelixA * std::sin(t), kHelixB * t)),
                  1e-9 * c);
    }
    // u = 0 and u = 1 are the base lines themselves, generated from their own laws.
    for (int end = 0; end < 2; ++end) {
        LaSpaceParams p = end == 0 ? p1 : p2;
        const SpaceCurveSamples& sec = end == 0 ? s.sections.front() : s.sections.back();
        p.start = {sec.points[0], sec.tangent[0], sec.normal[0]};
        const SpaceCurveSamples ref = laSpaceCurve(p, sp.vSamples, 40);
        for (std::size_t j = 0; j < ref.points.size(); ++j)
            EXPECT_LT(glm::distance(sec.points[j], ref.points[j]), 1e-6 * p.length) << end << j;
    }
    EXPECT_EQ(s.fallbackSamples, 0);
}

TEST(LaSurface, CurvatureAlongControlLineHasSlopeGamma) {
    const IntrinsicCurve b1 = intrinsicCurve(laSpaceCurve(baseParams(1.0, 0.01, 2.0, 0, 0), 101));
    const IntrinsicCurve b2 = intrinsicCurve(laSpaceCurve(baseParams(1.0, 0.08, 2.0, 0, 0), 101));
    for (double gamma : {-1.0, 0.0, 0.5, 2.0}) {
        LaSurfaceParams sp;
        sp.gammaCurvature = gamma;
        sp.uSamples = 201;
        sp.vSamples = 5;
        const LaSurface s = laSurface(guideHelix(401), b1, b2, sp);
        for (int j = 0; j < sp.vSamples; ++j) {
            // Along the CLDCT (fixed v) with arc length ∝ u, the γ graph is a line of slope γ.
            std::vector<double> arc, radius;
            for (int i = 0; i < sp.uSamples; ++i) {
                arc.push_back(double(i) / (sp.uSamples - 1));
                radius.push_back(1.0 / s.sections[std::size_t(i)].curvature[std::size_t(j)]);
            }
            const LogDistributionGraph graph = logDistributionGraph(arc, radius);
            EXPECT_NEAR(graph.slope, gamma, 0.02) << "gamma " << gamma << " v " << j;
        }
    }
}

TEST(LaSurface, EqualBaseLinesOnAStraightGuideSweepCongruentSections) {
    const IntrinsicCurve base =
        intrinsicCurve(laSpaceCurve(baseParams(0.0, 0.02, 4.0, 1, 0.01), 81));
    const Polyline3 straight{{0, 0, 0}, {25, 0, 0}, {50, 0, 0}, {75, 0, 0}, {100, 0, 0}};
    LaSurfaceParams sp;
    EXPECT_THROW(laSurface(straight, base, base, sp), std::invalid_argument);
    sp.useReferenceNormal = true;
    sp.referenceNormal = {0.0, 0.3, 1.0};
    const LaSurface s = laSurface(straight, base, base, sp);
    for (int i = 0; i < sp.uSamples; ++i) {
        EXPECT_NEAR(s.mesh.vertices[std::size_t(i * sp.vSamples)].x, 100.0 * i / (sp.uSamples - 1),
                    1e-9);
        for (int j = 0; j < sp.vSamples; ++j) {
            const glm::dvec3 offset = s.mesh.vertices[std::size_t(i * sp.vSamples + j)] -
                                      s.mesh.vertices[std::size_t(i * sp.vSamples)];
            const glm::dvec3 first = s.mesh.vertices[std::size_t(j)] - s.mesh.vertices[0];
            EXPECT_LT(glm::distance(offset, first), 1e-12 * 100.0) << i << " " << j;
        }
    }
    EXPECT_NEAR(glm::dot(s.guideNormal[0], glm::normalize(glm::dvec3(0, 0.3, 1))), 1.0, 1e-12);
}

TEST(LaSurface, MeshIsFiniteAndNotFolded) {
    const IntrinsicCurve b1 = intrinsicCurve(laSpaceCurve(baseParams(0.5, 0.02, 3.0, 1, 0.0), 201));
    const IntrinsicCurve b2 =
        intrinsicCurve(laSpaceCurve(baseParams(2.0, 0.03, 2.0, 1, 0.01), 201));
    LaSurfaceParams sp;
    sp.gammaCurvature = 0.5;
    sp.gammaTorsion = -1.0;
    const LaSurface s = laSurface(guideHelix(501), b1, b2, sp);
    // Base line 1 is planar (τ = 0) and base line 2 is not: the torsion law falls back on every
    // section strictly between them.
    EXPECT_EQ(s.fallbackSamples, (sp.uSamples - 2) * sp.vSamples);
    for (const glm::dvec3& v : s.mesh.vertices)
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
    auto normalOf = [&](const std::vector<int>& f) {
        const auto& v = s.mesh.vertices;
        return glm::normalize(glm::cross(v[std::size_t(f[2])] - v[std::size_t(f[0])],
                                         v[std::size_t(f[3])] - v[std::size_t(f[1])]));
    };
    const int cols = sp.vSamples - 1;
    for (std::size_t f = 0; f < s.mesh.faces.size(); ++f) {
        const glm::dvec3 nf = normalOf(s.mesh.faces[f]);
        if ((f + 1) % std::size_t(cols) != 0) {
            EXPECT_GT(glm::dot(nf, normalOf(s.mesh.faces[f + 1])), 0.9) << f;
        }
        if (f + std::size_t(cols) < s.mesh.faces.size()) {
            EXPECT_GT(glm::dot(nf, normalOf(s.mesh.faces[f + std::size_t(cols)])), 0.9) << f;
        }
    }
}

TEST(LaSurface, InterpolationLawAndFallback) {
    // γ = 1: radius linear in w; γ = −1: curvature linear; γ = 0: geometric mean of radii.
    EXPECT_NEAR(laInterpolate(0.5, 0.25, 0.5, 1.0), 1.0 / 3.0, 1e-15);
    EXPECT_NEAR(laInterpolate(0.5, 0.25, 0.5, -1.0), 0.375, 1e-15);
    EXPECT_NEAR(laInterpolate(-0.5, -0.125, 0.5, 0.0), -0.25, 1e-15);
    bool fallback = false;
    EXPECT_NEAR(laInterpolate(-0.2, 0.2, 0.25, 2.0, &fallback), -0.1, 1e-15);
    EXPECT_TRUE(fallback);
    EXPECT_NEAR(laInterpolate(0.3, 0.1, 1.0, 2.0, &fallback), 0.1, 1e-15);
    EXPECT_FALSE(fallback);
}

TEST(LaSurface, RefusesBadInput) {
    const IntrinsicCurve good{50.0, {0.01, 0.02, 0.03}, {0.0, 0.0, 0.0}};
    const Polyline3 guide = guideHelix(50);
    IntrinsicCurve bad = good;
    bad.length = 0.0;
    EXPECT_THROW(laSurface(guide, bad, good), std::invalid_argument);
    bad = good;
    bad.torsion.pop_back();
    EXPECT_THROW(laSurface(guide, good, bad), std::invalid_argument);
    bad = good;
    bad.curvature[1] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(laSurface(guide, good, bad), std::invalid_argument);
    LaSurfaceParams sp;
    sp.gammaTorsion = std::numeric_limits<double>::infinity();
    EXPECT_THROW(laSurface(guide, good, good, sp), std::invalid_argument);
    EXPECT_THROW(laSurface(Polyline3{{0, 0, 0}, {1, 1, 1}}, good, good), std::invalid_argument);
    sp = {};
    sp.useReferenceNormal = true;
    sp.referenceNormal = {1.0, 0.0, 0.0};
    EXPECT_THROW(laSurface(Polyline3{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, good, good, sp),
                 std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
