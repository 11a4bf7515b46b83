#include "vsculpt/sketch/Chaikin.h"
#include "vsculpt/sketch/DooSabin.h"
#include "vsculpt/sketch/Prism.h"
#include "vsculpt/sketch/ThreeSection.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = std::numbers::pi;

// Synthetic mirror-symmetric solid: half-length 3 (x), half-width 1.5 (y), top 2 (z > 0) and a
// hidden bottom at −1.5 that the sketch only shows down to part of it.
SurfaceLines syntheticLines() {
    SurfaceLines lines;
    const int n = 60;
    for (int i = 0; i <= n; ++i) {
        const double t = kPi * i / n;
        lines.back.push_back({3 * std::cos(t), 2 * std::sin(t)});       // (a) over the top
        lines.torso.push_back({3 * std::cos(t), 1.5 * std::sin(t)});    // (b) plan half
        lines.bottom.push_back({3 * std::cos(t), -0.7 * std::sin(t)});  // (d) unscaled depth
    }
    // (c) from the top down past the widest point to z = −0.6 on the lower half-ellipse.
    for (int i = 0; i <= n; ++i) {
        const double phi = (kPi / 2 + 0.41) * i / n;
        const double z = phi <= kPi / 2 ? 2 * std::cos(phi) : 1.5 * std::cos(phi);
        lines.belly.push_back({1.5 * std::sin(phi), z});
    }
    // L4 = 2/1·0.5 = 1, h4 = (0.5 + 1)/0.5·0.5 = 1.5.
    lines.L1 = 2;
    lines.L2 = 1;
    lines.L3 = 0.5;
    lines.h3 = 0.5;
    return lines;
}

bool insidePolygon(const Polyline2& polygon, const glm::dvec2& p) {
    bool inside = false;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
        const glm::dvec2 a = polygon[i], b = polygon[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y))
            inside = !inside;
    }
    return inside;
}

double distanceToPolygon(const Polyline2& polygon, const glm::dvec2& p) {
    double best = 1e300;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        const double t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
        best = std::min(best, glm::length(p - (a + t * (b - a))));
    }
    return best;
}

// True when the projection of the closed mesh along `axis` covers p (p inside some projected
// face; faces are fan-triangulated, fine for the convex faces of convex sections).
bool silhouetteCovers(const PolyMesh& mesh, Axis axis, const glm::dvec2& p) {
    for (const auto& face : mesh.faces) {
        const glm::dvec2 a = worldToSection(axis, mesh.vertices[face[0]]);
        for (std::size_t i = 1; i + 1 < face.size(); ++i) {
            const glm::dvec2 b = worldToSection(axis, mesh.vertices[face[i]]);
            const glm::dvec2 c = worldToSection(axis, mesh.vertices[face[i + 1]]);
            auto side = [&](glm::dvec2 u, glm::dvec2 v) {
                return (v.x - u.x) * (p.y - u.y) - (v.y - u.y) * (p.x - u.x);
            };
            const double s1 = side(a, b), s2 = side(b, c), s3 = side(c, a);
            if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)) {
                if (std::abs(s1) + std::abs(s2) + std::abs(s3) > 0) return true;
            }
        }
    }
    return false;
}

// Compares the mesh's silhouette along `axis` with `polygon` on a grid, skipping points within
// `band` of the polygon outline; returns the number of disagreeing grid points.
int silhouetteMismatches(const PolyMesh& mesh, Axis axis, const Polyline2& polygon, double band) {
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& p : polygon) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    int mismatches = 0;
    const int n = 40;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const glm::dvec2 p =
                lo - 0.2 * (hi - lo) + 1.4 * (hi - lo) * glm::dvec2(i, j) / double(n);
            if (distanceToPolygon(polygon, p) < band) continue;
            if (insidePolygon(polygon, p) != silhouetteCovers(mesh, axis, p)) ++mismatches;
        }
    return mismatches;
}

TEST(ThreeSection, HiddenBottomEstimate) {
    const HiddenBottom b = estimateHiddenBottom(2, 1, 3, 1);
    EXPECT_DOUBLE_EQ(b.L4, 6.0);
    EXPECT_DOUBLE_EQ(b.h4, 3.0);
    EXPECT_THROW(estimateHiddenBottom(2, 0, 3, 1), std::invalid_argument);
    EXPECT_THROW(estimateHiddenBottom(2, 1, std::nan(""), 1), std::invalid_argument);
}

TEST(ThreeSection, SectionsAreSymmetricAndReachTheHiddenBottom) {
    const ThreeSections s = buildSections(syntheticLines());
    EXPECT_DOUBLE_EQ(s.bottom.h4, 1.5);
    // The z-section (x, y) is symmetric in y, the x-section (y, z) in y as well (its first).
    auto symmetric = [](const Polyline2& polygon, bool mirrorSecond) {
        for (const auto& p : polygon) {
            const glm::dvec2 m = mirrorSecond ? glm::dvec2(p.x, -p.y) : glm::dvec2(-p.x, p.y);
            double best = 1e300;
            for (const auto& q : polygon)
                best = std::min(best, glm::length(q - m));
            if (best > 1e-12) return false;
        }
        return true;
    };
    EXPECT_TRUE(symmetric(s.z, true));
    EXPECT_TRUE(symmetric(s.x, false));
    // The natural spline closes the x-section through (0, −h4); the y-section bottom is −h4.
    double closest = 1e300, lowest = 0;
    for (const auto& p : s.x)
        closest = std::min(closest, glm::length(p - glm::dvec2(0, -1.5)));
    for (const auto& p : s.y)
        lowest = std::min(lowest, p.y);
    EXPECT_LT(closest, 1e-12);
    EXPECT_NEAR(lowest, -1.5, 1e-12);
    for (const auto* section : {&s.z, &s.x, &s.y})
        EXPECT_NO_THROW(requireSimplePolygon(*section, "test"));
}

TEST(ThreeSection, ControlMeshIsClosedSymmetricAndMatchesEachSilhouette) {
    const ThreeSectionSolid solid = reconstructThreeSections(syntheticLines());
    const PolyMesh& mesh = solid.controlMesh;
    ASSERT_TRUE(isClosedOriented(mesh));
    EXPECT_EQ(eulerCharacteristic(mesh), 2);
    // Merged facets: no two faces sharing an edge lie in one plane, and no vertex has
    // valence 2.
    std::vector<glm::dvec3> normals;
    for (const auto& face : mesh.faces) {
        glm::dvec3 n(0.0);  // Newell normal
        for (std::size_t i = 0; i < face.size(); ++i) {
            const auto& a = mesh.vertices[face[i]];
            const auto& b = mesh.vertices[face[(i + 1) % face.size()]];
            n += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                            (a.x - b.x) * (a.y + b.y));
        }
        normals.push_back(glm::normalize(n));
    }
    std::map<std::pair<int, int>, int> edgeFace;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        for (std::size_t i = 0; i < mesh.faces[f].size(); ++i)
            edgeFace[{mesh.faces[f][i], mesh.faces[f][(i + 1) % mesh.faces[f].size()]}] = int(f);
    for (const auto& [edge, f] : edgeFace) {
        const int g = edgeFace.at({edge.second, edge.first});
        EXPECT_LT(glm::dot(normals[f], normals[g]), 1 - 1e-9) << "faces " << f << ", " << g;
    }
    std::vector<int> valence(mesh.vertices.size(), 0);
    for (const auto& face : mesh.faces)
        for (int v : face)
            ++valence[v];
    for (int v : valence)
        EXPECT_GE(v, 3);
    EXPECT_GT(enclosedVolume(mesh), 0);
    // Symmetric under y → −y.
    for (const auto& p : mesh.vertices) {
        double best = 1e300;
        for (const auto& q : mesh.vertices)
            best = std::min(best, glm::length(q - glm::dvec3(p.x, -p.y, p.z)));
        EXPECT_LT(best, 1e-9);
    }
    // Silhouettes along z, x and y equal the section polygons (these sections are widest on
    // the coordinate planes, so every prism's slice contains the axis).
    const Axis axes[3] = {Axis::Z, Axis::X, Axis::Y};
    for (int k = 0; k < 3; ++k)
        EXPECT_EQ(silhouetteMismatches(mesh, axes[k], solid.polygons[k], 1e-6), 0) << "axis " << k;
    // The subdivided surface stays closed and symmetric.
    const PolyMesh surface = dooSabin(mesh, 2);
    EXPECT_TRUE(isClosedOriented(surface));
    EXPECT_EQ(eulerCharacteristic(surface), 2);
}

TEST(ThreeSection, EditingOneSurfaceLineChangesOnlyItsSection) {
    const SurfaceLines original = syntheticLines();
    SurfaceLines edited = original;
    // A flatter top on the belly line (the seed's Fig. 2 example).
    for (auto& p : edited.belly)
        if (p.y > 0) p.y = 2 * std::pow(std::max(p.y / 2, 0.0), 0.4);
    const ThreeSectionSolid a = reconstructThreeSections(original);
    const ThreeSectionSolid b = reconstructThreeSections(edited);
    EXPECT_EQ(a.sections.z, b.sections.z);
    EXPECT_EQ(a.sections.y, b.sections.y);
    EXPECT_NE(a.sections.x, b.sections.x);
    EXPECT_EQ(a.polygons[0], b.polygons[0]);
    EXPECT_EQ(a.polygons[2], b.polygons[2]);
    EXPECT_TRUE(isClosedOriented(b.controlMesh));
    // The x silhouette follows the new section; the others are unchanged.
    EXPECT_EQ(silhouetteMismatches(b.controlMesh, Axis::X, b.polygons[1], 1e-6), 0);
    EXPECT_EQ(silhouetteMismatches(b.controlMesh, Axis::Z, b.polygons[0], 1e-6), 0);
    // Deterministic: the same input gives the same mesh, bit for bit.
    const ThreeSectionSolid again = reconstructThreeSections(edited);
    EXPECT_EQ(again.controlMesh.vertices, b.controlMesh.vertices);
    EXPECT_EQ(again.controlMesh.faces, b.controlMesh.faces);
}

TEST(ThreeSection, BadInputThrows) {
    SurfaceLines lines = syntheticLines();
    lines.torso = {{0, 0}};
    EXPECT_THROW(buildSections(lines), std::invalid_argument);
    lines = syntheticLines();
    lines.back[3].x = std::nan("");
    EXPECT_THROW(buildSections(lines), std::invalid_argument);
    lines = syntheticLines();
    lines.h3 = -1;
    EXPECT_THROW(buildSections(lines), std::invalid_argument);
    PolyMesh open = sweepPrism({{0, 0}, {1, 0}, {0, 1}}, Axis::Z, 0, 1);
    open.faces.pop_back();
    EXPECT_THROW(intersectSolids({open}), std::invalid_argument);
    // Disjoint solids: empty intersection.
    EXPECT_THROW(intersectSolids({sweepPrism({{0, 0}, {1, 0}, {0, 1}}, Axis::Z, 0, 1),
                                  sweepPrism({{5, 5}, {6, 5}, {5, 6}}, Axis::Z, 0, 1)}),
                 std::runtime_error);
}

}  // namespace
}  // namespace vsculpt::sketch
