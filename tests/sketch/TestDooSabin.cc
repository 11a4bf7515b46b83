#include "vsculpt/sketch/Chaikin.h"
#include "vsculpt/sketch/DooSabin.h"
#include "vsculpt/sketch/Prism.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

PolyMesh cube() {
    PolyMesh c;
    for (int i = 0; i < 8; ++i)
        c.vertices.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    c.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return c;
}

const Polyline2 kConcaveHexagon{{0, 0}, {4, 0}, {4, 1}, {1.5, 1.2}, {1, 3}, {0, 3}};

TEST(DooSabin, CountsFollowTheEdgeCountAndEulerIsKept) {
    for (const PolyMesh& input :
         {cube(), sweepPrism(kConcaveHexagon, Axis::Z, -2, 2), dooSabin(cube(), 1)}) {
        PolyMesh mesh = input;
        for (int level = 0; level < 3; ++level) {
            const long v = long(mesh.vertices.size());
            const long e = long(countEdges(mesh));
            const long f = long(mesh.faces.size());
            const PolyMesh next = dooSabin(mesh, 1);
            EXPECT_EQ(long(next.vertices.size()), 2 * e);
            EXPECT_EQ(long(countEdges(next)), 4 * e);
            EXPECT_EQ(long(next.faces.size()), f + e + v);
            EXPECT_EQ(eulerCharacteristic(next), eulerCharacteristic(mesh));
            EXPECT_TRUE(isClosedOriented(next));
            // Every new vertex has valence 4 (one F-face, two E-faces, one V-face).
            std::vector<int> valence(next.vertices.size(), 0);
            for (const auto& face : next.faces)
                for (int i : face)
                    ++valence[i];
            for (int val : valence)
                EXPECT_EQ(val, 4);
            mesh = next;
        }
    }
}

TEST(DooSabin, HexagonalPrismCounts) {
    const Polyline2 hexagon{{2, 0}, {1, 1.7}, {-1, 1.7}, {-2, 0}, {-1, -1.7}, {1, -1.7}};
    const PolyMesh prism = sweepPrism(hexagon, Axis::Z, 0, 1);
    const PolyMesh one = dooSabin(prism, 1);
    const PolyMesh two = dooSabin(prism, 2);
    EXPECT_EQ(one.vertices.size(), 36u);
    EXPECT_EQ(countEdges(one), 72u);
    EXPECT_EQ(one.faces.size(), 38u);
    EXPECT_EQ(two.vertices.size(), 144u);
    EXPECT_EQ(countEdges(two), 288u);
    EXPECT_EQ(two.faces.size(), 146u);
}

TEST(DooSabin, CubeVolumeSequenceMatchesReference) {
    // [−1,1]³ with the classic weights. Levels 0 and 1 have planar faces only, so their volume
    // is unambiguous: 8 and 17/3 (5.666667 in the seeds001_003 report, 001-4 #4). From level 2
    // on, E- and V-faces are not planar and the volume of a fan triangulation depends on the
    // fan's start vertex by up to ~1/32 (the report's 5.208333 at level 2 is one such choice);
    // by level 6 the faces are nearly flat and every triangulation agrees with the report's
    // 5.033689 to within 1e-5.
    EXPECT_DOUBLE_EQ(enclosedVolume(dooSabin(cube(), 0)), 8.0);
    EXPECT_NEAR(enclosedVolume(dooSabin(cube(), 1)), 17.0 / 3.0, 1e-12);
    double previous = 17.0 / 3.0;
    for (int k = 2; k <= 6; ++k) {
        const double volume = enclosedVolume(dooSabin(cube(), k));
        EXPECT_LT(volume, previous) << "level " << k;  // corner cutting only removes material
        previous = volume;
    }
    EXPECT_NEAR(previous, 5.033689, 1e-5);
}

TEST(DooSabin, CubeLimitTouchesFaceCentresAndStaysInside) {
    const PolyMesh fine = dooSabin(cube(), 6);
    double minRadius = std::numeric_limits<double>::max(), maxRadius = 0;
    for (const auto& p : fine.vertices) {
        minRadius = std::min(minRadius, glm::length(p));
        maxRadius = std::max(maxRadius, glm::length(p));
    }
    EXPECT_NEAR(minRadius, 1.0, 1e-3);
    // The limit of the cube lies strictly inside the cube (radius < √3).
    EXPECT_LT(maxRadius, 1.16);
}

TEST(DooSabin, MirrorSymmetricInputGivesSymmetricOutput) {
    const PolyMesh fine =
        dooSabin(sweepPrism({{0, 0}, {3, 1}, {0, 2}, {-3, 1}}, Axis::Y, -1, 1), 3);
    for (const auto& p : fine.vertices) {
        double best = std::numeric_limits<double>::max();
        for (const auto& q : fine.vertices)
            best = std::min(best, glm::length(q - glm::dvec3(-p.x, p.y, p.z)));
        EXPECT_LT(best, 1e-12);
    }
}

TEST(DooSabin, PrismMidPlaneSliceIsTheChaikinPolygonExactly) {
    // The paper's lemma: the central band of a subdivided prism joins two rings with identical
    // section coordinates, and those rings are the Chaikin polygon of the section.
    for (Axis axis : {Axis::X, Axis::Y, Axis::Z}) {
        const PolyMesh prism = sweepPrism(kConcaveHexagon, axis, -2, 2);
        for (int k = 1; k <= 4; ++k) {
            const PolyMesh fine = dooSabin(prism, k);
            const Polyline2 expected = chaikin(kConcaveHexagon, k);
            // The ring just above the mid-plane (w > 0 nearest to it) and the one below.
            double lowestAbove = std::numeric_limits<double>::max();
            for (const auto& p : fine.vertices) {
                const double w = axis == Axis::X ? p.x : axis == Axis::Y ? p.y : p.z;
                if (w > 0) lowestAbove = std::min(lowestAbove, w);
            }
            std::vector<glm::dvec2> above, below;
            for (const auto& p : fine.vertices) {
                const double w = axis == Axis::X ? p.x : axis == Axis::Y ? p.y : p.z;
                if (std::abs(w - lowestAbove) < 1e-12) above.push_back(worldToSection(axis, p));
                if (std::abs(w + lowestAbove) < 1e-12) below.push_back(worldToSection(axis, p));
            }
            ASSERT_EQ(above.size(), expected.size()) << "level " << k;
            ASSERT_EQ(below.size(), expected.size()) << "level " << k;
            for (const auto* ring : {&above, &below})
                for (const auto& q : expected) {
                    double best = std::numeric_limits<double>::max();
                    for (const auto& p : *ring)
                        best = std::min(best, glm::length(p - q));
                    EXPECT_LT(best, 1e-9) << "level " << k;
                }
        }
    }
}

TEST(DooSabin, BadInputThrows) {
    PolyMesh open = cube();
    open.faces.pop_back();
    EXPECT_THROW(dooSabin(open, 1), std::invalid_argument);
    EXPECT_THROW(dooSabin(cube(), -1), std::invalid_argument);
    PolyMesh nan = cube();
    nan.vertices[3].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(dooSabin(nan, 1), std::invalid_argument);
    PolyMesh stray = cube();
    stray.vertices.push_back({5, 5, 5});
    EXPECT_THROW(dooSabin(stray, 1), std::invalid_argument);
    EXPECT_THROW(dooSabin(PolyMesh{}, 1), std::invalid_argument);
    // Two cubes sharing one corner: closed and oriented, but that vertex is not manifold.
    PolyMesh twin = cube();
    const PolyMesh other = cube();
    for (int i = 1; i < 8; ++i)
        twin.vertices.push_back(other.vertices[i] + glm::dvec3(2, 2, 2));
    for (auto face : other.faces) {
        for (int& i : face)
            i = (i == 0) ? 7 : 8 + (i - 1);  // other's corner 0 is cube's 7
        twin.faces.push_back(face);
    }
    ASSERT_TRUE(isClosedOriented(twin));
    EXPECT_THROW(dooSabin(twin, 1), std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
