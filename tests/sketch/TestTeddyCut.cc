#include "vsculpt/sketch/CutMesh.h"
#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/TeddyInflate.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = std::numbers::pi;

// Unit icosphere: an icosahedron subdivided `levels` times, vertices pushed onto the sphere.
PolyMesh icosphere(int levels) {
    const double t = (1 + std::sqrt(5.0)) / 2;
    PolyMesh m;
    for (const auto& v : std::vector<glm::dvec3>{{-1, t, 0},
                                                 {1, t, 0},
                                                 {-1, -t, 0},
                                                 {1, -t, 0},
                                                 {0, -1, t},
                                                 {0, 1, t},
                                                 {0, -1, -t},
                                                 {0, 1, -t},
                                                 {t, 0, -1},
                                                 {t, 0, 1},
                                                 {-t, 0, -1},
                                                 {-t, 0, 1}})
        m.vertices.push_back(glm::normalize(v));
    m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
               {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<int, int>, int> mid;
        const auto midpoint = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            const auto [it, fresh] = mid.try_emplace(key, static_cast<int>(m.vertices.size()));
            if (fresh) m.vertices.push_back(glm::normalize(m.vertices[a] + m.vertices[b]));
            return it->second;
        };
        std::vector<std::vector<int>> faces;
        for (const auto& f : m.faces) {
            const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]),
                      ca = midpoint(f[2], f[0]);
            faces.push_back({f[0], ab, ca});
            faces.push_back({f[1], bc, ab});
            faces.push_back({f[2], ca, bc});
            faces.push_back({ab, bc, ca});
        }
        m.faces = std::move(faces);
    }
    return m;
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

// Two discs of radius r centred at (±d, 0) joined by a neck of half-width w.
Polyline2 dumbbell(double r, double d, double w) {
    const double alpha = std::asin(w / r);
    Polyline2 points;
    for (int i = 0; i <= 120; ++i) {
        const double a = -(kPi - alpha) + 2 * (kPi - alpha) * i / 120;
        points.push_back({d + r * std::cos(a), r * std::sin(a)});
    }
    for (int i = 0; i <= 120; ++i) {
        const double a = alpha + 2 * (kPi - alpha) * i / 120;
        points.push_back({-d + r * std::cos(a), r * std::sin(a)});
    }
    return points;
}

void expectValidCut(const MeshCut& cut) {
    EXPECT_TRUE(isClosedOriented(cut.mesh));
    EXPECT_EQ(eulerCharacteristic(cut.mesh), 2);
    ASSERT_LT(cut.firstCapFace, cut.mesh.faces.size());
    const glm::dvec3 n = glm::normalize(cut.plane.normal);
    // Every kept vertex is on the kept side; cap vertices lie on the plane.
    for (const auto& v : cut.mesh.vertices)
        EXPECT_LE(glm::dot(n, v - cut.plane.point), 1e-9);
    for (std::size_t f = cut.firstCapFace; f < cut.mesh.faces.size(); ++f) {
        const auto& face = cut.mesh.faces[f];
        for (int v : face)
            EXPECT_NEAR(glm::dot(n, cut.mesh.vertices[v] - cut.plane.point), 0.0, 1e-9);
        // Flat and facing outward (towards the discarded side).
        const glm::dvec3 a = cut.mesh.vertices[face[0]], b = cut.mesh.vertices[face[1]],
                         c = cut.mesh.vertices[face[2]];
        const glm::dvec3 faceNormal = glm::cross(b - a, c - a);
        ASSERT_GT(glm::length(faceNormal), 0.0);
        EXPECT_NEAR(glm::dot(glm::normalize(faceNormal), n), 1.0, 1e-9);
    }
}

TEST(TeddyCut, SphereCapVolumes) {
    const PolyMesh sphere = icosphere(4);
    for (const double d : {-0.6, -0.2, 0.0, 0.35, 0.7}) {
        SCOPED_TRACE(d);
        // Plane x = d, discarding x > d: the kept part is the sphere minus the cap beyond d.
        const MeshCut cut = cutMeshByPlane(sphere, {{d, 0, 0}, {1, 0, 0}});
        expectValidCut(cut);
        EXPECT_EQ(cut.capLoops.size(), 1u);
        const double capBeyond = kPi * (1 - d) * (1 - d) * (2 + d) / 3;
        const double expected = 4 * kPi / 3 - capBeyond;
        EXPECT_NEAR(enclosedVolume(cut.mesh), expected, 0.03 * expected);
    }
}

TEST(TeddyCut, StrokeAcrossInflatedSolidKeepsRightSide) {
    const PolyMesh solid = inflateOutline(blob(), TeddyParams{});
    // Stroke left to right at y = 5: the right of its direction is y < 5.
    const MeshCut cut = cutMesh(solid, {{-60, 5}, {0, 7}, {60, 5}}, SketchView{});
    expectValidCut(cut);
    EXPECT_EQ(cut.plane.normal, glm::dvec3(0, 1, 0));
    EXPECT_EQ(cut.plane.point, glm::dvec3(-60, 5, 0));
    EXPECT_EQ(cut.capLoops.size(), 1u);
    EXPECT_LT(enclosedVolume(cut.mesh), enclosedVolume(solid));
    EXPECT_GT(enclosedVolume(cut.mesh), 0.0);
    // The cap's mirror symmetry about z = 0 survives: its area-weighted centroid has z ≈ 0.
    double area = 0, zMoment = 0;
    for (std::size_t f = cut.firstCapFace; f < cut.mesh.faces.size(); ++f) {
        const auto& face = cut.mesh.faces[f];
        const glm::dvec3 a = cut.mesh.vertices[face[0]], b = cut.mesh.vertices[face[1]],
                         c = cut.mesh.vertices[face[2]];
        const double faceArea = 0.5 * glm::length(glm::cross(b - a, c - a));
        area += faceArea;
        zMoment += faceArea * (a.z + b.z + c.z) / 3;
    }
    EXPECT_GT(area, 0.0);
    EXPECT_NEAR(zMoment / area, 0.0, 1e-6);
}

TEST(TeddyCut, SectionWithTwoLoopsIsCapped) {
    // A horizontal cut at y = 10 crosses both lobes of a dumbbell but not its neck (half-width
    // 5): two section loops, one kept component.
    const PolyMesh solid = inflateOutline(dumbbell(20, 35, 5), TeddyParams{});
    const MeshCut cut = cutMesh(solid, {{-80, 10}, {80, 10}}, SketchView{});
    expectValidCut(cut);
    EXPECT_EQ(cut.capLoops.size(), 2u);
}

TEST(TeddyCut, CutPlaneContainsTheViewDirection) {
    const PolyMesh solid = inflateOutline(blob(), TeddyParams{});
    // Looking along −x from +x: screen right is world −y... choose right = (0, 0, 1), up = y,
    // so the view direction is −cross(right, up) = (1, 0, 0)… i.e. the viewer sits at −x.
    SketchView side;
    side.right = {0, 0, 1};
    side.up = {0, 1, 0};
    const glm::dvec3 viewDirection = -glm::cross(side.right, side.up);
    const MeshCut cut = cutMesh(solid, {{-50, -40}, {50, 30}}, side);
    expectValidCut(cut);
    EXPECT_NEAR(glm::dot(cut.plane.normal, viewDirection), 0.0, 1e-12);
}

TEST(TeddyCut, BadCutsAreRejected) {
    const PolyMesh solid = inflateOutline(blob(), TeddyParams{});
    const SketchView view;
    EXPECT_THROW(cutMesh(solid, {{0, 0}}, view), std::invalid_argument);
    EXPECT_THROW(cutMesh(solid, {{1, 1}, {5, 5}, {1, 1}}, view), std::invalid_argument);
    EXPECT_THROW(cutMesh(solid, {{0, std::nan("")}, {1, 1}}, view), std::invalid_argument);
    try {
        cutMesh(solid, {{0, 0}, {80, 0}}, view);  // starts at the centre of the solid
        ADD_FAILURE() << "a stroke starting inside the silhouette was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("starts inside"), std::string::npos) << e.what();
    }
    // Misses the solid: everything kept, nothing to cap.
    EXPECT_THROW(cutMesh(solid, {{-80, 60}, {80, 60}}, view), std::invalid_argument);
    // Everything discarded.
    EXPECT_THROW(cutMesh(solid, {{80, 60}, {-80, 60}}, view), std::invalid_argument);
    PolyMesh open = solid;
    open.faces.pop_back();
    EXPECT_THROW(cutMeshByPlane(open, {{0, 0, 0}, {1, 0, 0}}), std::invalid_argument);
    SketchView skew;
    skew.up = {0.5, 1, 0};
    EXPECT_THROW(cutMesh(solid, {{-80, 0}, {80, 0}}, skew), std::invalid_argument);
}

TEST(TeddyCut, PlaneThroughVerticesIsSnappedAndClosed) {
    // The plane x = 0 passes through many icosphere vertices exactly.
    const MeshCut cut = cutMeshByPlane(icosphere(3), {{0, 0, 0}, {1, 0, 0}});
    expectValidCut(cut);
    EXPECT_NEAR(enclosedVolume(cut.mesh), 0.5 * enclosedVolume(icosphere(3)), 1e-9);
}

TEST(TeddyCut, RandomCutsOfInflatedSolidsStayClosed) {
    const PolyMesh solid = inflateOutline(dumbbell(20, 35, 5), TeddyParams{});
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int cuts = 0;
    for (int trial = 0; trial < 20; ++trial) {
        SCOPED_TRACE(trial);
        const double angle = 2 * kPi * unit(random);
        const glm::dvec2 through{-40 + 80 * unit(random), -15 + 30 * unit(random)};
        const glm::dvec2 along{std::cos(angle), std::sin(angle)};
        const Polyline2 stroke{through - 150.0 * along, through + 150.0 * along};
        MeshCut cut;
        try {
            cut = cutMesh(solid, stroke, SketchView{});
        } catch (const std::invalid_argument&) {
            continue;  // the line missed the solid or discarded all of it
        }
        ++cuts;
        EXPECT_TRUE(isClosedOriented(cut.mesh));
        // Genus 0 per kept component: χ = 2 per component (a cut can split the dumbbell).
        const long chi = eulerCharacteristic(cut.mesh);
        EXPECT_TRUE(chi == 2 || chi == 4) << chi;
        EXPECT_GT(enclosedVolume(cut.mesh), 0.0);
        for (const auto& v : cut.mesh.vertices)
            EXPECT_LE(glm::dot(cut.plane.normal, v - cut.plane.point), 1e-9);
    }
    EXPECT_GT(cuts, 10);
}

}  // namespace
}  // namespace vsculpt::sketch
