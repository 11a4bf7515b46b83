#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/TeddyInflate.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = std::numbers::pi;

Polyline2 ellipse(double a, double b, int count, glm::dvec2 center = {0, 0}, double phase = 0.1) {
    Polyline2 points;
    for (int i = 0; i < count; ++i) {
        const double t = phase + 2 * kPi * i / count;
        points.push_back(center + glm::dvec2(a * std::cos(t), b * std::sin(t)));
    }
    return points;
}

// Two discs of radius r centred at (±d, 0) joined by a neck of half-width w.
Polyline2 dumbbell(double r, double d, double w) {
    const double alpha = std::asin(w / r);
    Polyline2 points;
    const int arc = 120;
    for (int i = 0; i <= arc; ++i) {  // right lobe, from the bottom of the neck round to its top
        const double t = -(kPi - alpha) + 2 * (kPi - alpha) * i / arc;
        points.push_back({d + r * std::cos(t), r * std::sin(t)});
    }
    for (int i = 0; i <= arc; ++i) {  // left lobe, from the top of the neck round to its bottom
        const double t = alpha + 2 * (kPi - alpha) * i / arc;
        points.push_back({-d + r * std::cos(t), r * std::sin(t)});
    }
    return points;
}

// A three-armed star: a Y-shaped outline.
Polyline2 threeArms() {
    Polyline2 points;
    const int count = 300;
    for (int i = 0; i < count; ++i) {
        const double t = 2 * kPi * i / count;
        const double r = 12 + 18 * std::pow(std::max(0.0, std::cos(1.5 * t)), 4) +
                         18 * std::pow(std::max(0.0, -std::cos(1.5 * t)), 4);
        points.push_back({r * std::cos(t), r * std::sin(t)});
    }
    return points;
}

// An outline without symmetries, so rigid motions cannot map it onto itself.
Polyline2 blob() {
    Polyline2 points;
    for (int i = 0; i < 200; ++i) {
        const double t = 2 * kPi * i / 200;
        const double r = 20 + 5 * std::cos(3 * t) + 3 * std::sin(2 * t + 0.3);
        points.push_back({r * std::cos(t), r * std::sin(t)});
    }
    return points;
}

struct Shape {
    std::string name;
    Polyline2 outline;
};

std::vector<Shape> shapes() {
    return {{"circle", ellipse(30, 30, 200)},
            {"ellipse", ellipse(40, 10, 200)},
            {"dumbbell", dumbbell(20, 35, 5)},
            {"threeArms", threeArms()},
            {"blob", blob()},
            {"square", {{0, 0}, {40, 0}, {40, 40}, {0, 40}}}};
}

TeddyParams params(double edgeLength = 2.0) {
    TeddyParams p;
    p.edgeLength = edgeLength;
    return p;
}

double maxZ(const PolyMesh& mesh) {
    double z = 0;
    for (const auto& v : mesh.vertices)
        z = std::max(z, v.z);
    return z;
}

bool graphIsTree(const TeddyGraph2& graph) {
    const int n = static_cast<int>(graph.points.size());
    if (n == 0 || graph.edges.size() + 1 != graph.points.size()) return false;
    std::vector<int> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    const auto find = [&](int i) {
        while (parent[i] != i)
            i = parent[i] = parent[parent[i]];
        return i;
    };
    for (const auto& e : graph.edges) {
        const int a = find(e[0]), b = find(e[1]);
        if (a == b) return false;  // a cycle
        parent[a] = b;
    }
    return true;  // n − 1 edges without a cycle: connected
}

double triangleArea2(const std::vector<glm::dvec2>& p, const std::array<int, 3>& t) {
    const glm::dvec2 u = p[t[1]] - p[t[0]], v = p[t[2]] - p[t[0]];
    return 0.5 * (u.x * v.y - u.y * v.x);
}

TEST(TeddyInflate, TerminalsEqualJunctionsPlusTwoAndCdtCoversOutline) {
    for (const auto& shape : shapes()) {
        SCOPED_TRACE(shape.name);
        const TeddyInflation r = inflateOutlineDetailed(shape.outline, params());
        const std::size_t n = r.outline.size();
        ASSERT_EQ(r.cdtTriangles.size(), n - 2);
        double area = 0;
        for (const auto& t : r.cdtTriangles) {
            EXPECT_GT(triangleArea2(r.outline, t), 0.0);
            area += triangleArea2(r.outline, t);
        }
        EXPECT_NEAR(area, signedArea(r.outline), 1e-9 * area);
        const auto count = [&](TeddyTriangleClass c) {
            return std::count(r.classes.begin(), r.classes.end(), c);
        };
        EXPECT_EQ(count(TeddyTriangleClass::Terminal), count(TeddyTriangleClass::Junction) + 2);
        EXPECT_TRUE(graphIsTree(r.chordalAxis));
        EXPECT_TRUE(graphIsTree(r.spine));
        EXPECT_LE(r.spine.points.size(), r.chordalAxis.points.size());
    }
}

TEST(TeddyInflate, ClosedOrientedSphereTopologyWithoutDegenerateTriangles) {
    for (const auto& shape : shapes()) {
        SCOPED_TRACE(shape.name);
        const TeddyInflation r = inflateOutlineDetailed(shape.outline, params());
        const PolyMesh& mesh = r.mesh;
        EXPECT_TRUE(isClosedOriented(mesh));
        EXPECT_EQ(eulerCharacteristic(mesh), 2);
        EXPECT_GT(enclosedVolume(mesh), 0.0);
        double minArea = 1e300;
        for (const auto& f : mesh.faces) {
            ASSERT_EQ(f.size(), 3u);
            const glm::dvec3 a = mesh.vertices[f[0]], b = mesh.vertices[f[1]],
                             c = mesh.vertices[f[2]];
            minArea = std::min(minArea, 0.5 * glm::length(glm::cross(b - a, c - a)));
        }
        EXPECT_GT(minArea, 1e-4);  // mm²; edges are ~2 mm, so this is far from degenerate
        // The flat triangulation is counter-clockwise and tiles the outline.
        double flatArea = 0;
        for (const auto& t : r.flatTriangles) {
            EXPECT_GT(triangleArea2(r.flatVertices, t), 0.0);
            flatArea += triangleArea2(r.flatVertices, t);
        }
        EXPECT_NEAR(flatArea, signedArea(r.outline), 1e-9 * flatArea);
    }
}

TEST(TeddyInflate, MirrorSymmetricAboutCanvasAndOutlineKept) {
    const TeddyInflation r = inflateOutlineDetailed(dumbbell(20, 35, 5), params());
    std::vector<glm::dvec3> vertices = r.mesh.vertices, mirrored = r.mesh.vertices;
    for (auto& v : mirrored)
        v.z = -v.z;
    const auto less = [](const glm::dvec3& a, const glm::dvec3& b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    };
    std::sort(vertices.begin(), vertices.end(), less);
    std::sort(mirrored.begin(), mirrored.end(), less);
    for (std::size_t i = 0; i < vertices.size(); ++i)
        ASSERT_LT(glm::length(vertices[i] - mirrored[i]), 1e-9);
    // The first outline.size() vertices are the outline itself, on the canvas.
    for (std::size_t i = 0; i < r.outline.size(); ++i)
        EXPECT_EQ(r.mesh.vertices[i], glm::dvec3(r.outline[i], 0.0));
    // Both halves enclose the same volume: cut the faces by sheet.
    double front = 0, back = 0;
    for (const auto& f : r.mesh.faces) {
        const glm::dvec3 a = r.mesh.vertices[f[0]], b = r.mesh.vertices[f[1]],
                         c = r.mesh.vertices[f[2]];
        const double v = glm::dot(a, glm::cross(b, c)) / 6;
        (a.z + b.z + c.z > 0 ? front : back) += v;
    }
    EXPECT_NEAR(front, back, 1e-9 * front);
}

TEST(TeddyInflate, CircleInflatesToNearSphere) {
    const double radius = 30;
    const PolyMesh mesh = inflateOutline(ellipse(radius, radius, 300), params(1.5));
    const double sphere = 4.0 / 3.0 * kPi * radius * radius * radius;
    EXPECT_NEAR(enclosedVolume(mesh), sphere, 0.2 * sphere);
    EXPECT_NEAR(maxZ(mesh), radius, 0.2 * radius);
}

TEST(TeddyInflate, DumbbellLobesMoreThanTwiceAsHighAsNeck) {
    const double r = 20, d = 35, w = 5;
    const TeddyInflation result = inflateOutlineDetailed(dumbbell(r, d, w), params());
    double lobe = 0, neck = 0;
    for (std::size_t i = 0; i < result.spine.points.size(); ++i) {
        const double x = std::abs(result.spine.points[i].x);
        if (std::abs(x - d) < r / 2) lobe = std::max(lobe, result.spineHeights[i]);
        if (x < (d - r) / 2) neck = std::max(neck, result.spineHeights[i]);
    }
    ASSERT_GT(neck, 0.0) << "no spine in the neck";
    EXPECT_GT(lobe, 2 * neck);
    // The surface agrees: highest point over the lobes vs over the neck.
    double lobeZ = 0, neckZ = 0;
    for (const auto& v : result.mesh.vertices) {
        if (std::abs(std::abs(v.x) - d) < r / 2) lobeZ = std::max(lobeZ, v.z);
        if (std::abs(v.x) < (d - r) / 2) neckZ = std::max(neckZ, v.z);
    }
    EXPECT_GT(lobeZ, 2 * neckZ);
}

TEST(TeddyInflate, EllipseThicknessFollowsMinorAxis) {
    const double a = 40;
    std::vector<double> heights;
    for (const double b : {6.0, 12.0, 20.0}) {
        SCOPED_TRACE(b);
        const double h = maxZ(inflateOutline(ellipse(a, b, 300), params(1.0)));
        // Roughly elliptical cross-sections: half-thickness ≈ half-width at the widest point.
        EXPECT_GT(h, 0.85 * b);
        EXPECT_LT(h, 1.25 * b);
        heights.push_back(h);
    }
    EXPECT_NEAR(heights[1] / heights[0], 2.0, 0.2);
    EXPECT_NEAR(heights[2] / heights[0], 20.0 / 6.0, 0.33);
}

TEST(TeddyInflate, ElongatedEllipseSpineRunsAlongMajorAxis) {
    const double a = 40, b = 10;
    const TeddyInflation r = inflateOutlineDetailed(ellipse(a, b, 300, {0, 0}, 0.0), params());
    EXPECT_EQ(std::count(r.classes.begin(), r.classes.end(), TeddyTriangleClass::Junction), 0);
    double minX = 1e300, maxX = -1e300;
    for (const auto& p : r.spine.points) {
        EXPECT_LT(std::abs(p.y), 0.05 * b);
        minX = std::min(minX, p.x);
        maxX = std::max(maxX, p.x);
    }
    EXPECT_LT(maxX - minX, 2 * a);
    EXPECT_GT(maxX - minX, a);  // pruning removed the tips, not the body
}

TEST(TeddyInflate, ThreeArmsKeepOneJunctionAndThreeBranches) {
    const TeddyInflation r = inflateOutlineDetailed(threeArms(), params());
    std::vector<int> degree(r.spine.points.size(), 0);
    for (const auto& e : r.spine.edges)
        ++degree[e[0]], ++degree[e[1]];
    EXPECT_EQ(std::count(degree.begin(), degree.end(), 3), 1);
    EXPECT_EQ(std::count(degree.begin(), degree.end(), 1), 3);
    EXPECT_EQ(std::count_if(degree.begin(), degree.end(), [](int d) { return d > 3; }), 0);
}

TEST(TeddyInflate, InvariantUnderRigidMotionOfTheOutline) {
    const Polyline2 original = blob();
    const double angle = 0.7;
    const glm::dvec2 shift{120, -45};
    const auto move = [&](const glm::dvec2& p) {
        return glm::dvec2(std::cos(angle) * p.x - std::sin(angle) * p.y,
                          std::sin(angle) * p.x + std::cos(angle) * p.y) +
               shift;
    };
    Polyline2 moved;
    for (const auto& p : original)
        moved.push_back(move(p));
    const PolyMesh a = inflateOutline(original, params());
    const PolyMesh b = inflateOutline(moved, params());
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.faces.size(), b.faces.size());
    EXPECT_NEAR(enclosedVolume(a), enclosedVolume(b), 1e-9 * enclosedVolume(a));
    EXPECT_NEAR(maxZ(a), maxZ(b), 1e-9 * maxZ(a));
    // Every vertex of the moved solid is the moved vertex of the original (any order).
    const auto less = [](const glm::dvec3& p, const glm::dvec3& q) {
        return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    };
    std::vector<glm::dvec3> expected;
    for (const auto& v : a.vertices)
        expected.push_back({move({v.x, v.y}), v.z});
    std::vector<glm::dvec3> actual = b.vertices;
    std::sort(expected.begin(), expected.end(), less);
    std::sort(actual.begin(), actual.end(), less);
    double worst = 0;
    for (std::size_t i = 0; i < actual.size(); ++i)
        worst = std::max(worst, glm::length(actual[i] - expected[i]));
    EXPECT_LT(worst, 1e-8);
}

TEST(TeddyInflate, ClockwiseOutlineGivesTheSameSolid) {
    Polyline2 outline = blob();
    const double ccw = enclosedVolume(inflateOutline(outline, params()));
    std::reverse(outline.begin() + 1, outline.end());
    const PolyMesh mesh = inflateOutline(outline, params());
    EXPECT_TRUE(isClosedOriented(mesh));
    EXPECT_NEAR(enclosedVolume(mesh), ccw, 1e-9 * ccw);
}

TEST(TeddyInflate, ResamplingGivesEqualEdges) {
    const Polyline2 square{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};  // closing point repeated
    const Polyline2 r = resampleOutline(square, 40);
    ASSERT_EQ(r.size(), 40u);
    for (std::size_t i = 0; i < r.size(); ++i)
        EXPECT_NEAR(glm::length(r[(i + 1) % r.size()] - r[i]), 1.0, 1e-9);
    EXPECT_NEAR(signedArea(r), 100.0, 1e-9);
    // A clockwise input comes back counter-clockwise, starting at the same point.
    const Polyline2 cw{{0, 0}, {0, 10}, {10, 10}, {10, 0}};
    const Polyline2 rc = resampleOutline(cw, 40);
    EXPECT_EQ(rc[0], glm::dvec2(0, 0));
    EXPECT_NEAR(signedArea(rc), 100.0, 1e-9);
}

void expectInvalid(const Polyline2& outline, const std::string& fragment) {
    try {
        inflateOutline(outline, params());
        ADD_FAILURE() << "accepted an outline that should fail with: " << fragment;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

TEST(TeddyInflate, BadOutlinesAreRejectedWithReasons) {
    expectInvalid({}, "at least 3");
    expectInvalid({{0, 0}, {1, 0}, {1, 0}, {0, 0}}, "at least 3");
    expectInvalid({{0, 0}, {1, 0}, {2, 0}, {3, 0}}, "zero area");
    expectInvalid({{0, 0}, {1, 1}, {std::nan(""), 0}}, "not finite");
    // Figure eight: segment 0 crosses segment 2 at (6.25, 6.25).
    const Polyline2 eight{{0, 0}, {10, 10}, {10, 4}, {0, 10}};
    expectInvalid(eight, "self-intersects: segment 0 crosses segment 2");
    expectInvalid(eight, "(6.25, 6.25)");
    TeddyParams bad = params();
    bad.edgeLength = 0;
    EXPECT_THROW(inflateOutline(blob(), bad), std::invalid_argument);
    bad = params();
    bad.ellipseSegments = 0;
    EXPECT_THROW(inflateOutline(blob(), bad), std::invalid_argument);
}

TEST(TeddyInflate, CoarseEllipseSamplingStillClosed) {
    TeddyParams p = params(3.0);
    for (const int segments : {1, 2, 10}) {
        p.ellipseSegments = segments;
        const PolyMesh mesh = inflateOutline(threeArms(), p);
        EXPECT_TRUE(isClosedOriented(mesh));
        EXPECT_EQ(eulerCharacteristic(mesh), 2);
    }
}

TEST(TeddyInflate, RandomOutlinesGiveClosedSolids) {
    // Star-shaped outlines with random low-frequency radius, some deeply concave.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> amplitude(-1.0, 1.0);
    for (int trial = 0; trial < 30; ++trial) {
        SCOPED_TRACE(trial);
        std::array<double, 6> c{}, phase{};
        for (int k = 0; k < 6; ++k)
            c[k] = 4.0 * amplitude(random) / (k + 1), phase[k] = 3 * amplitude(random);
        Polyline2 outline;
        for (int i = 0; i < 240; ++i) {
            const double t = 2 * kPi * i / 240;
            double r = 25;
            for (int k = 0; k < 6; ++k)
                r += c[k] * std::cos((k + 2) * t + phase[k]);
            outline.push_back({r * std::cos(t), r * std::sin(t)});
        }
        const TeddyInflation result = inflateOutlineDetailed(outline, params(1.5));
        EXPECT_TRUE(isClosedOriented(result.mesh));
        EXPECT_EQ(eulerCharacteristic(result.mesh), 2);
        EXPECT_TRUE(graphIsTree(result.spine));
        for (double h : result.spineHeights)
            EXPECT_GT(h, 0.0);
    }
}

}  // namespace
}  // namespace vsculpt::sketch
