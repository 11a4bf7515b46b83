// The pieces of the incremental clean-up: feature points, line mixing, joining, knot division.
#include "vsculpt/sketch/FeaturePoints.h"
#include "vsculpt/sketch/JoinFeaturePoints.h"
#include "vsculpt/sketch/KnotDivision.h"
#include "vsculpt/sketch/LineMixing.h"
#include "vsculpt/sketch/NaturalSpline.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = glm::pi<double>();

Polyline2 row(std::initializer_list<double> xs, double y = 0.0) {
    Polyline2 out;
    for (double x : xs)
        out.push_back({x, y});
    return out;
}

void expectSame(const Polyline2& got, const Polyline2& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i)
        EXPECT_LT(glm::distance(got[i], want[i]), 1e-9) << "point " << i;
}

TEST(FeaturePoints, EndpointsAndFarthestFromChord) {
    Polyline2 arc;
    for (int i = 0; i <= 40; ++i) {
        const double a = kPi * i / 40;
        arc.push_back({-20 * std::cos(a), 20 * std::sin(a)});
    }
    const Polyline2 f = strokeFeaturePoints(arc);
    ASSERT_EQ(f.size(), 3u);
    EXPECT_EQ(f[0], arc.front());
    EXPECT_EQ(f[2], arc.back());
    EXPECT_LT(glm::distance(f[1], glm::dvec2(0, 20)), 1e-12);  // apex of the half circle
    EXPECT_THROW(strokeFeaturePoints(Polyline2{{1, 1}}), std::invalid_argument);
}

TEST(LineMixing, FitAndSeedMixRule) {
    const Segment2 fit = fitSegment(Polyline2{{0, 1}, {2, 2}, {4, 3}, {10, 6}});
    EXPECT_LT(glm::distance(fit.a, glm::dvec2(0, 1)), 1e-12);
    EXPECT_LT(glm::distance(fit.b, glm::dvec2(10, 6)), 1e-12);

    // Older at 0 degrees, newer at 10 degrees drawn the other way round: the mix runs at 5
    // degrees through the newer midpoint (seed 5.2 step 3).
    const double t = 10.0 * kPi / 180.0;
    const Segment2 older{{0, 0}, {40, 0}};
    const glm::dvec2 mid{20, 2};
    const glm::dvec2 half = 15.0 * glm::dvec2{std::cos(t), std::sin(t)};
    const Segment2 newer{mid + half, mid - half};
    const Segment2 mixed = mixSegments(older, newer);
    const glm::dvec2 dir = glm::normalize(mixed.b - mixed.a);
    EXPECT_NEAR(std::atan2(dir.y, dir.x), 0.5 * t, 1e-12);
    const glm::dvec2 toMid = mid - mixed.a;
    EXPECT_NEAR(toMid.x * dir.y - toMid.y * dir.x, 0.0, 1e-12);
    // Extent covers the older segment's ends.
    EXPECT_LE(glm::dot(older.a - mixed.a, dir), 1e-9);
    EXPECT_GE(glm::dot(older.b - mixed.b, dir), -1e-9);

    EXPECT_TRUE(isSameLine(older, newer));
    EXPECT_FALSE(isSameLine(older, Segment2{{0, 10}, {40, 10}}));    // parallel, 10 mm away
    EXPECT_FALSE(isSameLine(older, Segment2{{20, -10}, {20, 10}}));  // crossing at 90 degrees
    EXPECT_THROW(mixSegments(older, Segment2{{1, 1}, {1, 1}}), std::invalid_argument);
}

TEST(JoinFeaturePoints, NoOverlapChainsAndDropsNearPoint) {
    // Seed Fig. 5.6 (a): the newer A, B, C ends next to older point 0, which is dropped.
    const Polyline2 older = row({0, 10, 20, 30});
    const JoinResult r = joinFeaturePoints(older, false, row({-30, -15, -1}));
    EXPECT_EQ(r.overlap, Overlap::None);
    EXPECT_EQ(r.olderRemoved, 1u);
    expectSame(r.points, row({-30, -15, -1, 10, 20, 30}));
    // Drawn the other way round it is reversed to continue into the older curve.
    const JoinResult rev = joinFeaturePoints(older, false, row({-1, -15, -30}));
    EXPECT_TRUE(rev.reversed);
    expectSame(rev.points, row({-30, -15, -1, 10, 20, 30}));
    // Beyond the far end the newer points are appended.
    expectSame(joinFeaturePoints(older, false, row({40, 50, 60})).points,
               row({0, 10, 20, 30, 40, 50, 60}));
}

TEST(JoinFeaturePoints, PartialOverlapNewerWins) {
    // Seed Fig. 5.6 (b): older point 0 lies between B and C and is deleted.
    const JoinResult r = joinFeaturePoints(row({0, 10, 20, 30}), false, row({-20, -7, 5}, 0.5));
    EXPECT_EQ(r.overlap, Overlap::Partial);
    Polyline2 want = row({-20, -7, 5}, 0.5);
    for (double x : {10.0, 20.0, 30.0})
        want.push_back({x, 0});
    expectSame(r.points, want);
}

TEST(JoinFeaturePoints, FullOverlapReplacesOnlyTheOverlappedPart) {
    // Seed Fig. 5.6 (c), drawn in both directions.
    const Polyline2 older = row({0, 10, 20, 30, 40});
    Polyline2 want{{0, 0}, {10, 0}, {14, 1}, {21, 1.5}, {28, 1}, {40, 0}};
    for (bool reverse : {false, true}) {
        Polyline2 newer{{14, 1}, {21, 1.5}, {28, 1}};
        if (reverse) std::reverse(newer.begin(), newer.end());
        const JoinResult r = joinFeaturePoints(older, false, newer);
        EXPECT_EQ(r.overlap, Overlap::Full);
        EXPECT_EQ(r.reversed, reverse);
        // 20 is inside the span, 30 within 3 mm of C = (28, 1).
        EXPECT_EQ(r.olderRemoved, 2u);
        expectSame(r.points, want);
    }
    // A weight of 0.5 moves the newer points halfway from the older curve (here y = 0).
    JoinParams half;
    half.newStrokeWeight = 0.5;
    const JoinResult h =
        joinFeaturePoints(older, false, Polyline2{{14, 2}, {21, 2}, {26, 2}}, half);
    for (std::size_t i = 2; i < 5; ++i)
        EXPECT_NEAR(h.points[i].y, 1.0, 1e-9);
}

TEST(JoinFeaturePoints, ClosedLoopKeepsLoopAndReplacesOneSide) {
    const Polyline2 square{{0, 0},   {20, 0},  {40, 0}, {40, 20},
                           {40, 40}, {20, 40}, {0, 40}, {0, 20}};
    const Polyline2 newer{{12, 2}, {20, 3}, {28, 2}};  // over the bottom side
    const JoinResult r = joinFeaturePoints(square, true, newer);
    // (20, 0) is replaced; the loop is not repeated at its end.
    EXPECT_EQ(r.points.size(), square.size() + 2);
    EXPECT_NE(r.points.front(), r.points.back());
    std::size_t found = 0;
    for (const glm::dvec2& p : r.points) {
        EXPECT_GT(glm::distance(p, glm::dvec2(20, 0)), 1e-9);
        for (const glm::dvec2& q : newer)
            found += glm::distance(p, q) < 1e-12;
    }
    EXPECT_EQ(found, 3u);
    EXPECT_THROW(joinFeaturePoints(square, true, Polyline2{}), std::invalid_argument);
    EXPECT_THROW(joinFeaturePoints(Polyline2{{0, 0}, {1, 0}}, true, newer), std::invalid_argument);
}

TEST(JoinFeaturePoints, StrokeBridgingEndToStartClosesTheLoop) {
    const auto onCircle = [](double deg) {
        const double a = deg * kPi / 180.0;
        return glm::dvec2{30 * std::cos(a), 30 * std::sin(a)};
    };
    Polyline2 older;
    for (double deg : {0.0, 70.0, 140.0, 200.0, 260.0})
        older.push_back(onCircle(deg));
    const Polyline2 newer{onCircle(240), onCircle(310), onCircle(20)};
    const JoinResult r = joinFeaturePoints(older, false, newer);
    EXPECT_EQ(r.overlap, Overlap::Closes);
    // Older 0 and 260 lie outside the stretch 20..240 (and within merge distance of nothing
    // else); 70, 140, 200 are kept, then the bridge.
    Polyline2 want{onCircle(70), onCircle(140), onCircle(200)};
    want.insert(want.end(), newer.begin(), newer.end());
    expectSame(r.points, want);
}

TEST(FeaturePoints, RefinedForStronglyBentStrokes) {
    Polyline2 half;
    for (int i = 0; i <= 180; ++i) {
        const double a = kPi * i / 180;
        half.push_back({40 * std::cos(a), 40 * std::sin(a)});
    }
    EXPECT_EQ(strokeFeaturePoints(half, 0.0).size(), 3u);
    const Polyline2 fine = strokeFeaturePoints(half, 0.05);
    EXPECT_GT(fine.size(), 5u);
    EXPECT_EQ(fine.front(), half.front());
    EXPECT_EQ(fine.back(), half.back());
    // Between consecutive feature points every stroke point is within 5 % of the chord.
    for (std::size_t k = 0; k + 1 < fine.size(); ++k) {
        const glm::dvec2 a = fine[k], b = fine[k + 1];
        for (const glm::dvec2& p : half) {
            const glm::dvec2 d = b - a;
            const double t = glm::dot(p - a, d) / glm::dot(d, d);
            if (t <= 0.0 || t >= 1.0 || glm::dot(p, a + b) < 0.0) continue;  // other pieces
            const double h = std::abs(d.x * (p - a).y - d.y * (p - a).x) / glm::length(d);
            EXPECT_LE(h, 0.05 * glm::length(d) + 1e-9);
        }
    }
    EXPECT_THROW(strokeFeaturePoints(half, -1.0), std::invalid_argument);
}

TEST(KnotDivision, StraightAndSlightlyBumpyLinesReduceToTwoKnots) {
    Polyline2 line;
    for (int i = 0; i <= 100; ++i)
        line.push_back({double(i), 0.5 * std::sin(i * 0.7)});  // h / L = 0.005
    EXPECT_EQ(knotDivision(line, false), (std::vector<std::size_t>{0, 100}));
}

TEST(KnotDivision, KeepsChordCrossingAndSignificantShape) {
    // One full sine period crosses its chord in the middle: that point is kept.
    Polyline2 wave;
    for (int i = 0; i <= 200; ++i)
        wave.push_back({double(i), 20.0 * std::sin(2 * kPi * i / 200.0)});
    const auto kept = knotDivision(wave, false);
    EXPECT_NE(std::find(kept.begin(), kept.end(), 100u), kept.end());
    // The spline through the kept points follows the wave: Kondo's rule bounds the deviation of
    // every dropped point from its chord by epsilon * L, and the spline does better than chords.
    Polyline2 knots;
    for (std::size_t i : kept)
        knots.push_back(wave[i]);
    EXPECT_LT(knots.size(), 20u);
    const Polyline2 curve = sampleNaturalSpline(knots, false, 32);
    for (const glm::dvec2& p : curve)
        EXPECT_NEAR(p.y, 20.0 * std::sin(2 * kPi * p.x / 200.0), 1.0);
}

TEST(KnotDivision, RemovesSmallBumpKeepsLargeOne) {
    const auto bumped = [](double height) {
        Polyline2 c;
        for (int i = 0; i <= 100; ++i) {
            const double x = i, u = (x - 50.0) / 5.0;
            c.push_back({x, height * std::exp(-u * u)});
        }
        return c;
    };
    EXPECT_EQ(knotDivision(bumped(1.0), false).size(), 2u);  // h / L = 0.01 < 0.03
    const auto kept = knotDivision(bumped(10.0), false);     // h / L = 0.1
    EXPECT_GT(kept.size(), 2u);
    EXPECT_NE(std::find(kept.begin(), kept.end(), 50u), kept.end());  // the peak
}

TEST(KnotDivision, ClosedCircleKeepsFewKnotsAndRejectsBadInput) {
    Polyline2 circle;
    for (int i = 0; i < 128; ++i) {
        const double a = 2 * kPi * i / 128;
        circle.push_back({30 * std::cos(a), 30 * std::sin(a)});
    }
    const auto kept = knotDivision(circle, true);
    EXPECT_GE(kept.size(), 4u);
    EXPECT_LE(kept.size(), 32u);
    EXPECT_EQ(kept.front(), 0u);
    EXPECT_NE(std::find(kept.begin(), kept.end(), 64u), kept.end());  // farthest from point 0
    EXPECT_THROW(knotDivision(circle, true, {0.0}), std::invalid_argument);
    EXPECT_THROW(knotDivision(Polyline2{{0, 0}, {NAN, 0}}, false), std::invalid_argument);
}

// Peak resident memory of this process so far (MB); each test runs in its own process under
// ctest, and the other tests here stay far below the margins used.
double peakRssMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // kB on Linux
}

// The refinement as first written, depth first and without a cap: the reference the capped
// best-first version must equal whenever the cap is not reached.
void refineReference(const Polyline2& s, std::size_t i0, std::size_t i1, double ratio,
                     std::vector<std::size_t>& out) {
    if (i1 - i0 < 2) return;
    const glm::dvec2 a = s[i0], chord = s[i1] - a;
    const double len = glm::length(chord);
    std::size_t k = (i0 + i1) / 2;
    double d = -1.0;
    for (std::size_t i = i0 + 1; i < i1; ++i) {
        const glm::dvec2 v = s[i] - a;
        const double di =
            len > 0.0 ? std::abs(chord.x * v.y - chord.y * v.x) / len : glm::length(v);
        if (di > d) {
            d = di;
            k = i;
        }
    }
    if (!(d > ratio * len)) return;
    refineReference(s, i0, k, ratio, out);
    out.push_back(k);
    refineReference(s, k, i1, ratio, out);
}

TEST(FeaturePoints, CapKeepsTheLargestSplitsAndChangesNothingBelowIt) {
    // A jittery wave: at ratio 0.002 nearly every wiggle qualifies.
    Polyline2 wave;
    std::uint64_t state = 17;
    for (int i = 0; i <= 3000; ++i) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        const double jitter = 0.2 * (double(state >> 11) * 0x1.0p-53 - 0.5);
        wave.push_back({0.5 * i, 8.0 * std::sin(i * 0.02) + jitter});
    }
    const std::size_t unlimited = std::size_t(1) << 40;
    const Polyline2 all = strokeFeaturePoints(wave, 0.002, unlimited);
    ASSERT_GT(all.size(), 200u);
    // Equal to the uncapped depth-first refinement, point for point; its first split is the
    // point farthest from the whole stroke's chord.
    std::size_t far = 1;
    double farthest = -1.0;
    const glm::dvec2 a = wave.front(), chord = wave.back() - a;
    for (std::size_t i = 1; i + 1 < wave.size(); ++i) {
        const glm::dvec2 v = wave[i] - a;
        const double d = std::abs(chord.x * v.y - chord.y * v.x) / glm::length(chord);
        if (d > farthest) {
            farthest = d;
            far = i;
        }
    }
    std::vector<std::size_t> reference{0};
    refineReference(wave, 0, far, 0.002, reference);
    reference.push_back(far);
    refineReference(wave, far, wave.size() - 1, 0.002, reference);
    reference.push_back(wave.size() - 1);
    ASSERT_EQ(all.size(), reference.size());
    for (std::size_t i = 0; i < all.size(); ++i)
        EXPECT_EQ(all[i], wave[reference[i]]) << i;

    const Polyline2 capped = strokeFeaturePoints(wave, 0.002);  // default cap
    ASSERT_EQ(capped.size(), kMaxFeaturePoints);
    EXPECT_EQ(capped.front(), wave.front());
    EXPECT_EQ(capped.back(), wave.back());
    // A subset of the full set, in drawing order: the cap drops splits, it never moves them.
    std::size_t at = 0;
    for (const glm::dvec2& p : capped) {
        while (at < all.size() && all[at] != p)
            ++at;
        ASSERT_LT(at, all.size()) << "capped point not among the uncapped ones";
    }
    // The largest features survive: a kept point near every crest and trough of the sine.
    for (double x = 0.5 * kPi / 0.04; x < 1500.0; x += kPi / 0.04) {
        double nearest = 1e9;
        for (const glm::dvec2& p : capped)
            nearest = std::min(nearest, std::abs(p.x - x));
        EXPECT_LT(nearest, 15.0) << "crest at x " << x;
    }
    // Below the cap nothing changes: the seed's three points and the refined arc.
    EXPECT_EQ(strokeFeaturePoints(wave, 0.0, 3), strokeFeaturePoints(wave, 0.0, unlimited));
    EXPECT_THROW(strokeFeaturePoints(wave, 0.1, 2), std::invalid_argument);
}

TEST(KnotDivision, ZigzagNeedsLinearMemory) {
    // A zigzag whose amplitude grows along it: every interval first crosses its chord next to
    // its start, so the division nests once per point. Keeping each level's distances alive
    // cost memory quadratic in the points (127 MB for these 8000).
    Polyline2 zigzag;
    for (int i = 0; i < 8000; ++i)
        zigzag.push_back({double(i), (i % 2 ? 1.0 : -1.0) * (1.0 + i)});
    const double before = peakRssMb();
    const std::vector<std::size_t> kept = knotDivision(zigzag, false);
    EXPECT_LT(peakRssMb() - before, 32.0);
    ASSERT_EQ(kept.size(), zigzag.size());  // every corner is significant
    for (std::size_t i = 0; i < kept.size(); ++i)
        ASSERT_EQ(kept[i], i);
}

}  // namespace
}  // namespace vsculpt::sketch
