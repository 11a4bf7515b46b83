#include "vsculpt/sketch/Chaikin.h"
#include "vsculpt/sketch/DooSabin.h"
#include "vsculpt/sketch/StackSections.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

Polyline2 regular(int n, double radius, double phase = 0) {
    Polyline2 out;
    for (int i = 0; i < n; ++i) {
        const double t = phase + 2 * std::numbers::pi * i / n;
        out.push_back({radius * std::cos(t), radius * std::sin(t)});
    }
    return out;
}

TEST(PrismStack, EqualCountsGiveQuadsOnly) {
    const PolyMesh mesh = stackSections({{regular(6, 2), 0, 0.5}, {regular(6, 1.5), 2, 0.5}});
    EXPECT_TRUE(isClosedOriented(mesh));
    EXPECT_EQ(eulerCharacteristic(mesh), 2);
    EXPECT_EQ(mesh.vertices.size(), 24u);
    // 6 + 6 prism sides, 6 band quads, 2 caps.
    EXPECT_EQ(mesh.faces.size(), 20u);
    for (std::size_t f = 0; f + 2 < mesh.faces.size(); ++f)
        EXPECT_TRUE(mesh.faces[f].size() == 4u || mesh.faces[f].size() == 6u);
}

TEST(PrismStack, SectorCorrespondenceCoversEveryVertexOnce) {
    // Square against a rotated octagon: two octagon vertices per square sector.
    const auto runs = sectorCorrespondence(regular(4, 1), regular(8, 2, 0.1));
    ASSERT_EQ(runs.size(), 4u);
    int total = 0;
    for (std::size_t i = 0; i < runs.size(); ++i) {
        EXPECT_GE(runs[i].count, 1);
        EXPECT_EQ(runs[(i + 1) % runs.size()].first, (runs[i].first + runs[i].count) % 8);
        total += runs[i].count;
    }
    EXPECT_EQ(total, 8);
    // A triangle whose vertex directions leave a sector of the hexagon-like ring empty: the
    // ring's vertices crowd on one side, the empty sector borrows from the denser neighbour.
    const Polyline2 triangle{{1, 0}, {-0.5, 0.9}, {-0.5, -0.9}};
    Polyline2 crowded;
    for (double t : {-0.6, -0.3, 0.0, 0.3, 0.6, 3.0})
        crowded.push_back({std::cos(t) * 2, std::sin(t) * 2});
    const auto borrowed = sectorCorrespondence(triangle, crowded);
    int sum = 0;
    for (const auto& run : borrowed) {
        EXPECT_GE(run.count, 1);
        sum += run.count;
    }
    EXPECT_EQ(sum, 6);
}

TEST(PrismStack, DifferentVertexCountsStayClosedAndKeepEachSection) {
    const Polyline2 square = regular(4, 2, 0.3);
    const Polyline2 octagon = regular(8, 1.5);
    const Polyline2 pentagon = regular(5, 1.0, 0.2);
    const std::vector<StackedSection> stack{
        {square, 0, 0.5}, {octagon, 2, 0.4}, {pentagon, 4, 0.3}};
    const PolyMesh mesh = stackSections(stack);
    ASSERT_TRUE(isClosedOriented(mesh));
    EXPECT_EQ(eulerCharacteristic(mesh), 2);
    for (int level = 1; level <= 3; ++level) {
        const PolyMesh fine = dooSabin(mesh, level);
        EXPECT_TRUE(isClosedOriented(fine));
        // Each prism's mid-band keeps its section: the ring just above z_k is Chaikin^level.
        for (const auto& section : stack) {
            double above = std::numeric_limits<double>::max();
            for (const auto& p : fine.vertices)
                if (p.z > section.z && p.z < section.z + section.halfHeight)
                    above = std::min(above, p.z);
            std::vector<glm::dvec2> ring;
            for (const auto& p : fine.vertices)
                if (std::abs(p.z - above) < 1e-12) ring.push_back({p.x, p.y});
            const Polyline2 expected = chaikin(section.polygon, level);
            ASSERT_EQ(ring.size(), expected.size()) << "level " << level << " z " << section.z;
            for (const auto& q : expected) {
                double best = std::numeric_limits<double>::max();
                for (const auto& p : ring)
                    best = std::min(best, glm::length(p - q));
                EXPECT_LT(best, 1e-9);
            }
        }
    }
}

TEST(PrismStack, BadInputThrows) {
    EXPECT_THROW(stackSections({}), std::invalid_argument);
    EXPECT_THROW(stackSections({{regular(4, 1), 0, 0}}), std::invalid_argument);
    EXPECT_THROW(stackSections({{regular(4, 1), 0, 1}, {regular(5, 1), 1.5, 1}}),
                 std::invalid_argument);
    EXPECT_THROW(sectorCorrespondence(regular(8, 1), regular(4, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
