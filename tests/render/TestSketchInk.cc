// SPDX-License-Identifier: MIT
// The sketch canvas's ink tessellation and view mapping, without GL: coverage against the
// analytic capsule, exact strip widths, degenerate strokes, bad input.
#include "vsculpt/render/SketchInk.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

using namespace vsculpt::render;

namespace {

CanvasView testView() {
    CanvasView v;
    v.panMm = {-3.0, 2.0};
    v.zoom = 2.5;
    v.viewportMm = {200, 150};
    v.viewportPx = {800, 600};
    return v;
}

bool inside(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    auto side = [](glm::dvec2 o, glm::dvec2 u, glm::dvec2 q) {
        return (u.x - o.x) * (q.y - o.y) - (u.y - o.y) * (q.x - o.x);
    };
    const double d1 = side(a, b, p), d2 = side(b, c, p), d3 = side(c, a, p);
    const bool neg = d1 < 0 || d2 < 0 || d3<0, pos = d1> 0 || d2 > 0 || d3 > 0;
    return !(neg && pos);
}

bool covered(const std::vector<InkVertex>& tris, glm::dvec2 p) {
    for (size_t i = 0; i + 2 < tris.size(); i += 3)
        if (inside(p, tris[i].viewMm, tris[i + 1].viewMm, tris[i + 2].viewMm)) return true;
    return false;
}

double distanceToPolyline(glm::dvec2 p, const std::vector<glm::dvec2>& line) {
    double best = std::numeric_limits<double>::max();
    for (size_t i = 0; i + 1 < line.size(); ++i) {
        const glm::dvec2 a = line[i], d = line[i + 1] - a;
        const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
        best = std::min(best, glm::length(p - (a + t * d)));
    }
    if (line.size() == 1) best = glm::length(p - line[0]);
    return best;
}

void expectFinite(const std::vector<InkVertex>& tris) {
    ASSERT_EQ(tris.size() % 3, 0u);
    for (const InkVertex& v : tris) {
        ASSERT_TRUE(std::isfinite(v.viewMm.x) && std::isfinite(v.viewMm.y));
        ASSERT_TRUE(std::isfinite(v.darkness));
    }
}

/// Tessellation covers the stroke's capsule (points within h of the centre line, less the
/// arc's chord sag) and nothing beyond h.
void expectCapsule(const InkStroke& s, const CanvasView& v) {
    const auto tris = tessellateInk(s, v);
    expectFinite(tris);
    std::vector<glm::dvec2> line;
    for (auto p : s.pointsMm)
        line.push_back(v.viewFromCanvas(p));
    const double h = 0.5 * s.widthMm[0] * v.zoom;
    // Arcs use chords of <= 3 px (at least 8 per circle): the sag is below h (1 - cos(pi/8)).
    const double chordPx = 3.0 / v.pixelsPerMm().x;
    const double sag = h * (1 - std::cos(std::min(std::numbers::pi / 8, chordPx / h)));
    glm::dvec2 lo(1e30), hi(-1e30);
    for (auto p : line) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    int inCount = 0, outCount = 0;
    for (double y = lo.y - 2 * h; y <= hi.y + 2 * h; y += h / 7.3)
        for (double x = lo.x - 2 * h; x <= hi.x + 2 * h; x += h / 7.1) {
            const double d = distanceToPolyline({x, y}, line);
            if (d < h - sag - 1e-9) {
                EXPECT_TRUE(covered(tris, {x, y})) << x << " " << y << " d=" << d;
                ++inCount;
            } else if (d > h + 1e-9) {
                EXPECT_FALSE(covered(tris, {x, y})) << x << " " << y << " d=" << d;
                ++outCount;
            }
        }
    EXPECT_GT(inCount, 50);
    EXPECT_GT(outCount, 50);
}

}  // namespace

TEST(SketchInk, ViewMappingRoundTripsAndZoomKeepsThePointUnderThePen) {
    const CanvasView v = testView();
    const glm::dvec2 c(12.25, -7.5);
    const glm::dvec2 back = v.canvasFromView(v.viewFromCanvas(c));
    EXPECT_NEAR(back.x, c.x, 1e-12);
    EXPECT_NEAR(back.y, c.y, 1e-12);
    // viewMm = (canvasMm - panMm) * zoom, exactly as documented.
    EXPECT_DOUBLE_EQ(v.viewFromCanvas(c).x, (c.x - v.panMm.x) * v.zoom);
    const glm::dvec2 px = v.pixelFromView({10, 20});
    EXPECT_DOUBLE_EQ(px.x, 40);
    EXPECT_DOUBLE_EQ(px.y, 600 - 80);
    EXPECT_DOUBLE_EQ(v.viewFromPixel(px).y, 20);
    const glm::dvec2 q(70, 40);
    const CanvasView z = v.zoomedAbout(q, 2);
    EXPECT_DOUBLE_EQ(z.zoom, 5);
    EXPECT_NEAR(z.canvasFromView(q).x, v.canvasFromView(q).x, 1e-12);
    EXPECT_NEAR(z.canvasFromView(q).y, v.canvasFromView(q).y, 1e-12);
    EXPECT_THROW(v.zoomedAbout(q, 0), std::invalid_argument);
}

TEST(SketchInk, StraightStripIsExactlyWidthTimesZoom) {
    const CanvasView v = testView();
    // A diagonal straight stroke with a middle point: the half-width measured perpendicular to
    // the line is widthMm * zoom / 2 at every quad corner, and the caps reach no farther.
    const glm::dvec2 a(1, 1), b(6, 4), c(11, 7);
    InkStroke s{{a, b, c}, {1.6f}, {1.0f}};
    const auto tris = tessellateInk(s, v);
    expectFinite(tris);
    const glm::dvec2 va = v.viewFromCanvas(a), vc = v.viewFromCanvas(c);
    const glm::dvec2 u = glm::normalize(vc - va), n(-u.y, u.x);
    const double h = 0.5 * 1.6f * 2.5;
    double maxAcross = 0, minAlong = 1e30, maxAlong = -1e30;
    int atMiddle = 0;
    const double middleAlong = glm::dot(v.viewFromCanvas(b) - va, u);
    for (const InkVertex& t : tris) {
        const double across = std::abs(glm::dot(t.viewMm - va, n));
        const double along = glm::dot(t.viewMm - va, u);
        maxAcross = std::max(maxAcross, across);
        minAlong = std::min(minAlong, along);
        maxAlong = std::max(maxAlong, along);
        if (std::abs(along - middleAlong) < 1e-9 && std::abs(across - h) < 1e-9) ++atMiddle;
    }
    EXPECT_NEAR(maxAcross, h, 1e-9);
    EXPECT_NEAR(minAlong, -h, 1e-9);
    EXPECT_NEAR(maxAlong, glm::length(vc - va) + h, 1e-9);
    EXPECT_GE(atMiddle, 2);  // the strip has its full width at the middle point too
    expectCapsule(s, v);
}

TEST(SketchInk, SharpTurnsAndReversalsAreCoveredByRoundJoins) {
    const CanvasView v = testView();
    expectCapsule({{{0, 0}, {8, 0}, {2, 3}, {9, 6}}, {1.2f}, {1.0f}}, v);  // zig-zag
    expectCapsule({{{0, 0}, {8, 0}, {1, 0}}, {1.2f}, {1.0f}}, v);          // reverses on itself
    expectCapsule({{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {2.0f}, {0.5f}}, v);  // right angles
}

TEST(SketchInk, VariableWidthAndDarknessFollowThePoints) {
    const CanvasView v = testView();
    InkStroke s{{{0, 0}, {10, 0}}, {0.4f, 2.0f}, {0.2f, 0.9f}};
    const auto tris = tessellateInk(s, v);
    expectFinite(tris);
    const glm::dvec2 a = v.viewFromCanvas({0, 0}), b = v.viewFromCanvas({10, 0});
    double maxA = 0, maxB = 0;
    for (const InkVertex& t : tris) {
        if (std::abs(t.viewMm.x - a.x) < 1e-9) {
            maxA = std::max(maxA, std::abs(t.viewMm.y - a.y));
            EXPECT_FLOAT_EQ(t.darkness, 0.2f);
        }
        if (std::abs(t.viewMm.x - b.x) < 1e-9) {
            maxB = std::max(maxB, std::abs(t.viewMm.y - b.y));
            EXPECT_FLOAT_EQ(t.darkness, 0.9f);
        }
    }
    EXPECT_NEAR(maxA, 0.5 * 0.4f * v.zoom, 1e-9);
    EXPECT_NEAR(maxB, 0.5 * 2.0f * v.zoom, 1e-9);
}

TEST(SketchInk, DuplicateAndSinglePointsGiveFiniteDiscs) {
    const CanvasView v = testView();
    const InkStroke one{{{5, 5}}, {2.0f}, {1.0f}};
    expectCapsule(one, v);
    const InkStroke same{{{5, 5}, {5, 5}, {5, 5}}, {2.0f}, {1.0f}};
    const auto disc = tessellateInk(same, v);
    expectFinite(disc);
    ASSERT_FALSE(disc.empty());
    for (const InkVertex& t : disc)
        EXPECT_LE(glm::length(t.viewMm - v.viewFromCanvas({5, 5})), 2.5 + 1e-9);
    // Repeated points inside a stroke (a pen resting) change nothing about its outline.
    expectCapsule({{{0, 0}, {0, 0}, {6, 2}, {6, 2}, {6, 2}, {9, -1}, {9, -1}}, {1.0f}, {1.0f}}, v);
    // A closed stroke whose last point repeats the first.
    const auto loop =
        tessellateInk({{{0, 0}, {4, 0}, {4, 4}, {0, 0}}, {1.0f}, {1.0f}, InkClass::Clean, true}, v);
    expectFinite(loop);
    EXPECT_TRUE(tessellateInk({{}, {1.0f}, {1.0f}}, v).empty());
    EXPECT_TRUE(tessellateInk({{{0, 0}, {3, 3}}, {0.0f}, {1.0f}}, v).empty());
}

TEST(SketchInk, ClosedStrokeHasNoCapsButCoversItsCorner) {
    const CanvasView v = testView();
    const InkStroke tri{{{0, 0}, {6, 0}, {3, 5}}, {1.0f}, {1.0f}, InkClass::Draft, true};
    const auto tris = tessellateInk(tri, v);
    expectFinite(tris);
    // The closing edge (3,5) -> (0,0) is drawn: its midpoint is covered.
    EXPECT_TRUE(covered(tris, v.viewFromCanvas({1.5, 2.5})));
    // The inside of the triangle, far from the edges, is not.
    EXPECT_FALSE(covered(tris, v.viewFromCanvas({3, 1.8})));
}

TEST(SketchInk, InkColoursMixPaperAndInk) {
    EXPECT_EQ(inkRgb(InkClass::Draft, 0), kPaperRgb);
    const glm::vec3 full = inkRgb(InkClass::Draft, 1), half = inkRgb(InkClass::Draft, 0.5f);
    EXPECT_LT(full.r, 0.1f);
    EXPECT_NEAR(half.r, 0.5f * (full.r + kPaperRgb.r), 1e-6);
    EXPECT_GT(inkRgb(InkClass::Selected, 1).b, inkRgb(InkClass::Selected, 1).r);
    EXPECT_GT(inkRgb(InkClass::Consumed, 1).r, 0.5f);  // faint
}

TEST(SketchInk, BadInputIsRefusedByName) {
    const CanvasView v = testView();
    auto message = [&](const InkStroke& s, const CanvasView& view) {
        try {
            tessellateInk(s, view);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no exception");
    };
    EXPECT_NE(message({{{0, 0}, {1, 1}, {2, 2}}, {1, 2}, {1}}, v).find("widthMm"),
              std::string::npos);
    EXPECT_NE(message({{{0, 0}, {1, 1}}, {1}, {}}, v).find("darkness"), std::string::npos);
    EXPECT_NE(message({{{0, 0}, {1, 1}}, {1}, {1.5f}}, v).find("darkness[0]"), std::string::npos);
    EXPECT_NE(message({{{0, 0}, {1, 1}}, {-1}, {1}}, v).find("widthMm[0]"), std::string::npos);
    EXPECT_NE(message({{{0, 0}, {std::nan(""), 1}}, {1}, {1}}, v).find("pointsMm[1]"),
              std::string::npos);
    CanvasView bad = v;
    bad.zoom = 0;
    EXPECT_NE(message({{{0, 0}}, {1}, {1}}, bad).find("zoom"), std::string::npos);
    bad = v;
    bad.viewportPx = {0, 10};
    EXPECT_NE(message({{{0, 0}}, {1}, {1}}, bad).find("viewportPx"), std::string::npos);
}
