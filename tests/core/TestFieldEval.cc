// SPDX-License-Identifier: MIT
#include "vsculpt/core/EvalField.h"

#include "TestHelpers.h"

#include <gtest/gtest.h>

#include <random>
#include <thread>

using namespace vsculpt::core;
using vsculpt::test::emptyConfig;

namespace {

/// A sculpture with `n` random skeletons spread over all levels and both signs, clustered so
/// that their supports overlap (the interesting case), plus the initial sphere.
Sculpture randomSculpture(size_t n, unsigned seed) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 25;
    Sculpture s(cfg);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> level(1, kLevelCount);
    std::normal_distribution<double> pos(0, 30);
    std::uniform_real_distribution<double> w(-1.5, 2.0);
    while (s.store().vertexCount() < n) {
        const int k = level(rng);
        const double h = s.levels().level(k).spacingMm;
        const LatticeCoord c{int(std::lround(pos(rng) / h)), int(std::lround(pos(rng) / h)),
                             int(std::lround(pos(rng) / h))};
        s.store().set(k, c, float(w(rng)));
    }
    return s;
}

std::vector<Vec3> randomPoints(size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> pos(0, 35);
    std::vector<Vec3> p(n);
    for (auto& v : p)
        v = Vec3(pos(rng), pos(rng), pos(rng));
    p.push_back(Vec3(1e4, 0, 0));  // far from everything
    p.push_back(Vec3(0));
    return p;
}

TEST(FieldEval, AcceleratedEqualsBruteForce) {
    for (size_t n : {10u, 100u, 1000u, 5000u}) {
        const Sculpture s = randomSculpture(n, unsigned(n));
        FieldProbe probe(s);
        for (const Vec3& p : randomPoints(400, 99)) {
            const FieldSample fast = probe.sample(p), ref = evalFieldBruteForce(s, p);
            ASSERT_NEAR(fast.value, ref.value, 1e-9) << n << " skeletons at " << p.x;
            ASSERT_NEAR(probe.value(p), ref.value, 1e-9);
            for (int a = 0; a < 3; ++a)
                ASSERT_NEAR(fast.gradient[a], ref.gradient[a], 1e-9);
        }
    }
}

TEST(FieldEval, GradientEqualsFiniteDifferences) {
    const Sculpture s = randomSculpture(2000, 3);
    FieldProbe probe(s);
    const double e = 1e-5;
    for (const Vec3& p : randomPoints(300, 4)) {
        const Vec3 g = probe.sample(p).gradient;
        for (int a = 0; a < 3; ++a) {
            Vec3 d(0);
            d[a] = e;
            const double fd = (probe.value(p + d) - probe.value(p - d)) / (2 * e);
            ASSERT_NEAR(g[a], fd, 1e-5 * (1 + std::abs(fd))) << "axis " << a;
        }
    }
}

TEST(FieldEval, BatchFromManyThreadsEqualsSinglePoint) {
    const Sculpture s = randomSculpture(3000, 8);
    const auto pts = randomPoints(4000, 9);
    std::vector<double> single(pts.size());
    {
        FieldProbe probe(s);
        for (size_t i = 0; i < pts.size(); ++i)
            single[i] = probe.value(pts[i]);
    }
    std::vector<double> values(pts.size());
    std::vector<Vec3> grads(pts.size());
    std::vector<std::thread> threads;
    const size_t kThreads = 4, chunk = (pts.size() + kThreads - 1) / kThreads;
    for (size_t t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            const size_t b = t * chunk, e = std::min(pts.size(), b + chunk);
            evalFieldBatch(s, std::span(pts).subspan(b, e - b), std::span(values).subspan(b, e - b),
                           std::span(grads).subspan(b, e - b));
        });
    }
    for (auto& th : threads)
        th.join();
    EXPECT_EQ(values, single);
    std::vector<double> small(3);
    EXPECT_THROW(evalFieldBatch(s, pts, small), std::invalid_argument);
}

TEST(FieldEval, InitialSphereIsExact) {
    // The one-skeleton sphere of older projects (core weight 0), the default steep core and
    // another core: the surface lies at the radius either way; the core adds its weight at the
    // centre and steepens the surface by its own slope there.
    double plainSlope = 0;
    for (double coreWeight : {0.0, SculptConfig{}.sphereCoreWeight, 1.0}) {
        SCOPED_TRACE("core weight " + std::to_string(coreWeight));
        SculptConfig cfg = emptyConfig(PlacementMode::Free);
        cfg.sphereRadiusMm = 40;
        cfg.sphereCenterMm = Vec3(5, -3, 2);
        cfg.sphereCoreWeight = coreWeight;
        const Sculpture s(cfg);
        FieldProbe probe(s);
        EXPECT_NEAR(probe.value(cfg.sphereCenterMm), cfg.falloff.f0 * (1 + coreWeight) - cfg.iso,
                    1e-12);
        const HermiteFalloff F(cfg.falloff);
        const double a = cfg.sphereCoreSupportOverRadius;
        const double coreSlope = -coreWeight * F.derivative(1 / a) / (a * 40);
        std::mt19937 rng(1);
        std::normal_distribution<double> N(0, 1);
        for (int i = 0; i < 100; ++i) {
            const Vec3 dir = glm::normalize(Vec3(N(rng), N(rng), N(rng)));
            EXPECT_NEAR(probe.value(cfg.sphereCenterMm + 40.0 * dir), 0.0, 1e-12);
            EXPECT_GT(probe.value(cfg.sphereCenterMm + 39.9 * dir), 0.0);
            EXPECT_LT(probe.value(cfg.sphereCenterMm + 40.1 * dir), 0.0);
            // Outward normal: the gradient points inward (f decreases outward).
            const Vec3 g = probe.sample(cfg.sphereCenterMm + 40.0 * dir).gradient;
            EXPECT_LT(glm::dot(g, dir), 0);
            if (coreWeight == 0) {
                plainSlope = glm::length(g);
            } else {
                // The outer skeleton's support grows a little (its value at the surface is
                // c - core), so its slope there is within 20 % of the plain sphere's.
                EXPECT_GT(glm::length(g), coreSlope + 0.8 * plainSlope);
                EXPECT_LT(glm::length(g), coreSlope + 1.2 * plainSlope);
            }
        }
        if (coreWeight == SculptConfig{}.sphereCoreWeight) {  // 1.87x the plain sphere's slope
            EXPECT_NEAR(glm::length(probe.sample(cfg.sphereCenterMm + Vec3(40, 0, 0)).gradient) /
                            plainSlope,
                        1.87, 0.01);
        }
        EXPECT_EQ(probe.value(Vec3(1000, 0, 0)), -cfg.iso);
        EXPECT_EQ(s.counts().total(), coreWeight > 0 ? 2u : 1u);
    }
}

TEST(FieldEval, ThesisModeKeepsTheThesissOneSkeletonSphere) {
    // Thesis-mode carves read the field inside the sphere: it stays the thesis's, whatever
    // initial_sphere.core_weight says.
    SculptConfig cfg = emptyConfig(PlacementMode::Thesis);
    cfg.sphereRadiusMm = 40;
    ASSERT_GT(cfg.sphereCoreWeight, 0);
    const Sculpture s(cfg);
    EXPECT_EQ(s.counts().point, 1u);
    EXPECT_NEAR(FieldProbe(s).value(Vec3(0.0)), cfg.falloff.f0 - cfg.iso, 1e-12);
    EXPECT_NEAR(FieldProbe(s).value(Vec3(40, 0, 0)), 0.0, 1e-12);
}

TEST(FieldEval, EditsAfterTheProbeWasMadeAreSeen) {
    Sculpture s(emptyConfig(PlacementMode::Thesis));
    FieldProbe probe(s);
    EXPECT_EQ(probe.value(Vec3(0)), -s.levels().iso());
    s.store().set(6, LatticeCoord{0, 0, 0}, 1.0f);
    EXPECT_NEAR(probe.value(Vec3(0)), 1.0 - s.levels().iso(), 1e-12);
    s.store().erase(6, LatticeCoord{0, 0, 0});
    EXPECT_EQ(probe.value(Vec3(0)), -s.levels().iso());
}

}  // namespace
