#include "vsculpt/sketch/CurveCurvature.h"
#include "vsculpt/sketch/LogAestheticCurve.h"
#include "vsculpt/sketch/LogAestheticGraph.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = 3.14159265358979323846;

Polyline3 helix(double a, double b, double turns, int n) {
    Polyline3 pts;
    for (int i = 0; i < n; ++i) {
        const double t = 2.0 * kPi * turns * i / (n - 1);
        pts.push_back({a * std::cos(t), a * std::sin(t), b * t});
    }
    return pts;
}

// ∫₀ˣ cos t² dt and ∫₀ˣ sin t² dt by their power series (accurate to ~1e-14 for |x| < 2.5).
double fresnelC(double x) {
    double sum = 0.0, term = x;  // (−1)^n x^(4n+1) / (2n)!
    for (int n = 0; n < 40; ++n) {
        sum += term / (4 * n + 1);
        term *= -x * x * x * x / ((2 * n + 1) * (2 * n + 2));
    }
    return sum;
}
double fresnelS(double x) {
    double sum = 0.0, term = x * x * x;  // (−1)^n x^(4n+3) / (2n+1)!
    for (int n = 0; n < 40; ++n) {
        sum += term / (4 * n + 3);
        term *= -x * x * x * x / ((2 * n + 2) * (2 * n + 3));
    }
    return sum;
}

LaPlanarParams planarWithRatio(double alpha, double k0, double length, double radiusRatio) {
    LaPlanarParams p;
    p.alpha = alpha;
    p.startCurvature = k0;
    p.length = length;
    p.lambda = laLambdaForRadiusRatio(alpha, radiusRatio, length * std::abs(k0));
    return p;
}

// The documented discretisation error is O(h²): relative error within (h/R)² inside the curve
// and 4(h/R)² at the shifted end windows, R the smallest radius of curvature.
double relativeBound(std::size_t i, std::size_t n, double hOverR) {
    return (i < 2 || i + 2 >= n ? 4.0 : 1.0) * hOverR * hOverR;
}

TEST(CurveCurvature, HelixCurvatureAndTorsion) {
    const double a = 20.0, b = 5.0;
    const double c2 = a * a + b * b;
    const int n = 2001;
    const CurveDifferential d = curveDifferential(helix(a, b, 2.0, n));
    const double hOverR = (4.0 * kPi * std::sqrt(c2) / (n - 1)) / std::sqrt(c2);
    for (std::size_t i = 0; i < d.curvature.size(); ++i) {
        const double tol = relativeBound(i, d.curvature.size(), hOverR);
        EXPECT_NEAR(d.curvature[i], a / c2, tol * a / c2) << i;
        EXPECT_NEAR(d.torsion[i], b / c2, tol * b / c2) << i;
        EXPECT_NEAR(glm::dot(d.tangent[i], d.normal[i]), 0.0, 1e-12);
        EXPECT_NEAR(glm::length(d.binormal[i]), 1.0, 1e-12);
    }
}

TEST(CurveCurvature, PlanarCircleIsSignedAndHasNoTorsion) {
    Polyline2 ccw;
    for (int i = 0; i < 50; ++i)
        ccw.push_back({7.0 * std::cos(0.05 * i), 7.0 * std::sin(0.05 * i)});
    const double hOverR = 0.05;
    const CurveDifferential d = curveDifferential(ccw);
    for (std::size_t i = 0; i < d.curvature.size(); ++i)
        EXPECT_NEAR(d.curvature[i], 1.0 / 7.0, relativeBound(i, 50, hOverR) / 7.0);
    const Polyline2 cw(ccw.rbegin(), ccw.rend());
    const CurveDifferential r = curveDifferential(cw);
    for (std::size_t i = 0; i < r.curvature.size(); ++i)
        EXPECT_NEAR(r.curvature[i], -1.0 / 7.0, relativeBound(i, 50, hOverR) / 7.0);
    Polyline3 flat;
    for (const auto& p : ccw)
        flat.push_back({p.x, 2.0, p.y});
    for (double t : curveDifferential(flat).torsion)
        EXPECT_NEAR(t, 0.0, 1e-9);
}

TEST(CurveCurvature, RefusesBadInput) {
    EXPECT_THROW(curveDifferential(Polyline2{{0, 0}, {1, 0}}), std::invalid_argument);
    EXPECT_THROW(curveDifferential(Polyline2{{0, 0}, {0, 0}, {0, 0}}), std::invalid_argument);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(curveDifferential(Polyline3{{0, 0, 0}, {1, nan, 0}, {2, 0, 0}}),
                 std::invalid_argument);
    EXPECT_THROW(curveDifferential(Polyline2{{0, 0}, {1, 0}, {2, 1}}, 0), std::invalid_argument);
    EXPECT_THROW(curvatureGraph(Polyline2{{0, 0}, {1, 0}}), std::invalid_argument);
    EXPECT_THROW(resampleByCount(Polyline2{{1, 1}, {1, 1}, {1, 1}}, 10), std::invalid_argument);
}

TEST(LogGraph, SlopeOfGeneratedPlanarCurves) {
    for (double alpha : {-1.0, 0.0, 1.0, 2.0, 0.5, -2.0}) {
        const LaPlanarCurve c = laPlanarCurve(planarWithRatio(alpha, 0.1, 100.0, 10.0), 1001);
        const LogDistributionGraph fromPoints = curvatureGraph(c.points);
        EXPECT_NEAR(fromPoints.slope, alpha, 0.02) << "alpha " << alpha;
        // R² means nothing for a flat line (α = 0): there is no variance to explain.
        if (alpha != 0.0) {
            EXPECT_GT(fromPoints.rSquared, 0.999) << "alpha " << alpha;
        }
        std::vector<double> radius;
        for (double k : c.curvature)
            radius.push_back(1.0 / std::abs(k));
        EXPECT_NEAR(logDistributionGraph(c.arcLength, radius).slope, alpha, 0.005);
    }
}

TEST(LogGraph, TorsionSlopeOfGeneratedSpaceCurves) {
    for (double beta : {-1.0, 0.0, 1.0, 2.0}) {
        LaSpaceParams p;
        p.alpha = 0.5;
        p.startCurvature = 0.05;
        p.lambda = laLambdaForRadiusRatio(p.alpha, 4.0, 100.0 * p.startCurvature);
        p.beta = beta;
        p.startTorsion = 0.04;
        p.omega = laLambdaForRadiusRatio(beta, 8.0, 100.0 * p.startTorsion);
        p.length = 100.0;
        const SpaceCurveSamples c = laSpaceCurve(p, 2001);
        EXPECT_NEAR(torsionGraph(c.points, {}, 3).slope, beta, 0.02) << "beta " << beta;
        EXPECT_NEAR(curvatureGraph(c.points, {}, 3).slope, 0.5, 0.02) << "beta " << beta;
    }
}

TEST(LogGraph, ConstantCurvatureIsRefused) {
    LaPlanarParams p;
    p.startCurvature = 0.1;
    p.length = 20.0;
    const LaPlanarCurve c = laPlanarCurve(p, 200);
    EXPECT_THROW(curvatureGraph(c.points), std::invalid_argument);
}

TEST(LaPlanar, CircleWhenLambdaIsZero) {
    LaPlanarParams p;
    p.alpha = 1.0;
    p.startCurvature = 1.0 / 30.0;
    p.length = 150.0;
    const LaPlanarCurve c = laPlanarCurve(p, 101);
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        const double s = c.arcLength[i];
        EXPECT_NEAR(c.points[i].x, 30.0 * std::sin(s / 30.0), 1e-10);
        EXPECT_NEAR(c.points[i].y, 30.0 * (1.0 - std::cos(s / 30.0)), 1e-10);
    }
}

TEST(LaPlanar, ClothoidMatchesFresnelIntegrals) {
    // α = −1: κ(s) = κ0 + c·s; here κ rises from 0.01 to 0.05 over 100 mm.
    const double k0 = 0.01, c = 0.0004, length = 100.0;
    LaPlanarParams p;
    p.alpha = -1.0;
    p.startCurvature = k0;
    p.lambda = -c / (k0 * k0);
    p.length = length;
    const LaPlanarCurve curve = laPlanarCurve(p, 51);
    const double a = std::sqrt(c / 2.0), phi0 = k0 * k0 / (2.0 * c);
    const double u0 = a * k0 / c;
    for (std::size_t i = 0; i < curve.points.size(); ++i) {
        const double s = curve.arcLength[i];
        const double u1 = a * (s + k0 / c);
        const double dc = fresnelC(u1) - fresnelC(u0), ds = fresnelS(u1) - fresnelS(u0);
        const double x = (std::cos(phi0) * dc + std::sin(phi0) * ds) / a;
        const double y = (std::cos(phi0) * ds - std::sin(phi0) * dc) / a;
        EXPECT_NEAR(curve.points[i].x, x, 1e-9 * length) << s;
        EXPECT_NEAR(curve.points[i].y, y, 1e-9 * length) << s;
        EXPECT_NEAR(curve.curvature[i], k0 + c * s, 1e-14);
    }
}

TEST(LaPlanar, LogarithmicSpiralAndCircleInvolute) {
    for (double lambda : {0.3, -0.05}) {
        // α = 1, start radius 1 mm (normalised units): a logarithmic spiral.
        LaPlanarParams p;
        p.alpha = 1.0;
        p.lambda = lambda;
        p.startCurvature = 1.0;
        p.length = 12.0;
        const LaPlanarCurve c = laPlanarCurve(p, 61);
        for (std::size_t i = 0; i < c.points.size(); ++i) {
            const double th = std::log1p(lambda * c.arcLength[i]) / lambda;
            const double e = std::exp(lambda * th), d = 1.0 + lambda * lambda;
            EXPECT_NEAR(c.tangentAngle[i], th, 1e-13);
            EXPECT_NEAR(c.points[i].x, (e * (lambda * std::cos(th) + std::sin(th)) - lambda) / d,
                        1e-11);
            EXPECT_NEAR(c.points[i].y, (e * (lambda * std::sin(th) - std::cos(th)) + 1.0) / d,
                        1e-11);
        }
        // α = 2: a circle involute.
        p.alpha = 2.0;
        p.length = 6.0;
        const LaPlanarCurve inv = laPlanarCurve(p, 61);
        for (std::size_t i = 0; i < inv.points.size(); ++i) {
            const double th = (std::sqrt(2.0 * lambda * inv.arcLength[i] + 1.0) - 1.0) / lambda;
            const double q = lambda * th + 1.0;
            EXPECT_NEAR(inv.points[i].x, q * std::sin(th) + lambda * std::cos(th) - lambda, 1e-11);
            EXPECT_NEAR(inv.points[i].y, -q * std::cos(th) + lambda * std::sin(th) + 1.0, 1e-11);
        }
    }
}

TEST(LaPlanar, SpecialCasesAreContinuousInAlpha) {
    // The closed forms at α = 0 and α = 1 must agree with the general form just beside them.
    for (double s : {0.5, 3.0, 9.0}) {
        for (double lambda : {0.4, -0.02}) {
            EXPECT_NEAR(laTurningAngle(0.0, lambda, s), laTurningAngle(1e-7, lambda, s), 1e-6);
            EXPECT_NEAR(laTurningAngle(1.0, lambda, s), laTurningAngle(1.0 + 1e-7, lambda, s),
                        1e-6);
            EXPECT_NEAR(laRelativeCurvature(0.0, lambda, s), laRelativeCurvature(-1e-7, lambda, s),
                        1e-6);
        }
        EXPECT_NEAR(laTurningAngle(0.7, 1e-12, s), s, 1e-9);
    }
}

TEST(LaPlanar, CurvatureIsMonotoneAndDomainIsEnforced) {
    const LaPlanarCurve c = laPlanarCurve(planarWithRatio(0.0, -0.2, 50.0, 5.0), 200);
    for (std::size_t i = 1; i < c.curvature.size(); ++i)
        EXPECT_GT(c.curvature[i], c.curvature[i - 1]);  // negative and shrinking in magnitude
    LaPlanarParams p;
    p.alpha = 1.0;
    p.lambda = -0.1;  // ρ = 1 − 0.1ŝ reaches 0 at ŝ = 10
    p.startCurvature = 1.0;
    p.length = 10.0;
    EXPECT_THROW(laPlanarCurve(p, 10), std::invalid_argument);
    p.length = 9.9;
    EXPECT_NO_THROW(laPlanarCurve(p, 10));
    p.startCurvature = 0.0;
    EXPECT_THROW(laPlanarCurve(p, 10), std::invalid_argument);
    p.startCurvature = 1.0;
    p.alpha = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(laPlanarCurve(p, 10), std::invalid_argument);
}

TEST(LaSpace, FramesStayOrthonormal) {
    LaSpaceParams p;
    p.alpha = -0.5;
    p.lambda = -0.01;
    p.startCurvature = 0.2;
    p.beta = 1.5;
    p.omega = 0.05;
    p.startTorsion = -0.1;
    p.length = 400.0;
    p.start.tangent = {0.0, 0.0, 2.0};
    p.start.normal = {1.0, 0.0, 1.0};
    const SpaceCurveSamples c = laSpaceCurve(p, 20001, 1);
    double worst = 0.0;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        const glm::dvec3 &t = c.tangent[i], &n = c.normal[i], &b = c.binormal[i];
        for (double v : {glm::dot(t, t) - 1.0, glm::dot(n, n) - 1.0, glm::dot(b, b) - 1.0,
                         glm::dot(t, n), glm::dot(t, b), glm::dot(n, b)})
            worst = std::max(worst, std::abs(v));
        worst = std::max(worst, glm::length(glm::cross(t, n) - b));
    }
    EXPECT_LT(worst, 1e-12);
    EXPECT_NEAR(glm::dot(c.normal[0], glm::dvec3(1, 0, 0)), 1.0, 1e-15);
}

TEST(LaSpace, ConstantCurvatureAndTorsionIsAHelix) {
    const double a = 20.0, b = 5.0, c2 = a * a + b * b, c = std::sqrt(c2);
    LaSpaceParams p;
    p.startCurvature = a / c2;
    p.startTorsion = b / c2;
    p.length = 4.0 * kPi * c;
    p.start.point = {a, 0.0, 0.0};
    p.start.tangent = {0.0, a, b};
    p.start.normal = {-1.0, 0.0, 0.0};
    const SpaceCurveSamples h = laSpaceCurve(p, 201, 8);
    for (std::size_t i = 0; i < h.points.size(); ++i) {
        const double t = h.arcLength[i] / c;
        const glm::dvec3 expected(a * std::cos(t), a * std::sin(t), b * t);
        EXPECT_LT(glm::distance(h.points[i], expected), 1e-8 * p.length) << i;
    }
}

TEST(LaSpace, ZeroTorsionReproducesThePlanarCurve) {
    const LaPlanarParams planar = planarWithRatio(0.7, 0.08, 120.0, 6.0);
    const LaPlanarCurve flat = laPlanarCurve(planar, 121);
    LaSpaceParams p;
    p.alpha = planar.alpha;
    p.lambda = planar.lambda;
    p.startCurvature = planar.startCurvature;
    p.length = planar.length;
    const SpaceCurveSamples c = laSpaceCurve(p, 121, 8);
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        EXPECT_LT(glm::distance(c.points[i], glm::dvec3(flat.points[i], 0.0)), 1e-8 * p.length);
        EXPECT_EQ(c.torsion[i], 0.0);
    }
}

TEST(LaSpace, RefusesBadParameters) {
    LaSpaceParams p;
    p.startCurvature = 0.1;
    p.length = 10.0;
    p.start.normal = {2.0, 0.0, 0.0};  // parallel to the tangent
    EXPECT_THROW(laSpaceCurve(p, 10), std::invalid_argument);
    p.start.normal = {0.0, 1.0, 0.0};
    p.startCurvature = -0.1;
    EXPECT_THROW(laSpaceCurve(p, 10), std::invalid_argument);
    p.startCurvature = 0.1;
    p.startTorsion = std::numeric_limits<double>::infinity();
    EXPECT_THROW(laSpaceCurve(p, 10), std::invalid_argument);
    p.startTorsion = 0.1;
    p.beta = 1.0;
    p.omega = -1.0;  // torsion radius reaches 0 at s = 10 mm
    EXPECT_THROW(laSpaceCurve(p, 10), std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
