#include "vsculpt/sketch/CutMesh.h"
#include "vsculpt/sketch/ExtrudeMesh.h"
#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/TeddyInflate.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = std::numbers::pi;

Polyline2 circle(double r, int count, glm::dvec2 centre = {0, 0}) {
    Polyline2 points;
    for (int i = 0; i < count; ++i) {
        const double a = 2 * kPi * i / count + 0.05;
        points.push_back(centre + r * glm::dvec2(std::cos(a), std::sin(a)));
    }
    return points;
}

Polyline2 blob() {
    Polyline2 points;
    for (int i = 0; i < 200; ++i) {
        const double a = 2 * kPi * i / 200;
        const double r = 20 + 5 * std::cos(3 * a) + 3 * std::sin(2 * a + 0.3);
        points.push_back({r * std::cos(a), r * std::sin(a)});
    }
    return points;
}

// Side view: screen (u, v) = world (x, z); the viewer is at −y looking along +y.
SketchView sideView() {
    SketchView view;
    view.right = {1, 0, 0};
    view.up = {0, 0, 1};
    return view;
}

// Distance from p to the region enclosed by the closed polygon (0 inside).
double distanceToRegion(const Polyline2& polygon, const glm::dvec2& p) {
    bool inside = false;
    double best = 1e300;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
        const glm::dvec2 a = polygon[j], b = polygon[i];
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (b.x - a.x) * (p.y - a.y) / (b.y - a.y))
            inside = !inside;
        const double t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
        best = std::min(best, glm::length(p - (a + t * (b - a))));
    }
    return inside ? 0.0 : best;
}

double maxZ(const PolyMesh& mesh) {
    double z = -1e300;
    for (const auto& v : mesh.vertices)
        z = std::max(z, v.z);
    return z;
}

TEST(TeddyExtrude, NewellVectorIsAreaTimesNormal) {
    // A 2 × 3 rectangle in the plane with unit normal (1, 1, 1)/√3.
    const glm::dvec3 n = glm::normalize(glm::dvec3(1, 1, 1));
    const glm::dvec3 a = glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0)));
    const glm::dvec3 b = glm::cross(n, a);
    const glm::dvec3 o{5, -2, 7};
    const Polyline3 rectangle{o, o + 2.0 * a, o + 2.0 * a + 3.0 * b, o + 3.0 * b};
    const glm::dvec3 v = newellNormal(rectangle);
    EXPECT_NEAR(glm::length(v), 6.0, 1e-12);
    EXPECT_NEAR(glm::dot(glm::normalize(v), n), 1.0, 1e-12);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(v[k], 6.0 / std::sqrt(3.0), 1e-12);
}

struct Dome {
    PolyMesh solid = inflateOutline(circle(25, 200), TeddyParams{});
    double top = maxZ(solid);
};

TEST(TeddyExtrude, OutwardSilhouetteGrowsAClosedProtrusion) {
    const Dome s;
    // Base: a circle of radius 6 around the top of the dome, seen from above.
    const Polyline2 base = circle(6, 60);
    // Silhouette seen from the side: up 20 mm and back down, an arch over the base.
    const Polyline2 arch{
        {-6, s.top}, {-5, s.top + 15}, {0, s.top + 20}, {5, s.top + 15}, {6, s.top}};
    const Extrusion e = extrudeMesh(s.solid, base, SketchView{}, arch, sideView(), {});
    EXPECT_TRUE(isClosedOriented(e.mesh));
    EXPECT_EQ(eulerCharacteristic(e.mesh), 2);
    EXPECT_GT(enclosedVolume(e.mesh), enclosedVolume(s.solid));
    // The tip reaches the top of the silhouette (up to one pointer step).
    EXPECT_NEAR(maxZ(e.mesh), s.top + 20, 2.0);
    // The base normal points up out of the dome; the sweep plane faces the side viewer.
    EXPECT_GT(glm::normalize(e.baseNormal).z, 0.95);
    EXPECT_NEAR(std::abs(e.sweepPlaneNormal.y), 1.0, 0.05);
    // The base loop keeps the original vertex positions, and they are on the dome.
    for (int v : e.baseLoop) {
        const glm::dvec3 p = e.mesh.vertices[v];
        const bool original = std::any_of(s.solid.vertices.begin(), s.solid.vertices.end(),
                                          [&](const glm::dvec3& q) { return q == p; });
        EXPECT_TRUE(original);
    }
    // Seen from the side, the swept copies stay inside the region the silhouette encloses
    // (closed by the base line), up to 3% of the stroke's length.
    const double tolerance = 0.03 * length(arch, false);
    const std::set<int> baseLoop(e.baseLoop.begin(), e.baseLoop.end());
    for (std::size_t f = e.firstNewFace; f < e.mesh.faces.size(); ++f)
        for (int v : e.mesh.faces[f]) {
            if (baseLoop.count(v)) continue;
            const glm::dvec3 p = e.mesh.vertices[v];
            EXPECT_LT(distanceToRegion(arch, {p.x, p.z}), tolerance)
                << "copy vertex at x " << p.x << ", z − top " << p.z - s.top;
        }
}

TEST(TeddyExtrude, InwardSilhouetteDigsADent) {
    const Dome s;
    const Polyline2 dip{{-6, s.top}, {-4, s.top - 8}, {0, s.top - 10}, {4, s.top - 8}, {6, s.top}};
    const Extrusion e = extrudeMesh(s.solid, circle(6, 60), SketchView{}, dip, sideView(), {});
    EXPECT_TRUE(isClosedOriented(e.mesh));
    EXPECT_EQ(eulerCharacteristic(e.mesh), 2);
    EXPECT_LT(enclosedVolume(e.mesh), enclosedVolume(s.solid));
}

TEST(TeddyExtrude, ExtrudeFromACutFace) {
    const PolyMesh solid = inflateOutline(blob(), TeddyParams{});
    const MeshCut cut = cutMesh(solid, {{-60, 5}, {60, 5}}, SketchView{});
    std::vector<int> cap;
    for (std::size_t f = cut.firstCapFace; f < cut.mesh.faces.size(); ++f)
        cap.push_back(static_cast<int>(f));
    // The cap faces +y; the top view sees the sweep plane z = 0 face-on.
    double xMin = 1e300, xMax = -1e300;
    for (int v : cut.capLoops[0])
        xMin = std::min(xMin, cut.mesh.vertices[v].x),
        xMax = std::max(xMax, cut.mesh.vertices[v].x);
    const Polyline2 arm{{xMin, 5}, {xMin + 3, 30}, {xMax - 3, 30}, {xMax, 5}};
    const Extrusion e = extrudeRegion(cut.mesh, cap, arm, SketchView{}, {});
    EXPECT_TRUE(isClosedOriented(e.mesh));
    EXPECT_EQ(eulerCharacteristic(e.mesh), 2);
    EXPECT_GT(enclosedVolume(e.mesh), enclosedVolume(cut.mesh));
    double yMax = -1e300;
    for (const auto& v : e.mesh.vertices)
        yMax = std::max(yMax, v.y);
    EXPECT_NEAR(yMax, 30, 2.5);
}

TEST(TeddyExtrude, BadExtrusionsAreRejected) {
    const Dome s;
    const Polyline2 arch{{-6, s.top}, {0, s.top + 20}, {6, s.top}};
    // Looking straight down the base normal.
    EXPECT_THROW(extrudeMesh(s.solid, circle(6, 60), SketchView{}, {{-6, 0}, {0, 5}, {6, 0}},
                             SketchView{}, {}),
                 std::invalid_argument);
    // A base stroke away from the solid encloses nothing.
    EXPECT_THROW(
        extrudeMesh(s.solid, circle(3, 30, {200, 200}), SketchView{}, arch, sideView(), {}),
        std::invalid_argument);
    // A base stroke around the whole dome selects the whole front sheet: still a disk, but a
    // ring-shaped selection (annulus) is not.
    std::vector<int> annulus;
    const std::vector<int> big = facesInsideStroke(s.solid, circle(15, 60), SketchView{});
    const std::vector<int> small = facesInsideStroke(s.solid, circle(5, 60), SketchView{});
    std::set_difference(big.begin(), big.end(), small.begin(), small.end(),
                        std::back_inserter(annulus));
    EXPECT_THROW(extrudeRegion(s.solid, annulus, arch, sideView(), {}), std::invalid_argument);
    EXPECT_THROW(extrudeRegion(s.solid, {}, arch, sideView(), {}), std::invalid_argument);
    EXPECT_THROW(extrudeMesh(s.solid, circle(6, 60), SketchView{}, {{0, 1}}, sideView(), {}),
                 std::invalid_argument);
    ExtrudeParams bad;
    bad.stepLength = -1;
    EXPECT_THROW(extrudeMesh(s.solid, circle(6, 60), SketchView{}, arch, sideView(), bad),
                 std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
