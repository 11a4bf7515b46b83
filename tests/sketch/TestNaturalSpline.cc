#include "vsculpt/sketch/NaturalSpline.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

TEST(NaturalSpline, PassesThroughKnotsOpen) {
    const Polyline2 knots{{0, 0}, {10, 5}, {20, -3}, {27, 8}, {40, 0}};
    const int perSpan = 7;
    const Polyline2 curve = sampleNaturalSpline(knots, false, perSpan);
    ASSERT_EQ(curve.size(), (knots.size() - 1) * perSpan + 1);
    for (std::size_t i = 0; i < knots.size(); ++i) {
        EXPECT_NEAR(curve[i * perSpan].x, knots[i].x, 1e-12);
        EXPECT_NEAR(curve[i * perSpan].y, knots[i].y, 1e-12);
    }
}

TEST(NaturalSpline, PassesThroughKnotsClosed3D) {
    const Polyline3 knots{{0, 0, 0}, {10, 0, 2}, {12, 9, -1}, {1, 11, 4}};
    const int perSpan = 5;
    const Polyline3 curve = sampleNaturalSpline(knots, true, perSpan);
    ASSERT_EQ(curve.size(), knots.size() * perSpan);
    for (std::size_t i = 0; i < knots.size(); ++i)
        EXPECT_LT(glm::distance(curve[i * perSpan], knots[i]), 1e-12);
}

TEST(NaturalSpline, ReproducesStraightLineExactly) {
    // Unequal spacing: chord-length parameters still make the second derivatives vanish.
    const glm::dvec2 a{3, -2}, dir = glm::normalize(glm::dvec2{4, 1});
    const Polyline2 knots{a, a + 1.0 * dir, a + 7.5 * dir, a + 8.0 * dir, a + 20.0 * dir};
    const Polyline2 curve = sampleNaturalSpline(knots, false, 9);
    for (const glm::dvec2& p : curve) {
        const glm::dvec2 d = p - a;
        EXPECT_NEAR(d.x * dir.y - d.y * dir.x, 0.0, 1e-12);  // on the line
        const double t = glm::dot(d, dir);
        EXPECT_GE(t, -1e-12);
        EXPECT_LE(t, 20.0 + 1e-12);
    }
    // Samples within a span are equally spaced on the line (linear in the chord parameter).
    EXPECT_NEAR(glm::distance(curve[10], curve[11]), 6.5 / 9.0, 1e-12);
}

TEST(NaturalSpline, ClosedSplineThroughCirclePointsStaysOnCircle) {
    // 16 knots on a circle of radius 50 mm: a periodic cubic through them deviates from the
    // circle by O(h^4 / R^3); with h ~ 19.6 mm that is well under 0.01 mm.
    const double radius = 50.0;
    const int n = 16;
    Polyline2 knots;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * glm::pi<double>() * i / n;
        knots.push_back({radius * std::cos(a), radius * std::sin(a)});
    }
    const Polyline2 curve = sampleNaturalSpline(knots, true, 20);
    double worst = 0.0;
    for (const glm::dvec2& p : curve)
        worst = std::max(worst, std::abs(glm::length(p) - radius));
    EXPECT_LT(worst, 0.01);
    // Rotational symmetry of the input gives the same deviation at every knot mid-span.
    const double mid0 = glm::length(curve[10]);
    for (int i = 1; i < n; ++i)
        EXPECT_NEAR(glm::length(curve[i * 20 + 10]), mid0, 1e-9);
}

TEST(NaturalSpline, NaturalEndsHaveZeroCurvature) {
    const Polyline2 knots{{0, 0}, {10, 10}, {20, 0}, {30, 10}};
    const int perSpan = 200;
    const Polyline2 c = sampleNaturalSpline(knots, false, perSpan);
    // Second difference at the ends ~ h^2 * S'' ; relative to the interior it must vanish.
    const auto secondDiff = [&](std::size_t i) {
        return glm::length(c[i - 1] - 2.0 * c[i] + c[i + 1]);
    };
    const double interior = secondDiff(perSpan);
    EXPECT_GT(interior, 0.0);
    EXPECT_LT(secondDiff(1), 0.02 * interior);
    EXPECT_LT(secondDiff(c.size() - 2), 0.02 * interior);
}

TEST(NaturalSpline, MergesDuplicatesAndRejectsBadInput) {
    const Polyline2 withDup{{0, 0}, {0, 0}, {10, 0}, {10, 0}, {20, 5}};
    EXPECT_EQ(sampleNaturalSpline(withDup, false, 4).size(), 2u * 4u + 1u);
    const Polyline2 closedRepeat{{0, 0}, {10, 0}, {5, 8}, {0, 0}};
    EXPECT_EQ(sampleNaturalSpline(closedRepeat, true, 4).size(), 3u * 4u);

    EXPECT_THROW(sampleNaturalSpline(Polyline2{{1, 1}}, false, 4), std::invalid_argument);
    EXPECT_THROW(sampleNaturalSpline(Polyline2{{1, 1}, {1, 1}}, false, 4), std::invalid_argument);
    EXPECT_THROW(sampleNaturalSpline(Polyline2{{0, 0}, {1, 1}}, true, 4), std::invalid_argument);
    EXPECT_THROW(sampleNaturalSpline(Polyline2{{0, 0}, {1, 1}}, false, 0), std::invalid_argument);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(sampleNaturalSpline(Polyline2{{0, 0}, {nan, 1}, {2, 2}}, false, 4),
                 std::invalid_argument);
    EXPECT_THROW(sampleNaturalSpline(Polyline3{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, true, 0),
                 std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
