#include "vsculpt/sketch/ResampleStroke.h"
#include "vsculpt/sketch/ScribbleDetection.h"
#include "vsculpt/sketch/SelfIntersections.h"
#include "vsculpt/sketch/Stroke.h"
#include "vsculpt/sketch/StrokeClosedness.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = glm::pi<double>();

Polyline2 arc(double radius, double a0, double a1, int n, glm::dvec2 c = {0, 0}) {
    Polyline2 out;
    for (int i = 0; i <= n; ++i) {
        const double a = a0 + (a1 - a0) * i / n;
        out.push_back(c + radius * glm::dvec2{std::cos(a), std::sin(a)});
    }
    return out;
}

TEST(Stroke, ValidationNamesTheProblem) {
    EXPECT_THROW(validateStroke(Stroke{}), std::invalid_argument);
    Stroke s = makeStroke({{0, 0}, {1, 0}, {2, 0}});
    EXPECT_NO_THROW(validateStroke(s));
    Stroke back = s;
    back.samples[2].time = -1.0;
    try {
        validateStroke(back);
        FAIL() << "expected a throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("backwards"), std::string::npos);
    }
    Stroke nanPos = s;
    nanPos.samples[1].position.y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(validateStroke(nanPos), std::invalid_argument);
    Stroke pressure = s;
    pressure.hasPressure = true;
    pressure.samples[0].pressure = 1.5;
    EXPECT_THROW(validateStroke(pressure), std::invalid_argument);
    pressure.samples[0].pressure = 0.7;
    EXPECT_NO_THROW(validateStroke(pressure));
    EXPECT_DOUBLE_EQ(peakPressure(pressure), 1.0);
    EXPECT_DOUBLE_EQ(peakPressure(s), 0.0);  // no pressure data
}

TEST(ResampleStroke, EqualSpacingAndInterpolatedTimeAndPressure) {
    // An L shape, 10 mm + 5 mm, drawn at non-uniform speed.
    Stroke s;
    s.hasPressure = true;
    s.samples = {{{0, 0}, 0.0, 0.2}, {{10, 0}, 1.0, 0.6}, {{10, 5}, 3.0, 1.0}};
    const Stroke r = resampleBySpacing(s, 1.0);
    ASSERT_EQ(r.samples.size(), 16u);
    for (std::size_t i = 0; i < r.samples.size(); ++i) {
        const double arcLen = double(i);
        const glm::dvec2 expected =
            arcLen <= 10 ? glm::dvec2{arcLen, 0} : glm::dvec2{10, arcLen - 10};
        EXPECT_LT(glm::distance(r.samples[i].position, expected), 1e-9) << i;
    }
    // Time and pressure follow the input segment linearly: 12.5 mm is halfway up the second leg.
    EXPECT_NEAR(r.samples[12].time, 1.0 + 2.0 * (2.0 / 5.0), 1e-12);
    EXPECT_NEAR(r.samples[12].pressure, 0.6 + 0.4 * (2.0 / 5.0), 1e-12);
    EXPECT_TRUE(r.hasPressure);
    EXPECT_EQ(r.samples.back().time, 3.0);
}

TEST(ResampleStroke, KeepsLastPointAndHandlesDegenerateInput) {
    const Polyline2 line = resampleBySpacing(Polyline2{{0, 0}, {0, 0}, {3.5, 0}}, 1.0);
    ASSERT_EQ(line.size(), 5u);
    EXPECT_EQ(line.back(), glm::dvec2(3.5, 0));
    EXPECT_EQ(resampleBySpacing(Polyline2{{2, 2}, {2, 2}}, 1.0).size(), 1u);
    EXPECT_THROW(resampleBySpacing(Polyline2{}, 1.0), std::invalid_argument);
    EXPECT_THROW(resampleBySpacing(Polyline2{{0, 0}, {1, 0}}, 0.0), std::invalid_argument);
    EXPECT_THROW(
        resampleBySpacing(Polyline2{{0, 0}, {1, 0}}, std::numeric_limits<double>::quiet_NaN()),
        std::invalid_argument);
}

TEST(StrokeClosedness, LoopsWithGapOrOvershootAreClosed) {
    // Circle radius 20 (length ~125.7): a 5 mm gap and a 20-degree overshoot are closed.
    EXPECT_TRUE(isClosedStroke(arc(20, 0, 2 * kPi - 0.25, 60)));
    EXPECT_TRUE(isClosedStroke(arc(20, 0, 2 * kPi + 0.35, 60)));
    // A half circle or a C with a wide mouth is open; so is a straight line.
    EXPECT_FALSE(isClosedStroke(arc(20, 0, kPi, 30)));
    EXPECT_FALSE(isClosedStroke(arc(20, 0, 1.6 * kPi, 30)));
    EXPECT_FALSE(isClosedStroke(Polyline2{{0, 0}, {5, 0}, {10, 0}}));
    EXPECT_FALSE(isClosedStroke(Polyline2{{0, 0}, {0, 0}, {0, 0}}));
    EXPECT_THROW(isClosedStroke(Polyline2{{0, 0}, {1, 0}, {1, 1}}, {0.0, 0.25}),
                 std::invalid_argument);
}

TEST(SelfIntersections, FigureEightCrossesOnceAtTheCentre) {
    Polyline2 eight;
    for (int i = 0; i < 200; ++i) {
        const double t = 2 * kPi * i / 200;
        eight.push_back({30 * std::sin(t), 15 * std::sin(2 * t)});  // lemniscate-like
    }
    const auto hits = findSelfIntersections(eight, true);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_LT(glm::length(hits[0].point), 1e-9);
    // The same curve as an open stroke stopping before it returns: no crossing.
    const Polyline2 half(eight.begin(), eight.begin() + 100);
    EXPECT_FALSE(hasSelfIntersection(half, false));
    // A circle is simple when closed.
    Polyline2 circle = arc(10, 0, 2 * kPi, 64);
    circle.pop_back();
    EXPECT_FALSE(hasSelfIntersection(circle, true));
}

TEST(SelfIntersections, ReportsExactCrossingParameters) {
    // Segment 0 (0,0)-(10,0) is crossed by segment 2 (8,-2)-(8,4) at t = 0.8 and 1/3.
    const Polyline2 hook{{0, 0}, {10, 0}, {8, -2}, {8, 4}};
    const auto hits = findSelfIntersections(hook, false);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_EQ(hits[0].segmentA, 0u);
    EXPECT_EQ(hits[0].segmentB, 2u);
    EXPECT_NEAR(hits[0].tA, 0.8, 1e-12);
    EXPECT_NEAR(hits[0].tB, 1.0 / 3.0, 1e-12);
    // Retracing a segment (collinear overlap) is an intersection too.
    EXPECT_TRUE(hasSelfIntersection(Polyline2{{0, 0}, {10, 0}, {10, 1}, {5, 0}, {2, 0}}, false));
    EXPECT_THROW(findSelfIntersections(Polyline2{{0, 0}, {INFINITY, 0}, {1, 1}}, false),
                 std::invalid_argument);
}

TEST(ScribbleDetection, ZigzagIsScribbleSmoothCurvesAreNot) {
    Polyline2 zigzag;
    for (int i = 0; i < 12; ++i) {
        zigzag.push_back({0.0 + i * 0.8, 0.0});
        zigzag.push_back({0.4 + i * 0.8, 15.0});
    }
    EXPECT_GE(countReversals(zigzag), 20);
    EXPECT_TRUE(isScribble(zigzag));
    EXPECT_FALSE(isScribble(Polyline2{{0, 0}, {100, 0}}));
    EXPECT_FALSE(isScribble(arc(30, 0, 2 * kPi, 120)));  // one loop is a closed stroke
    Polyline2 wave;  // gentle wave: amplitude 3 mm, wavelength 40 mm
    for (int i = 0; i <= 200; ++i)
        wave.push_back({i * 1.0, 3.0 * std::sin(2 * kPi * i / 40.0)});
    EXPECT_EQ(countReversals(wave), 0);
    EXPECT_FALSE(isScribble(wave));
    // A single hairpin reverses once but is not a scribble.
    const Polyline2 hairpin{{0, 0}, {50, 0}, {50, 1}, {0, 1}};
    EXPECT_EQ(countReversals(hairpin), 1);
    EXPECT_FALSE(isScribble(hairpin));
}

// ---------------------------------------------------------------------------------------------
// Bounds: input of any size costs bounded memory, or is refused before anything is allocated.

// Peak resident memory of this process so far (MB); each test runs in its own process under
// ctest, and the other tests here stay far below the margins used.
double peakRssMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // kB on Linux
}

// 20 points zigzagging between opposite edges of the canvas: 38 km of ink.
Polyline2 canvasZigzag() {
    Polyline2 pts;
    for (int i = 0; i < 20; ++i)
        pts.push_back({-9.5e5 + 1e5 * i, i % 2 ? 9.9e5 : -9.9e5});
    return pts;
}

TEST(Stroke, PositionsAndTimesAreBounded) {
    Stroke s = makeStroke({{0, 0}, {kMaxStrokeCoordinate, -kMaxStrokeCoordinate}});
    EXPECT_NO_THROW(validateStroke(s));
    s.samples[1].position.x = 1e308;
    try {
        validateStroke(s);
        FAIL() << "expected a throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), "stroke: position outside [-1e6, 1e6] mm at sample 1");
    }
    s.samples[1].position.x = 0.0;
    s.samples[1].time = 1e11;
    EXPECT_THROW(validateStroke(s), std::invalid_argument);
    s.samples[1].time = 1.7e9;  // seconds since the Unix epoch
    EXPECT_NO_THROW(validateStroke(s));
}

TEST(ResampleStroke, TooFineAStepIsRefusedBeforeAllocating) {
    const Stroke across = makeStroke({{-1e6, 0}, {1e6, 0}});
    const double before = peakRssMb();
    // 2 million points at 1 mm: over the default bound of a million.
    EXPECT_THROW(resampleBySpacing(across, 1.0), std::invalid_argument);
    EXPECT_THROW(resampleBySpacing(strokePositions(across), 0.5), std::invalid_argument);
    EXPECT_LT(peakRssMb() - before, 16.0);
    EXPECT_EQ(resampleBySpacing(across, 1e5, 21).samples.size(), 21u);
    EXPECT_THROW(resampleBySpacing(across, 1e5, 20), std::invalid_argument);
}

TEST(ResampleStroke, BoundedSpacingKeepsAnyLengthWithinThePointLimit) {
    EXPECT_EQ(boundedSpacing(100.0, 0.5, 4096), 0.5);  // short strokes keep their step
    for (const std::size_t maxPoints : {std::size_t(4), std::size_t(17), std::size_t(4096)})
        for (const double len : {0.0, 1e-9, 0.3, 7.0, 2047.0, 2048.0, 2049.5, 1e4, 1.9e6}) {
            const Stroke s = makeStroke({{0, 0}, {len / 2, 0}, {len / 2, len / 2}});
            const double spacing = boundedSpacing(strokeLength(s), 0.5, maxPoints);
            EXPECT_GE(spacing, 0.5);
            EXPECT_LE(resampleBySpacing(s, spacing, maxPoints).samples.size(), maxPoints)
                << len << " mm, " << maxPoints;
        }
    EXPECT_THROW(boundedSpacing(INFINITY, 0.5, 100), std::invalid_argument);
    EXPECT_THROW(boundedSpacing(1.0, 0.0, 100), std::invalid_argument);
    EXPECT_THROW(boundedSpacing(1.0, 0.5, 3), std::invalid_argument);
}

TEST(ScribbleDetection, CanvasSizedZigzagCostsBoundedMemory) {
    const double before = peakRssMb();
    // At the 1 mm step this resampled to 38 million points (over 1 GB).
    EXPECT_GE(countReversals(canvasZigzag()), 18);
    EXPECT_TRUE(isScribble(canvasZigzag()));
    EXPECT_LT(peakRssMb() - before, 16.0);
    ScribbleParams p;
    p.maxPoints = 3;
    EXPECT_THROW(isScribble(canvasZigzag(), p), std::invalid_argument);
}

TEST(SelfIntersections, CrossingsAreCappedInOrder) {
    // A star polygon: its 400 chords nearly all cross each other, about 80 000 crossings.
    Polyline2 star;
    for (int i = 0; i < 400; ++i) {
        const double a = i * kPi * (1.0 - 1.0 / 401.0);
        star.push_back({100 * std::cos(a), 100 * std::sin(a)});
    }
    const auto hits = findSelfIntersections(star, false);
    ASSERT_EQ(hits.size(), kMaxSelfIntersections);
    const auto more = findSelfIntersections(star, false, 100000);
    ASSERT_GT(more.size(), hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        ASSERT_EQ(hits[i].segmentA, more[i].segmentA);
        ASSERT_EQ(hits[i].segmentB, more[i].segmentB);
    }
    const auto first = findSelfIntersections(star, false, 1);
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].point, more[0].point);
    EXPECT_TRUE(findSelfIntersections(star, false, 0).empty());
    EXPECT_TRUE(hasSelfIntersection(star, false));
}

}  // namespace
}  // namespace vsculpt::sketch
