// SPDX-License-Identifier: MIT
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/render/RayTrace.h"

#include "TestScene.h"

#include <gtest/gtest.h>

#include <random>

using namespace vsculpt;
using namespace vsculpt::render;
using core::Vec3;

namespace {

using vsculpt::test::sculptureMesh;

TEST(RayTrace, PrimaryHitsLieOnTheMesh) {
    const core::Mesh mesh = sculptureMesh();
    const RayScene scene(mesh);
    std::mt19937 rng(3);
    std::normal_distribution<double> N(0, 1);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 origin = glm::normalize(Vec3(N(rng), N(rng), N(rng))) * 200.0;
        // A target inside the initial sphere (radius 30): every ray must hit.
        const Vec3 target =
            glm::normalize(Vec3(N(rng), N(rng), N(rng))) * (25.0 * std::abs(std::tanh(N(rng))));
        const auto hit = scene.intersect(origin, target - origin);
        if (!hit) continue;
        ++hits;
        // On the plane of the triangle it reports, inside it (barycentric), at the distance t.
        const Vec3 a = mesh.positions[mesh.indices[3 * hit->triangle]];
        const Vec3 b = mesh.positions[mesh.indices[3 * hit->triangle + 1]];
        const Vec3 c = mesh.positions[mesh.indices[3 * hit->triangle + 2]];
        const Vec3 n = glm::normalize(glm::cross(b - a, c - a));
        EXPECT_LT(std::abs(glm::dot(hit->position - a, n)), 1e-3);
        const double area = glm::length(glm::cross(b - a, c - a));
        const double u = glm::length(glm::cross(c - b, hit->position - b)) / area;
        const double v = glm::length(glm::cross(a - c, hit->position - c)) / area;
        const double w = glm::length(glm::cross(b - a, hit->position - a)) / area;
        EXPECT_NEAR(u + v + w, 1.0, 1e-3);
        // Nothing nearer: the segment up to just before the hit is free.
        EXPECT_FALSE(scene.occluded(origin, target - origin, 0, hit->t - 1e-2));
        EXPECT_GT(glm::dot(hit->normal, origin - hit->position), 0);
    }
    EXPECT_EQ(hits, 2000);
}

TEST(RayTrace, StillsAreDeterministicAndShaded) {
    const core::Mesh mesh = sculptureMesh();
    RayTraceOptions o;
    o.width = 160;
    o.height = 120;
    o.aoSamples = 8;
    o.shadowSamples = 4;
    const Image a = rayTrace(mesh, o), b = rayTrace(mesh, o);
    EXPECT_EQ(a.rgba, b.rgba);
    // Occlusion darkens the creases: the sculpture is not one flat grey.
    int lo = 255, hi = 0, fg = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const uint8_t* p = a.pixel(x, y);
            if (p[0] == kBackground[0] && p[1] == kBackground[1]) continue;
            ++fg;
            lo = std::min<int>(lo, p[0]);
            hi = std::max<int>(hi, p[0]);
        }
    EXPECT_GT(fg, a.width * a.height / 12);
    EXPECT_GT(hi - lo, 60);
}

}  // namespace
