// SPDX-License-Identifier: MIT
#include "vsculpt/core/Falloff.h"

#include "TestHelpers.h"

#include <gtest/gtest.h>

#include <random>

using namespace vsculpt::core;

namespace {

const FalloffParams kDefault{};

TEST(Falloff, EndValuesAndControlPoint) {
    const HermiteFalloff F(kDefault);
    EXPECT_DOUBLE_EQ(F.value(0.0), kDefault.f0);
    EXPECT_DOUBLE_EQ(F.value(kDefault.controlU), kDefault.controlValue);
    EXPECT_DOUBLE_EQ(F.value(1.0), 0.0);
    EXPECT_DOUBLE_EQ(F.derivative(0.0), 0.0);
    EXPECT_NEAR(F.derivative(1.0 - 1e-12), 0.0, 1e-9);
}

TEST(Falloff, CompactSupport) {
    const HermiteFalloff F(kDefault);
    for (double u : {1.0, 1.0 + 1e-12, 1.5, 2.0, 1e6}) {
        EXPECT_EQ(F.value(u), 0.0) << u;
        EXPECT_EQ(F.derivative(u), 0.0) << u;
    }
    // Continuity into the zero region: values just inside the support are tiny.
    EXPECT_LT(F.value(1.0 - 1e-6), 1e-10);
}

TEST(Falloff, MonotoneOnDenseSamples) {
    for (double slope : {0.0, -0.3, -1.5, -3.0}) {  // -3 is the steepest allowed here
        FalloffParams p = kDefault;
        p.controlSlope = slope;
        const HermiteFalloff F(p);
        double prev = F.value(0.0);
        for (int i = 1; i <= 100000; ++i) {
            const double v = F.value(i * 1.1e-5);
            ASSERT_LE(v, prev + 1e-15) << "slope " << slope << " at u=" << i * 1.1e-5;
            prev = v;
        }
    }
}

TEST(Falloff, SlopeAtControlPointEqualsParameterAndIsC1) {
    for (double slope : {-0.2, -1.0, -1.5, -2.7}) {
        FalloffParams p = kDefault;
        p.controlSlope = slope;
        const HermiteFalloff F(p);
        const double a = p.controlU, e = 1e-6;
        EXPECT_NEAR(F.derivative(a), slope, 1e-12);
        // One-sided difference quotients from both segments agree with the parameter (C1).
        EXPECT_NEAR((F.value(a) - F.value(a - e)) / e, slope, 1e-5);
        EXPECT_NEAR((F.value(a + e) - F.value(a)) / e, slope, 1e-5);
        EXPECT_NEAR(F.derivative(a - 1e-9), F.derivative(a + 1e-9), 1e-7);
    }
}

TEST(Falloff, DerivativeMatchesFiniteDifferences) {
    FalloffParams p{1.3, 0.35, 0.8, -2.0};
    const HermiteFalloff F(p);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(1e-3, 0.999);
    for (int i = 0; i < 1000; ++i) {
        const double u = U(rng), e = 1e-6;
        EXPECT_NEAR(F.derivative(u), (F.value(u + e) - F.value(u - e)) / (2 * e), 1e-6) << u;
    }
}

TEST(Falloff, InverseFindsTheLevel) {
    const HermiteFalloff F(kDefault);
    for (double level : {0.01, 0.25, 0.5, 0.75, 0.99}) {
        EXPECT_NEAR(F.value(F.inverse(level)), level, 1e-12);
    }
    EXPECT_THROW(F.inverse(0.0), std::invalid_argument);
    EXPECT_THROW(F.inverse(kDefault.f0), std::invalid_argument);
}

TEST(Falloff, RejectsNonMonotoneOrInvalidParameters) {
    FalloffParams p = kDefault;
    p.controlSlope = -3.01;  // steeper than 3x the secant (-1) of either segment
    EXPECT_NE(validateFalloff(p), "");
    EXPECT_THROW(HermiteFalloff{p}, std::invalid_argument);
    p.controlSlope = 0.1;  // rising
    EXPECT_NE(validateFalloff(p), "");
    p = kDefault;
    p.controlU = 1.0;
    EXPECT_NE(validateFalloff(p), "");
    p = kDefault;
    p.controlValue = 1.0;  // == f0
    EXPECT_NE(validateFalloff(p), "");
    EXPECT_EQ(validateFalloff(kDefault), "");
}

// Fig. 24: a gentle slope at the control point blends two shapes with a wider neck.
TEST(Falloff, GentleSlopeBlendsWithWiderNeck) {
    auto neckRadius = [](double slope) {
        FalloffParams p = kDefault;
        p.controlSlope = slope;
        const HermiteFalloff F(p);
        // Two unit-support skeletons 1.2 apart; the mid-plane is at u0 = 0.6 from each.
        auto field = [&](double r) { return 2 * F.value(std::sqrt(0.36 + r * r)); };
        if (field(0) <= 0.5) return 0.0;
        double lo = 0, hi = 1;
        for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi);
            (field(mid) > 0.5 ? lo : hi) = mid;
        }
        return lo;
    };
    const double gentle = neckRadius(-0.5), sharp = neckRadius(-2.8);
    EXPECT_GT(gentle, sharp + 0.05) << gentle << " vs " << sharp;
}

// Each level stretches F horizontally: F_k(d) = F(d / R_k), and L_k = R_k / R_4.
TEST(Falloff, ScalingLawPerLevel) {
    Sculpture s(vsculpt::test::emptyConfig(PlacementMode::Thesis));
    const ToolLevels& lv = s.levels();
    const HermiteFalloff& F = lv.falloff();
    for (int k = 1; k <= kLevelCount; ++k) {
        Sculpture one(vsculpt::test::emptyConfig(PlacementMode::Thesis));
        one.store().set(k, LatticeCoord{0, 0, 0}, 1.0f);
        FieldProbe probe(one);
        const ToolLevel& l = lv.level(k);
        EXPECT_NEAR(l.scale, l.supportMm / lv.level(4).supportMm, 1e-12);
        for (double d4 : {0.0, 0.1, 0.3, 0.5, 0.8, 0.99}) {
            // Distance d4 * R_4 at level 4 corresponds to d4 * R_4 * L_k at level k.
            const double d = d4 * lv.level(4).supportMm * l.scale;
            EXPECT_NEAR(probe.rawSum(Vec3(d, 0, 0)), F.value(d4), 1e-12) << "level " << k;
        }
        EXPECT_EQ(probe.rawSum(Vec3(l.supportMm * 1.0001, 0, 0)), 0.0);
    }
}

}  // namespace
