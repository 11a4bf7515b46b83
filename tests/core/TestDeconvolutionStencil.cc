// SPDX-License-Identifier: MIT
// The swept strokes' deconvolution stencil (docs/placement.md, "Stability"): the response it
// realises at every lattice frequency, and what that means over a long session.
#include "vsculpt/core/DeconvolutionStencil.h"

#include "TestHelpers.h"
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Sculpture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <set>

using namespace vsculpt::core;

namespace {

constexpr int kSteps = 2;  // PlaceStroke.cpp's kDeconvolveSteps
constexpr double kPi = std::numbers::pi;

struct Fixture {
    SculptConfig cfg;
    Sculpture sculpture{cfg};
    const HermiteFalloff& F = sculpture.levels().falloff();
    double supportOverSpacing =
        sculpture.levels().level(4).supportMm / sculpture.levels().level(4).spacingMm;
};

double transform(const std::vector<StencilTap>& s, const std::array<double, 3>& w) {
    double sum = 0;
    for (const StencilTap& t : s)
        sum += t.weight * std::cos(t.offset[0] * w[0] + t.offset[1] * w[1] + t.offset[2] * w[2]);
    return sum;
}

// Every frequency of the Brillouin zone's irreducible wedge on a grid (pi / 24 apart).
template <class Fn>
void forEachFrequency(Fn&& fn) {
    constexpr int N = 24;
    for (int i = 0; i <= N; ++i)
        for (int j = 0; j <= i; ++j)
            for (int k = 0; k <= j; ++k)
                fn(std::array<double, 3>{kPi * i / N, kPi * j / N, kPi * k / N});
}

}  // namespace

TEST(DeconvolutionStencil, PlainRichardsonRealisesOneMinusTheResidualCubed) {
    Fixture f;
    const auto K = latticeBlur(f.F, f.supportOverSpacing);
    ASSERT_EQ(K.size(), 19u);  // centre, faces, edges at R / h = 1.66
    double S = 0;
    for (const StencilTap& t : K)
        S += t.weight;
    const auto P = deconvolutionStencil(f.F, f.supportOverSpacing, kSteps, false);
    forEachFrequency([&](const std::array<double, 3>& w) {
        const double lambda = transform(K, w) / S;
        EXPECT_NEAR(realisedResponse(K, P, w), 1 - std::pow(1 - lambda, kSteps + 1), 1e-12);
    });
    // The cause of the instability: the blur is negative at the checkerboard frequency, and
    // a change there comes out with the opposite sign, a third of its size.
    EXPECT_LT(transform(K, {kPi, kPi, kPi}) / S, -0.05);
    EXPECT_LT(realisedResponse(K, P, {kPi, kPi, kPi}), -0.25);
}

TEST(DeconvolutionStencil, StabilisedResponseIsNeverFarBelowZeroAndKeepsThePassBand) {
    Fixture f;
    const auto K = latticeBlur(f.F, f.supportOverSpacing);
    const auto plain = deconvolutionStencil(f.F, f.supportOverSpacing, kSteps, false);
    const auto stable = deconvolutionStencil(f.F, f.supportOverSpacing, kSteps, true);
    double lowest = 1, highest = 0, passBandChange = 0;
    forEachFrequency([&](const std::array<double, 3>& w) {
        const double r = realisedResponse(K, stable, w);
        lowest = std::min(lowest, r);
        highest = std::max(highest, r);
        if (std::hypot(w[0], w[1], w[2]) <= 2.0)
            passBandChange = std::max(passBandChange, std::abs(r - realisedResponse(K, plain, w)));
    });
    EXPECT_GE(lowest, -0.035);  // measured -0.031; plain: -0.33 (a loop gain of 1.33 per stroke)
    EXPECT_LE(highest, 1 + 1e-9);
    EXPECT_LT(passBandChange, 0.01);
    EXPECT_NEAR(realisedResponse(K, stable, {0, 0, 0}), 1.0, 1e-12);
}

// Adds and carves alternating over one spot of the sphere, as a sculptor working a detail:
// each stroke's targets are read from the field the others left (level 5 strokes, random
// centres and directions within a third of the tool of one spot). Returns the largest |w|,
// the field's range over the spot and the levels the weights are on.
struct Scrubbed {
    double maxWeight = 0, lo = 0, hi = 0;
    std::set<int> levels;
};
Scrubbed scrubOneSpot(Sculpture& s, int strokes) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    const int level = 5;
    const double D = s.levels().level(level).diameterMm;
    for (int i = 0; i < strokes; ++i) {
        const Vec3 c(U(rng) * 0.3 * D, U(rng) * 0.3 * D, 40 + U(rng) * 0.5 * D);
        const Vec3 d = glm::normalize(Vec3(U(rng), U(rng), 0.2 * U(rng)));
        std::vector<Vec3> path;
        for (int k = -10; k <= 10; ++k)
            path.push_back(c + d * (k * 0.25 * D));
        applyStroke(s, i % 2 ? ToolOp::Carve : ToolOp::Add, level, path);
    }
    Scrubbed r;
    s.store().forEach([&](const SkeletonEntry& e) {
        r.maxWeight = std::max(r.maxWeight, double(std::abs(e.weight)));
        r.levels.insert(e.level);
    });
    FieldProbe probe(s);
    for (int k = 0; k < 4000; ++k) {
        const double v = probe.value(Vec3(U(rng) * D, U(rng) * D, 40 + U(rng) * D));
        r.lo = std::min(r.lo, v);
        r.hi = std::max(r.hi, v);
    }
    std::printf("%d strokes: max |w| %.3f, the field %.3f .. %.3f\n", strokes, r.maxWeight, r.lo,
                r.hi);
    return r;
}

// The weights and the field within what one stroke's fresh field reaches (f = sum - c, c = 0.5).
void expectBounded(const Scrubbed& r) {
    EXPECT_LT(r.maxWeight, 1.0);
    EXPECT_GT(r.lo, -1.0);
    EXPECT_LT(r.hi, 1.0);
}

Scrubbed scrubOneSpotWith(const SculptConfig& cfg, int strokes = 160);

// 600 strokes of it in a new sculpture of `cfg`: 30-40 s in a Release build. Skipped under the
// sanitizers, where it would take ten times that and the property is numerical.
void expectBoundedOverALongSession(const SculptConfig& cfg) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "numerical and long: Release builds only";
#else
    expectBounded(scrubOneSpotWith(cfg, 600));
#endif
}

// The same in a new sculpture of `cfg`, for `strokes` strokes or VSCULPT_SCRUB_STROKES (longer
// runs by hand).
Scrubbed scrubOneSpotWith(const SculptConfig& cfg, int strokes) {
    Sculpture s(cfg);
    const char* n = std::getenv("VSCULPT_SCRUB_STROKES");
    return scrubOneSpot(s, n ? std::atoi(n) : strokes);
}

// With the plain stencil the weights grew without bound (240 strokes: max |w| 1.5e3, the field
// +-300 around a 0.5 iso value; measured before the fix); they must stay of the order of one
// stroke's.
TEST(DeconvolutionStencil, AddsAndCarvesAlternatingInOnePlaceKeepTheWeightsBounded) {
    SculptConfig cfg;
    ASSERT_EQ(cfg.placement, PlacementMode::Swept);
    Sculpture s(cfg);
    const Scrubbed r = scrubOneSpot(s, 240);
    EXPECT_LT(r.maxWeight, 1.0);  // measured 0.32
    // f = sum - c with c = 0.5: within what one stroke's fresh field reaches.
    EXPECT_GT(r.lo, -1.0);
    EXPECT_LT(r.hi, 1.0);
}

// docs/placement.md "Stability": a random pile of strokes of every size (adds, and a carve in
// six) in a 60 mm cube; prints the weights' growth. VSCULPT_PLACEMENT_TABLES=1 to run (about
// two minutes for the default 1 400 strokes; VSCULPT_PILE_STROKES to change).
TEST(DeconvolutionStencil, PrintPileGrowth) {
    const char* e = std::getenv("VSCULPT_PLACEMENT_TABLES");
    if (!e || !*e || *e == '0') GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    const char* n = std::getenv("VSCULPT_PILE_STROKES");
    const int strokes = n ? std::atoi(n) : 1400;
    SculptConfig cfg;
    Sculpture s(cfg);
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> U(-1, 1);
    const Vec3 centre(0, 0, 40);
    for (int i = 0; i < strokes; ++i) {
        const int level = 1 + i % 7;
        const double D = s.levels().level(level).diameterMm;
        Vec3 p = centre + Vec3(U(rng), U(rng), U(rng)) * 30.0;
        Vec3 d(U(rng), U(rng), U(rng));
        std::vector<Vec3> path;
        for (int k = 0; k < 30; ++k) {
            path.push_back(p);
            p += glm::normalize(d) * 0.3 * D;
            d += Vec3(U(rng), U(rng), U(rng)) * 0.5;
        }
        applyStroke(s, i % 6 == 5 ? ToolOp::Carve : ToolOp::Add, level, path);
        if ((i + 1) % 200 == 0) {
            std::vector<double> w;
            s.store().forEach([&](const SkeletonEntry& x) { w.push_back(std::abs(x.weight)); });
            std::sort(w.begin(), w.end());
            std::printf("%5d strokes: %zu skeletons, |w| p99 %.3g, max %.3g\n", i + 1, w.size(),
                        w[w.size() * 99 / 100], w.back());
        }
    }
}

// The same work with the weights two levels finer than the tool (placement.finer_lattice_levels
// = 2): each fit share is normalised by the shares realised around its aim, which on a finer
// lattice can sum to nearly nothing; without a floor on that sum the weights reached 1e14
// within 40 strokes (measured). With it they stay of the order of a stroke's.
TEST(DeconvolutionStencil, AddsAndCarvesAlternatingOnAFinerLatticeKeepTheWeightsBounded) {
    SculptConfig cfg;
    cfg.finerLatticeLevels = 2;
    const Scrubbed r = scrubOneSpotWith(cfg);
    EXPECT_EQ(r.levels, std::set<int>{3});  // every weight two levels below the tool's 5
    EXPECT_LT(r.maxWeight, 1.0);            // measured 0.54
    // Measured -0.17 .. 0.09 (the long session: AFinerLatticeStaysBoundedOverALongSession).
    EXPECT_GT(r.lo, -1.0);
    EXPECT_LT(r.hi, 1.0);
}

// The same over a long session: on the finer lattice a checkerboard of weights, almost
// invisible in the field, grew once a few hundred strokes had worked the spot (max |w| 0.54
// after 300 strokes, 2.9 after 600, 5.5 after 800 with the field out of its range; measured
// before kFineCheckerboardDecay; now 0.54).
TEST(DeconvolutionStencil, AFinerLatticeStaysBoundedOverALongSession) {
    SculptConfig cfg;
    cfg.finerLatticeLevels = 2;
    expectBoundedOverALongSession(cfg);
}

// placement.refine_levels = 2 (docs/placement.md "Refining strokes"): each stroke also leaves
// a two-sided residual two levels down, which the next stroke reads as clay; adds and carves
// alternating over one spot must not grow it without bound.
TEST(DeconvolutionStencil, AddsAndCarvesAlternatingWithRefinementKeepTheWeightsBounded) {
    SculptConfig cfg;
    cfg.refineLevels = 2;
    const Scrubbed r = scrubOneSpotWith(cfg);
    EXPECT_EQ(r.levels, (std::set<int>{3, 5}));  // the tool's and two below
    // Measured 0.58, the field -0.11 .. 0.17 (the long session: below).
    EXPECT_LT(r.maxWeight, 1.0);
    EXPECT_GT(r.lo, -1.0);
    EXPECT_LT(r.hi, 1.0);
}

// The same over a long session. The two lattices grew large, opposite weights whose fields
// cancel (max |w| 5.0 after 600 strokes, 14 after 800 with the field out of its range; 2.7 and
// 5.6 with the finer lattice's checkerboard decay alone) until each refined stroke handed a
// share of the fine weights in its reach to the tool's lattice (kRefineLeak; now 0.56 after 800).
TEST(DeconvolutionStencil, ARefinedSessionStaysBoundedOverALongSession) {
    SculptConfig cfg;
    cfg.refineLevels = 2;
    expectBoundedOverALongSession(cfg);
}
