#include "vsculpt/sketch/LogAestheticCurve.h"
#include "vsculpt/sketch/LogAestheticFit.h"
#include "vsculpt/sketch/LogAestheticTwoView.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

double distanceToPolyline(const glm::dvec3& p, const Polyline3& line) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i < line.size(); ++i) {
        const glm::dvec3 a = line[i - 1], d = line[i] - a;
        const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
        best = std::min(best, glm::distance(p, a + t * d));
    }
    return best;
}

// A space LA curve heading along +Y that turns by less than 90°, so both views are monotone in Y.
LaSpaceParams knownSpaceCurve() {
    LaSpaceParams p;
    p.alpha = 0.5;
    p.startCurvature = 0.01;
    p.lambda = laLambdaForRadiusRatio(p.alpha, 3.0, 150.0 * p.startCurvature);
    p.beta = 1.0;
    p.startTorsion = 0.01;
    p.omega = laLambdaForRadiusRatio(p.beta, 2.0, 150.0 * p.startTorsion);
    p.length = 150.0;
    p.start.point = {10.0, -20.0, 5.0};
    p.start.tangent = {0.2, 1.0, 0.1};
    p.start.normal = {1.0, 0.0, 0.0};
    return p;
}

TEST(TwoView, RecombinesAKnownSpaceCurve) {
    const LaSpaceParams p = knownSpaceCurve();
    const Polyline3 truth = laSpaceCurve(p, 3001).points;
    // The two views are drawn at different rates, and the side view runs backwards in Y.
    const Polyline2 top = projectTopView(laSpaceCurve(p, 120).points);
    Polyline2 side = projectSideView(laSpaceCurve(p, 77).points);
    std::reverse(side.begin(), side.end());
    const Polyline3 combined = combineTwoViews(top, side);
    ASSERT_EQ(combined.size(), top.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < combined.size(); ++i) {
        // Inner points keep the top stroke exactly; the overlap ends may be interpolated.
        const double tol = (i == 0 || i + 1 == combined.size()) ? 1e-9 * p.length : 0.0;
        EXPECT_NEAR(combined[i].x, top[i].x, tol);
        EXPECT_NEAR(combined[i].y, top[i].y, tol);
        worst = std::max(worst, distanceToPolyline(combined[i], truth));
    }
    EXPECT_LT(worst, 0.005 * p.length);
    EXPECT_LT(worst, 1e-4 * p.length);  // cubic interpolation of the side view: far inside 0.5 %
    EXPECT_LT(maxDeviation(side, projectSideView(combined)), 1e-4 * p.length);
}

TEST(TwoView, CombinesOnlyTheOverlap) {
    const Polyline2 top{{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}};
    const Polyline2 side{{1.5, 0.0}, {2.5, 1.0}, {3.5, 2.0}, {5.0, 3.5}};  // Z = Y − 1.5
    const Polyline3 c = combineTwoViews(top, side);
    ASSERT_EQ(c.size(), 4u);  // overlap Y ∈ [1.5, 4]: ends added at 1.5 and kept at 4
    EXPECT_DOUBLE_EQ(c.front().y, 1.5);
    EXPECT_NEAR(c.front().x, 1.5, 1e-12);
    EXPECT_DOUBLE_EQ(c.back().y, 4.0);
    for (const glm::dvec3& q : c)
        EXPECT_NEAR(q.z, q.y - 1.5, 1e-12);
}

TEST(TwoView, RefusesAmbiguousOrDisjointStrokes) {
    const Polyline2 top{{0, 0}, {1, 1}, {2, 2}, {3, 3}};
    EXPECT_THROW(combineTwoViews(top, {{0, 0}, {2, 1}, {1, 2}, {3, 3}}), std::invalid_argument);
    EXPECT_THROW(combineTwoViews(top, {{5, 0}, {6, 1}, {7, 2}}), std::invalid_argument);
    EXPECT_THROW(combineTwoViews(top, {{0, 0}, {1, 1}}), std::invalid_argument);
    EXPECT_THROW(
        combineTwoViews({{0, 0}, {1, std::numeric_limits<double>::quiet_NaN()}, {2, 2}}, top),
        std::invalid_argument);
    EXPECT_THROW(combineTwoViews({{0, 0}, {1, 1}, {1, 1}, {2, 2}}, top), std::invalid_argument);
}

LaPlanarParams fitTarget(double alpha, double k0, double k1) {
    LaPlanarParams p;
    p.alpha = alpha;
    p.startCurvature = k0;
    p.length = 100.0;
    p.lambda = laLambdaForRadiusRatio(alpha, k0 / k1, p.length * std::abs(k0));
    p.start = {3.0, 4.0};
    p.startAngle = 0.3;
    return p;
}

TEST(LaFit, RecoversAnExactCurve) {
    for (const LaPlanarParams& truth :
         {fitTarget(0.5, 0.05, 0.01), fitTarget(-1.0, -0.01, -0.06)}) {
        const LaFitResult fit = fitLaPlanarCurve(laPlanarCurve(truth, 300).points);
        EXPECT_NEAR(fit.params.alpha, truth.alpha, 0.02);
        EXPECT_NEAR(fit.params.startCurvature, truth.startCurvature,
                    0.01 * std::abs(truth.startCurvature));
        EXPECT_NEAR(fit.params.startAngle, truth.startAngle, 1e-3);
        EXPECT_LT(glm::distance(fit.params.start, truth.start), 1e-3 * truth.length);
        EXPECT_LT(fit.maxError, 1e-3 * truth.length);
    }
}

TEST(LaFit, NoisyStrokeWithinOnePercent) {
    const LaPlanarParams truth = fitTarget(1.0, 0.06, 0.012);
    Polyline2 stroke = laPlanarCurve(truth, 200).points;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.1, 0.1);  // ±0.1 mm on a 100 mm stroke
    for (glm::dvec2& q : stroke)
        q += glm::dvec2(jitter(rng), jitter(rng));
    const LaFitResult fit = fitLaPlanarCurve(stroke);
    EXPECT_NEAR(fit.params.alpha, truth.alpha, 0.1);
    EXPECT_LT(fit.maxError, 0.01 * truth.length);
    const Polyline2 clean = laPlanarCurve(truth, 200).points;
    EXPECT_LT(maxDeviation(clean, laPlanarCurve(fit.params, 800).points), 0.01 * truth.length);
}

TEST(LaFit, RefusesBadStrokes) {
    EXPECT_THROW(fitLaPlanarCurve({{0, 0}, {1, 1}}), std::invalid_argument);
    EXPECT_THROW(fitLaPlanarCurve({{2, 2}, {2, 2}, {2, 2}, {2, 2}}), std::invalid_argument);
    EXPECT_THROW(fitLaPlanarCurve({{0, 0}, {std::numeric_limits<double>::infinity(), 1}, {2, 0}}),
                 std::invalid_argument);
    LaFitOptions bad;
    bad.samples = 3;
    EXPECT_THROW(fitLaPlanarCurve({{0, 0}, {1, 1}, {2, 0}}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch

namespace vsculpt::sketch {
namespace {

TEST(LaFit, RecoversASpaceCurve) {
    LaSpaceParams truth;
    truth.alpha = 0.5;
    truth.startCurvature = 0.05;
    truth.length = 100.0;
    truth.lambda = laLambdaForRadiusRatio(truth.alpha, 4.0, truth.length * truth.startCurvature);
    truth.beta = 1.0;
    truth.startTorsion = -0.03;
    truth.omega = laLambdaForRadiusRatio(truth.beta, 3.0, truth.length * 0.03);
    truth.start.point = {1.0, 2.0, 3.0};
    truth.start.tangent = {1.0, 0.5, 0.0};
    truth.start.normal = {0.0, 0.0, 1.0};
    const LaSpaceFitResult fit = fitLaSpaceCurve(laSpaceCurve(truth, 300).points);
    EXPECT_NEAR(fit.params.alpha, truth.alpha, 0.1);
    EXPECT_NEAR(fit.params.beta, truth.beta, 0.1);
    EXPECT_LT(fit.params.startTorsion, 0.0);
    EXPECT_LT(fit.maxError, 0.01 * truth.length);
    EXPECT_THROW(fitLaSpaceCurve(Polyline3{{0, 0, 0}, {1, 1, 1}}), std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
