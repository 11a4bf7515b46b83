// SPDX-License-Identifier: MIT
// The sketch canvas with real OpenGL under Xvfb + Mesa (ctest runs this binary through
// xvfb-run): ink lands on the pixels the view mapping says, zoom and pan move it exactly, the
// grid stays anchored to the canvas, overlays show, and a sub-rectangle leaves the rest alone.
#include "vsculpt/render/SketchCanvas.h"
#include "vsculpt/render/Viewer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace vsculpt::render;

namespace {

constexpr int kW = 400, kH = 300;

/// 4 pixels per mm, canvas = view at zoom 1.
CanvasView baseView() {
    CanvasView v;
    v.viewportMm = {100, 75};
    v.viewportPx = {kW, kH};
    return v;
}

struct Gl {
    Viewer viewer{kW, kH, "vsculpt sketch canvas test", false};
    SketchCanvas canvas;  // after the viewer: destroyed first, with its context current

    Image draw(const std::vector<InkStroke>& ink, const CanvasView& view,
               const CanvasOverlay& overlay = noGrid()) {
        canvas.draw(ink, view, {0, 0}, overlay);
        return viewer.readFrame();
    }
    static CanvasOverlay noGrid() {
        CanvasOverlay o;
        o.grid = false;
        return o;
    }
};

glm::ivec3 rgb255(glm::vec3 c) {
    return glm::ivec3(glm::round(c * 255.0f));
}

int diff(const uint8_t* p, glm::ivec3 c) {
    return std::max({std::abs(p[0] - c.x), std::abs(p[1] - c.y), std::abs(p[2] - c.z)});
}

bool isPaper(const uint8_t* p) {
    return diff(p, rgb255(kPaperRgb)) <= 1;
}

bool isDark(const uint8_t* p) {
    return p[0] < 60 && p[1] < 60 && p[2] < 60;
}

/// Dark rows in a column: count and mean pixel-centre y.
std::pair<int, double> darkRows(const Image& img, int x) {
    int n = 0;
    double sum = 0;
    for (int y = 0; y < img.height; ++y)
        if (isDark(img.pixel(x, y))) {
            ++n;
            sum += y + 0.5;
        }
    return {n, n ? sum / n : -1.0};
}

InkStroke horizontalStroke(double yMm, float widthMm) {
    return {{{10, yMm}, {90, yMm}}, {widthMm}, {1.0f}};
}

}  // namespace

TEST(SketchCanvas, ThickDarkStrokeCoversItsPixelsAndLeavesPaperElsewhere) {
    Gl gl;
    const CanvasView v = baseView();
    // Centre line at pixel y = 300 - 4 * 30.1 = 179.6, 12 px wide: rows 174..185.
    const Image img = gl.draw({horizontalStroke(30.1, 3.0f)}, v);
    ASSERT_EQ(img.width, kW);
    const glm::ivec3 ink = rgb255(inkRgb(InkClass::Draft, 1));
    int checkedPaper = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const glm::dvec2 c = v.canvasFromView(v.viewFromPixel({x + 0.5, y + 0.5}));
            // Distance to the stroke's centre segment, in canvas mm.
            const double dx = std::max({10.0 - c.x, 0.0, c.x - 90.0}), dy = c.y - 30.1;
            const double d = std::hypot(dx, dy);
            if (d < 1.5 - 0.3) {
                EXPECT_LE(diff(img.pixel(x, y), ink), 1) << x << "," << y;
            } else if (d > 1.5 + 0.3) {
                EXPECT_TRUE(isPaper(img.pixel(x, y))) << x << "," << y;
                ++checkedPaper;
            }
        }
    EXPECT_GT(checkedPaper, kW * kH / 2);
    const auto [rows, centre] = darkRows(img, 200);
    EXPECT_EQ(rows, 12);
    EXPECT_NEAR(centre, 179.6, 0.5);
}

TEST(SketchCanvas, ZoomDoublesTheWidthAndKeepsTheCanvasPlace) {
    Gl gl;
    const CanvasView v = baseView();
    const std::vector<InkStroke> ink{horizontalStroke(30.1, 3.0f)};
    const auto [rows1, centre1] = darkRows(gl.draw(ink, v), 200);
    const CanvasView z = v.zoomedAbout({50, 40}, 2.0);
    const Image img = gl.draw(ink, z);
    const auto [rows2, centre2] = darkRows(img, 200);
    EXPECT_EQ(rows1, 12);
    EXPECT_EQ(rows2, 24);
    // Map the stroke's pixel centre back to the canvas: the same place in both views, to
    // within half a pixel of each.
    const double c1 = v.canvasFromView(v.viewFromPixel({200.5, centre1})).y;
    const double c2 = z.canvasFromView(z.viewFromPixel({200.5, centre2})).y;
    EXPECT_NEAR(c1, 30.1, 0.5 / 4);
    EXPECT_NEAR(c2, 30.1, 0.5 / 8);
    // The point zoomed about stays put: canvas (50, 40) is at pixel (200, 140) in both.
    const glm::dvec2 p = z.pixelFromView(z.viewFromCanvas({50, 40}));
    EXPECT_DOUBLE_EQ(p.x, 200);
    EXPECT_DOUBLE_EQ(p.y, 140);
}

TEST(SketchCanvas, PanMovesTheInkByTheExactPixelAmount) {
    Gl gl;
    const CanvasView v = baseView();
    const std::vector<InkStroke> ink{{{{20, 20}, {45, 50}, {70, 30}}, {2.2f}, {1.0f}},
                                     {{{80.3, 60.2}}, {5.0f}, {1.0f}}};
    CanvasView p = v;
    p.panMm += glm::dvec2(2.5, -1.75);  // content moves 10 px left and 7 px up
    const Image a = gl.draw(ink, v), b = gl.draw(ink, p);
    double ax = 0, ay = 0, bx = 0, by = 0;
    int na = 0, nb = 0, mismatched = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool da = isDark(a.pixel(x, y)), db = isDark(b.pixel(x, y));
            if (da) ax += x, ay += y, ++na;
            if (db) bx += x, by += y, ++nb;
            if (da && x >= 10 && y >= 7) mismatched += !isDark(b.pixel(x - 10, y - 7));
        }
    ASSERT_GT(na, 500);
    EXPECT_EQ(na, nb);
    EXPECT_NEAR(bx / nb - ax / na, -10, 0.05);
    EXPECT_NEAR(by / nb - ay / na, -7, 0.05);
    EXPECT_LE(mismatched, na / 100);
}

TEST(SketchCanvas, DarknessAndClassSetTheColour) {
    Gl gl;
    const CanvasView v = baseView();
    InkStroke grey = horizontalStroke(20, 3.0f);
    grey.darkness = {0.5f};
    InkStroke selected = horizontalStroke(50, 3.0f);
    selected.cls = InkClass::Selected;
    const Image img = gl.draw({grey, selected}, v);
    EXPECT_LE(diff(img.pixel(200, kH - 80), rgb255(inkRgb(InkClass::Draft, 0.5f))), 1);
    EXPECT_LE(diff(img.pixel(200, kH - 200), rgb255(inkRgb(InkClass::Selected, 1))), 1);
}

TEST(SketchCanvas, GridIsAnchoredToTheCanvasAtAnyPanAndZoom) {
    Gl gl;
    CanvasOverlay grid;
    for (const auto& [pan, zoom] :
         {std::pair{glm::dvec2(0, 0), 1.0}, std::pair{glm::dvec2(1234567.3, -89.1), 1.0},
          std::pair{glm::dvec2(-3.7, 2.2), 3.0}, std::pair{glm::dvec2(12.9, 4.4), 0.2}}) {
        CanvasView v = baseView();
        v.panMm = pan;
        v.zoom = zoom;
        const double spacing = canvasGridSpacingMm(zoom);
        EXPECT_GE(spacing * zoom, 5.0);
        EXPECT_LT(spacing * zoom, 50.0);
        const Image img = gl.draw({}, v, grid);
        // Vertical lines along one row: runs of non-paper pixels, their centres in canvas mm
        // are multiples of the spacing, every one of those in view has a line.
        const int y = kH / 2 + 3;
        int runs = 0;
        for (int x = 0; x < kW;) {
            if (isPaper(img.pixel(x, y))) {
                ++x;
                continue;
            }
            double wsum = 0, xsum = 0;
            int x1 = x;
            for (; x1 < kW && !isPaper(img.pixel(x1, y)); ++x1) {
                const double w = 255 - img.pixel(x1, y)[0];
                wsum += w;
                xsum += w * (x1 + 0.5);
            }
            if (x > 0 && x1 < kW) {
                const double c = v.canvasFromView(v.viewFromPixel({xsum / wsum, 0.5})).x;
                const double k = c / spacing;
                EXPECT_NEAR(k, std::round(k), 0.25 / (4 * zoom * spacing))
                    << "pan " << pan.x << " zoom " << zoom;
                ++runs;
            }
            x = x1;
        }
        const double expected = 100 / (zoom * spacing);  // lines across the 100 mm view
        EXPECT_GE(runs, int(expected) - 2) << "zoom " << zoom;
        EXPECT_LE(runs, int(expected) + 1) << "zoom " << zoom;
    }
}

TEST(SketchCanvas, PenCursorAndLassoAreDrawn) {
    Gl gl;
    const CanvasView v = baseView();
    CanvasOverlay o = Gl::noGrid();
    o.penMm = glm::dvec2(50, 37.5);  // pixel (200, 150)
    o.penWidthMm = 4;                // ring radius 8 px
    Image img = gl.draw({}, v, o);
    EXPECT_TRUE(isPaper(img.pixel(200, 150)));
    EXPECT_FALSE(isPaper(img.pixel(207, 149)));
    EXPECT_FALSE(isPaper(img.pixel(192, 150)));
    EXPECT_FALSE(isPaper(img.pixel(199, 142)));
    EXPECT_TRUE(isPaper(img.pixel(212, 150)));
    o.penTouching = true;
    img = gl.draw({}, v, o);
    EXPECT_FALSE(isPaper(img.pixel(200, 150)));

    o = Gl::noGrid();
    o.lassoMm = {{20, 20}, {60, 20}, {60, 50}, {20, 50}};  // pixels x 80..240, y 100..220
    img = gl.draw({}, v, o);
    const glm::ivec3 blue = rgb255(inkRgb(InkClass::Selected, 1));
    for (const glm::ivec2 p :
         {glm::ivec2(160, 220), glm::ivec2(240, 160), glm::ivec2(160, 100), glm::ivec2(80, 160)}) {
        // The 1.5 px outline straddles the pixel border at the edge: one of the two is ink.
        const bool hit =
            diff(img.pixel(p.x, p.y), blue) <= 40 || diff(img.pixel(p.x - 1, p.y - 1), blue) <= 40;
        EXPECT_TRUE(hit) << p.x << "," << p.y;
    }
    EXPECT_TRUE(isPaper(img.pixel(160, 160)));
}

TEST(SketchCanvas, DrawsOnlyInsideItsRectangleAndCullsFarStrokes) {
    Gl gl;
    const CanvasView v = baseView();
    const std::vector<InkStroke> ink{horizontalStroke(37.5, 40.0f)};  // covers most rows
    const Image full = gl.draw(ink, v);
    CanvasView small = baseView();
    small.viewportPx = {100, 80};
    small.viewportMm = {25, 20};
    small.panMm = {5000, 5000};  // empty canvas there
    const InkStroke far{{{-5000, 0}, {-4990, 0}}, {1.0f}, {1.0f}};
    const CanvasStats stats = gl.canvas.draw({far}, small, {50, 40}, Gl::noGrid());
    EXPECT_EQ(stats.strokesCulled, 1u);
    EXPECT_EQ(stats.strokesDrawn, 0u);
    const Image img = gl.viewer.readFrame();
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            // GL's lower-left (50, 40) and 100 x 80: image rows kH-120 .. kH-41.
            const bool inRect = x >= 50 && x < 150 && y >= kH - 120 && y < kH - 40;
            if (inRect) {
                EXPECT_TRUE(isPaper(img.pixel(x, y))) << x << "," << y;
            } else {
                EXPECT_EQ(diff(img.pixel(x, y), glm::ivec3(full.pixel(x, y)[0], full.pixel(x, y)[1],
                                                           full.pixel(x, y)[2])),
                          0)
                    << x << "," << y;
            }
        }
}

TEST(SketchCanvas, BadViewOrStrokeThrowsBeforeDrawing) {
    Gl gl;
    CanvasView v = baseView();
    v.zoom = -1;
    EXPECT_THROW(gl.canvas.draw({}, v), std::invalid_argument);
    EXPECT_THROW(gl.canvas.draw({{{{1, 1}, {2, 2}}, {1, 2, 3}, {1}}}, baseView()),
                 std::invalid_argument);
    CanvasOverlay o;
    o.penMm = glm::dvec2(1, 1);
    o.penWidthMm = std::nan("");
    EXPECT_THROW(gl.canvas.draw({}, baseView(), {0, 0}, o), std::invalid_argument);
}
