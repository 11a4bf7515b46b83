// SPDX-License-Identifier: MIT
// Drawing on the model: strokes in pixels projected onto a sphere mesh with Embree. Points lie
// on the sphere within the mesh's chord error, respect the spacing, split where the stroke
// leaves the surface or one sphere hides another, and misses give nothing.
#include "vsculpt/render/ProjectStroke.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

using namespace vsculpt;
using namespace vsculpt::render;

namespace {

/// A latitude-longitude sphere, outward winding.
void addSphere(core::Mesh& m, core::Vec3 centre, double r, int rings, int segments) {
    const auto base = uint32_t(m.positions.size());
    for (int i = 0; i <= rings; ++i) {
        const double th = std::numbers::pi * i / rings;
        for (int j = 0; j <= segments; ++j) {
            const double ph = 2 * std::numbers::pi * j / segments;
            const core::Vec3 n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                               std::cos(th));
            m.positions.push_back(centre + r * n);
            m.normals.push_back(n);
        }
    }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const uint32_t a = base + uint32_t(i * (segments + 1) + j),
                           b = a + uint32_t(segments + 1);
            for (uint32_t k : {a, b, a + 1, a + 1, b, b + 1})
                m.indices.push_back(k);
        }
}

/// The smallest distance from `centre` of any point of the mesh: the triangles' planes (the
/// vertices are on the sphere, so every point is between this and r).
double innerRadius(const core::Mesh& m, core::Vec3 centre) {
    double best = 1e30;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const core::Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                         c = m.positions[m.indices[3 * t + 2]];
        const core::Vec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) < 1e-12) continue;  // the poles' collapsed triangles
        best = std::min(best, std::abs(glm::dot(a - centre, glm::normalize(n))));
    }
    return best;
}

constexpr double kR = 30;
const glm::ivec2 kViewport{640, 480};

ProjectionCamera frontCamera(const core::Mesh& mesh) {
    const core::Aabb box = core::meshBounds(mesh);
    StereoDisplay d;
    d.ipdMm = 0;
    const glm::dmat4 worldFromHead =
        frameFromFront(box.min, box.max, double(kViewport.x) / kViewport.y, d);
    return ProjectionCamera::fromEye(stereoEyes(worldFromHead, d)[0], glm::dmat4(1.0), kViewport);
}

struct SphereScene {
    core::Mesh mesh;
    ProjectionCamera camera;
    double rMin = 0;
    double radiusPx = 0;  // the silhouette's radius along the centre row
    glm::dvec2 centrePx{0.0};
    SphereScene() {
        addSphere(mesh, core::Vec3(0), kR, 48, 96);
        camera = frontCamera(mesh);
        rMin = innerRadius(mesh, core::Vec3(0));
        centrePx = glm::dvec2(kViewport) * 0.5;
        const RayScene scene(mesh);
        while (pickSurface(scene, camera, centrePx + glm::dvec2(radiusPx + 1, 0)))
            radiusPx += 1;
    }
};

const SphereScene& sphere() {
    static const SphereScene s;
    return s;
}

void expectOnSphere(const std::vector<SurfacePoint>& piece, core::Vec3 centre, double rMin,
                    double r) {
    for (const SurfacePoint& p : piece) {
        const double d = glm::length(p.position - centre);
        EXPECT_GE(d, rMin - 1e-3);
        EXPECT_LE(d, r + 1e-3);
        EXPECT_NEAR(glm::length(p.normal), 1.0, 1e-9);
    }
}

/// Consecutive points are within the spacing, except across steps finer than the bisection
/// limit (documented); returns how many such exceptions there were.
int expectSpacing(const std::vector<SurfacePoint>& piece, const StrokeProjectionOptions& o) {
    int steep = 0;
    for (size_t i = 1; i < piece.size(); ++i) {
        const double gap = glm::length(piece[i].position - piece[i - 1].position);
        if (gap <= o.spacingMm) continue;
        EXPECT_LT(glm::length(piece[i].pixel - piece[i - 1].pixel), o.minPixelStep);
        EXPECT_LE(gap, o.maxDepthJumpMm);
        ++steep;
    }
    return steep;
}

}  // namespace

TEST(ProjectStroke, SphereIsSeenWhereExpected) {
    const SphereScene& s = sphere();
    // The sphere fills a good part of the view, so the strokes below cross real surface.
    EXPECT_GT(s.radiusPx, 60);
    EXPECT_LT(s.radiusPx, 240);
    EXPECT_LT(kR - s.rMin, 0.1);  // chord error of the 48 x 96 sphere
}

TEST(ProjectStroke, PickSurfaceHitsTheNearSideAndProjectsBackToThePixel) {
    const SphereScene& s = sphere();
    const RayScene scene(s.mesh);
    const auto hit = pickSurface(scene, s.camera, s.centrePx);
    ASSERT_TRUE(hit);
    // The camera looks along +y from -y: the nearest point is (0, -r, 0).
    EXPECT_NEAR(hit->position.y, -kR, kR - s.rMin + 1e-3);
    EXPECT_LT(hit->normal.y, -0.99);
    // Every hit projects back onto the pixel it was picked from.
    for (const glm::dvec2 px : {s.centrePx, s.centrePx + glm::dvec2(37.3, -21.9),
                                s.centrePx + glm::dvec2(-0.9 * s.radiusPx, 0.25)}) {
        const auto h = pickSurface(scene, s.camera, px);
        ASSERT_TRUE(h);
        const glm::dvec4 clip = s.camera.clipFromObject * glm::dvec4(h->position, 1);
        const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
        EXPECT_NEAR((ndc.x + 1) * 0.5 * kViewport.x, px.x, 1e-3);
        EXPECT_NEAR((1 - ndc.y) * 0.5 * kViewport.y, px.y, 1e-3);
    }
    EXPECT_FALSE(pickSurface(scene, s.camera, {2.0, 2.0}));
}

TEST(ProjectStroke, StrokeInsideTheSilhouetteIsOnePieceOnTheSphere) {
    const SphereScene& s = sphere();
    std::vector<glm::dvec2> stroke;
    for (int k = 0; k <= 40; ++k) {
        const double a = 1.5 * std::numbers::pi * k / 40;
        stroke.push_back(s.centrePx + 0.7 * s.radiusPx * glm::dvec2(std::cos(a), std::sin(a)));
    }
    for (double spacing : {2.0, 0.5, 0.2}) {
        StrokeProjectionOptions o;
        o.spacingMm = spacing;
        const auto pieces = projectStroke(s.mesh, s.camera, stroke, o);
        ASSERT_EQ(pieces.size(), 1u) << spacing;
        expectOnSphere(pieces[0], core::Vec3(0), s.rMin, kR);
        EXPECT_EQ(expectSpacing(pieces[0], o), 0);  // no steep parts well inside
        // The piece runs from the stroke's first pixel to its last.
        EXPECT_NEAR(glm::length(pieces[0].front().pixel - stroke.front()), 0, 1e-12);
        EXPECT_NEAR(glm::length(pieces[0].back().pixel - stroke.back()), 0, 1e-12);
        // The arc on the sphere is 0.75 of a circle of radius ~ r sin(angle); enough points to
        // cover its length at the spacing.
        double length = 0;
        for (size_t i = 1; i < pieces[0].size(); ++i)
            length += glm::length(pieces[0][i].position - pieces[0][i - 1].position);
        EXPECT_GE(double(pieces[0].size() - 1), length / spacing - 1e-9);
    }
}

TEST(ProjectStroke, LeavingAndReenteringTheSilhouetteSplitsThePiece) {
    const SphereScene& s = sphere();
    const RayScene scene(s.mesh);
    const double R = s.radiusPx;
    // Out to the right, down a little, and back in.
    const std::vector<glm::dvec2> stroke{s.centrePx, s.centrePx + glm::dvec2(2 * R, 0),
                                         s.centrePx + glm::dvec2(2 * R, 0.4 * R),
                                         s.centrePx + glm::dvec2(0, 0.4 * R)};
    StrokeProjectionOptions o;
    o.spacingMm = 0.5;
    const auto pieces = projectStroke(scene, s.camera, stroke, o);
    ASSERT_EQ(pieces.size(), 2u);
    int steep = 0;
    for (const auto& piece : pieces) {
        expectOnSphere(piece, core::Vec3(0), s.rMin, kR);
        steep += expectSpacing(piece, o);
    }
    RecordProperty("steepSteps", steep);
    // The first piece ends where the stroke leaves the surface: a bisection step further
    // misses. The second starts where it comes back.
    const glm::dvec2 out = pieces[0].back().pixel;
    EXPECT_NEAR(out.y, s.centrePx.y, 1e-9);
    EXPECT_FALSE(pickSurface(scene, s.camera, out + glm::dvec2(o.minPixelStep, 0)));
    EXPECT_NEAR(out.x - s.centrePx.x, R, 1.0);
    const glm::dvec2 in = pieces[1].front().pixel;
    EXPECT_FALSE(pickSurface(scene, s.camera, in + glm::dvec2(o.minPixelStep, 0)));
    // Near the silhouette the surface turns away from the camera.
    core::Vec3 origin, dir;
    pixelRayInObject(s.camera, out, origin, dir);
    EXPECT_LT(std::abs(glm::dot(dir, glm::normalize(pieces[0].back().position))), 0.2);
}

TEST(ProjectStroke, OneSphereHidingAnotherSplitsAtTheDepthJump) {
    core::Mesh mesh;
    addSphere(mesh, core::Vec3(0), kR, 48, 96);
    const core::Vec3 front(0, -60, 0);
    addSphere(mesh, front, 10, 24, 48);
    const ProjectionCamera camera = frontCamera(mesh);
    const RayScene scene(mesh);
    const core::Vec3 frontCentre = front;
    const glm::dvec4 clip = camera.clipFromObject * glm::dvec4(frontCentre, 1);
    const glm::dvec2 c((clip.x / clip.w + 1) * 0.5 * kViewport.x,
                       (1 - clip.y / clip.w) * 0.5 * kViewport.y);
    // From the small sphere's centre sideways onto the big one behind it, still inside the
    // big one's silhouette.
    double bigPx = 0;
    while (pickSurface(scene, camera, c + glm::dvec2(bigPx + 1, 0)))
        bigPx += 1;
    const std::vector<glm::dvec2> stroke{c, c + glm::dvec2(0.8 * bigPx, 0)};
    StrokeProjectionOptions o;
    o.spacingMm = 0.5;
    o.maxDepthJumpMm = 5;
    const auto pieces = projectStroke(scene, camera, stroke, o);
    ASSERT_EQ(pieces.size(), 2u);
    for (const SurfacePoint& p : pieces[0])
        EXPECT_NEAR(glm::length(p.position - front), 10, 0.05);
    expectOnSphere(pieces[1], core::Vec3(0), innerRadius(mesh, core::Vec3(0)) - 1, kR);
    for (const SurfacePoint& p : pieces[1])
        EXPECT_NEAR(glm::length(p.position), kR, 0.1);
    // The break lies where the small sphere's silhouette is: its last point and the big
    // sphere's first are less than a bisection step apart on screen.
    EXPECT_LT(glm::length(pieces[1].front().pixel - pieces[0].back().pixel), o.minPixelStep);
    for (const auto& piece : pieces)
        expectSpacing(piece, o);
}

TEST(ProjectStroke, MissesGiveNothingAndOnePointGivesOnePoint) {
    const SphereScene& s = sphere();
    EXPECT_TRUE(projectStroke(s.mesh, s.camera, {{3, 3}, {60, 5}, {5, 50}}).empty());
    EXPECT_TRUE(projectStroke(s.mesh, s.camera, {}).empty());
    EXPECT_TRUE(projectStroke(s.mesh, s.camera, {{3, 3}}).empty());
    const auto dot = projectStroke(s.mesh, s.camera, {s.centrePx});
    ASSERT_EQ(dot.size(), 1u);
    ASSERT_EQ(dot[0].size(), 1u);
    EXPECT_NEAR(dot[0][0].position.y, -kR, kR - s.rMin + 1e-3);
    // A stroke that grazes the sphere for less than a spacing still gives no one-point piece.
    for (const auto& piece : projectStroke(s.mesh, s.camera, {{3, 3}, s.centrePx, {3, 470}}))
        EXPECT_GE(piece.size(), 2u);
}

TEST(ProjectStroke, BadInputIsRefusedByName) {
    const SphereScene& s = sphere();
    auto message = [&](const std::vector<glm::dvec2>& stroke, const StrokeProjectionOptions& o,
                       const ProjectionCamera& camera) {
        try {
            projectStroke(s.mesh, camera, stroke, o);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no exception");
    };
    StrokeProjectionOptions o;
    o.spacingMm = 0;
    EXPECT_NE(message({s.centrePx}, o, s.camera).find("spacingMm"), std::string::npos);
    o = {};
    o.maxDepthJumpMm = 0.5;
    EXPECT_NE(message({s.centrePx}, o, s.camera).find("maxDepthJumpMm"), std::string::npos);
    o = {};
    EXPECT_NE(message({s.centrePx, {std::nan(""), 0}}, o, s.camera).find("strokePx[1]"),
              std::string::npos);
    ProjectionCamera bad = s.camera;
    bad.viewportPx = {0, 480};
    EXPECT_NE(message({s.centrePx}, o, bad).find("viewportPx"), std::string::npos);
    bad = s.camera;
    bad.clipFromObject = glm::dmat4(0.0);
    EXPECT_NE(message({s.centrePx}, o, bad).find("clipFromObject"), std::string::npos);
}
