// SPDX-License-Identifier: MIT
#include "vsculpt/core/SweptVertices.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

using namespace vsculpt::core;

namespace {

std::set<LatticeCoord> bruteForce(double h, const Vec3& a, const Vec3& b, double r) {
    std::set<LatticeCoord> out;
    const Vec3 lo = glm::floor((glm::min(a, b) - Vec3(r)) / h) - Vec3(1);
    const Vec3 hi = glm::ceil((glm::max(a, b) + Vec3(r)) / h) + Vec3(1);
    for (int i = int(lo.x); i <= int(hi.x); ++i)
        for (int j = int(lo.y); j <= int(hi.y); ++j)
            for (int k = int(lo.z); k <= int(hi.z); ++k)
                if (distanceToSegment(Vec3(i, j, k) * h, a, b) <= r * (1 + 1e-9))
                    out.insert(LatticeCoord{i, j, k});
    return out;
}

TEST(SweptVertices, MatchesBruteForceOnRandomCapsules) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-30, 30), R(0.5, 6), H(0.7, 3);
    for (int t = 0; t < 200; ++t) {
        const double h = H(rng), r = R(rng);
        const Vec3 a(U(rng), U(rng), U(rng));
        // Short and long segments, including a point (a == b).
        const Vec3 b = t % 5 == 0 ? a : a + Vec3(U(rng), U(rng), U(rng)) * (t % 2 ? 0.1 : 1.0);
        const auto got = sweptVertices(h, a, b, r);
        const auto want = bruteForce(h, a, b, r);
        ASSERT_EQ(got.size(), want.size()) << "case " << t;
        size_t i = 0;
        for (const LatticeCoord& c : want) {
            ASSERT_EQ(got[i].coord, c) << "case " << t;  // sorted, each once
            const double d = distanceToSegment(Vec3(c.x, c.y, c.z) * h, a, b);
            EXPECT_NEAR(got[i].lateralMm, std::min(d, r), 1e-9);
            ++i;
        }
    }
}

TEST(SweptVertices, BoundaryVerticesCountAsInside) {
    // A sphere of radius h centred on a vertex holds that vertex and its 6 face neighbours.
    const auto v = sweptVertices(2.0, Vec3(0), Vec3(0), 2.0);
    EXPECT_EQ(v.size(), 7u);
}

}  // namespace
