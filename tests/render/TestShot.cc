// SPDX-License-Identifier: MIT
// Real OpenGL under Xvfb + Mesa (ctest runs this binary through xvfb-run): screenshots in each
// stereo mode, checked for content.
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/render/RayTrace.h"
#include "vsculpt/render/Shot.h"
#include "vsculpt/render/StereoCamera.h"
#include "vsculpt/render/UiLayer.h"
#include "vsculpt/render/Viewer.h"

#include "TestScene.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <imgui.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <filesystem>
#include <vector>

using namespace vsculpt;
using namespace vsculpt::render;

namespace {

using vsculpt::test::sculptureMesh;

bool foreground(const uint8_t* p, int channel) {
    return std::abs(int(p[channel]) - int(kBackground[channel])) > 12;
}

struct Coverage {
    double fraction = 0, centroidX = 0;  ///< centroid in pixels from the region's left edge
};

Coverage coverage(const Image& img, int x0, int x1, int channel) {
    Coverage c;
    size_t n = 0;
    double sx = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = x0; x < x1; ++x)
            if (foreground(img.pixel(x, y), channel)) {
                ++n;
                sx += x - x0;
            }
    c.fraction = double(n) / (double(x1 - x0) * img.height);
    c.centroidX = n ? sx / double(n) : 0;
    return c;
}

TEST(Shot, MonoShowsTheSculptureInTheMiddle) {
    ShotOptions o;
    o.width = 320;
    o.height = 240;
    const Image img = renderShot(sculptureMesh(), o);
    const Coverage c = coverage(img, 0, img.width, 0);
    EXPECT_GT(c.fraction, 0.08);
    EXPECT_LT(c.fraction, 0.8);
    EXPECT_NEAR(c.centroidX, img.width / 2.0, img.width * 0.1);
    const auto path = std::filesystem::temp_directory_path() / "vsculpt-shot-test.png";
    writePng(img, path);
    EXPECT_GT(std::filesystem::file_size(path), 1000u);
    std::filesystem::remove(path);
}

TEST(Shot, SideBySideHalvesShowHorizontalParallax) {
    ShotOptions o;
    o.width = 640;
    o.height = 240;
    o.mode = StereoMode::SideBySide;
    o.display.ipdMm = 63;
    const Image img = renderShot(sculptureMesh(), o);
    const Coverage left = coverage(img, 0, img.width / 2, 0);
    const Coverage right = coverage(img, img.width / 2, img.width, 0);
    EXPECT_GT(left.fraction, 0.08);
    EXPECT_NEAR(left.fraction, right.fraction, 0.05);
    // The visible front of the sculpture is nearer than the zero-parallax plane through its
    // centre: crossed parallax, so the left eye sees it further right.
    EXPECT_GT(left.centroidX, right.centroidX + 0.5);
    size_t differ = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width / 2; ++x)
            differ += img.pixel(x, y)[0] != img.pixel(x + img.width / 2, y)[0];
    EXPECT_GT(differ, size_t(img.width / 2 * img.height / 200));
}

TEST(Shot, AnaglyphChannelsCarryDifferentEyes) {
    ShotOptions o;
    o.width = 320;
    o.height = 240;
    o.mode = StereoMode::Anaglyph;
    o.display.ipdMm = 63;
    const Image img = renderShot(sculptureMesh(), o);
    const Coverage red = coverage(img, 0, img.width, 0);   // left eye
    const Coverage cyan = coverage(img, 0, img.width, 1);  // right eye
    EXPECT_GT(red.fraction, 0.08);
    EXPECT_GT(cyan.fraction, 0.08);
    EXPECT_GT(red.centroidX, cyan.centroidX + 0.5);
    EXPECT_EQ(parseStereoMode("anaglyph"), StereoMode::Anaglyph);
    EXPECT_THROW(parseStereoMode("3d"), std::invalid_argument);
}

// The ray tracer frames the mesh exactly like the rasterizer: their silhouettes agree.
TEST(Shot, RayTracedSilhouetteMatchesTheRasterizedOne) {
    const core::Mesh mesh = sculptureMesh();
    for (FrameFit fit : {FrameFit::Sphere, FrameFit::Box}) {
        ShotOptions so;
        so.width = 320;
        so.height = 240;
        so.fit = fit;
        const Image raster = renderShot(mesh, so);
        RayTraceOptions ro;
        ro.width = 320;
        ro.height = 240;
        ro.aoSamples = 1;
        ro.shadowSamples = 1;
        ro.fit = fit;
        const Image traced = rayTrace(mesh, ro);
        size_t agree = 0, fg = 0;
        for (int y = 0; y < raster.height; ++y)
            for (int x = 0; x < raster.width; ++x) {
                const bool a =
                    foreground(raster.pixel(x, y), 0) || foreground(raster.pixel(x, y), 2);
                const uint8_t* t = traced.pixel(x, y);
                const bool b =
                    !(t[0] == kBackground[0] && t[1] == kBackground[1] && t[2] == kBackground[2]);
                agree += a == b;
                fg += a;
            }
        EXPECT_GT(fg, size_t(raster.width * raster.height / 12)) << int(fit);
        EXPECT_GT(double(agree) / (raster.width * raster.height), 0.99) << int(fit);
    }
}

}  // namespace

#include "vsculpt/render/Viewer.h"

namespace {

// The window's renderer keeps chunks on the GPU and re-uploads only those an edit changed.
TEST(Viewer, DrawsChunksAndReuploadsOnlyChangedOnes) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 64;
    core::Sculpture s(cfg);
    core::Polygonizer poly(s, core::zoomRegion(cfg, s.levels(), 1, core::Vec3(0)),
                           core::PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    Viewer viewer(320, 240, "test", false);
    const size_t first = viewer.syncChunks(poly);
    EXPECT_GT(first, 10u);
    EXPECT_EQ(viewer.syncChunks(poly), 0u);  // nothing changed
    ToolDraw tool;
    tool.worldPos = core::Vec3(0, -45, 0);
    tool.radiusMm = 7.5;
    const FrameStats st = viewer.draw(glm::dmat4(1.0), core::meshBounds(poly.mesh()), tool,
                                      StereoMode::Mono, StereoDisplay{});
    EXPECT_EQ(st.chunksDrawn, first);
    EXPECT_EQ(st.triangles, poly.mesh().triangleCount());
    const Image img = viewer.readFrame();
    size_t fg = 0, green = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const uint8_t* p = img.pixel(x, y);
            fg += foreground(p, 0);
            green += p[1] > p[0] + 40;  // the tool, in the air: green
        }
    EXPECT_GT(fg, size_t(img.width * img.height / 12));
    EXPECT_GT(green, 20u);
    // A small edit: a few chunks re-uploaded, not all.
    core::StrokeBuilder stroke(s, core::ToolOp::Add, 5);
    const core::EditResult r = stroke.addSample(core::Vec3(0, 0, 32));
    poly.update(r.changedPoints, r.supportMm);
    const size_t again = viewer.syncChunks(poly);
    EXPECT_GT(again, 0u);
    EXPECT_LT(again, first / 2);
}

}  // namespace

namespace {

bool orange(const uint8_t* p) {
    return p[0] > 230 && p[1] > 100 && p[1] < 160 && p[2] < 30;
}

// The first orange column of row `y` in [x0, x1), or -1.
int firstOrange(const Image& img, int y, int x0, int x1) {
    for (int x = x0; x < x1; ++x)
        if (orange(img.pixel(x, y))) return x;
    return -1;
}

// The UI is drawn once into its texture and composited into each eye: at the same place on
// the zero-parallax plane, shifted by the eyes' disparity when it is nearer, and resampled
// with the scene by the lens correction. The pointer maps back through the eye under it.
TEST(Viewer, UiIsCompositedIntoEachEyeAtItsDepth) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 32;
    core::Sculpture s(cfg);
    core::Polygonizer poly(s, core::zoomRegion(cfg, s.levels(), 1, core::Vec3(0)),
                           core::PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    Viewer viewer(480, 240, "test", false);
    viewer.syncChunks(poly);
    UiLayer ui(viewer);
    ToolDraw tool;
    tool.visible = false;
    const core::Aabb box = core::meshBounds(poly.mesh());
    const glm::ivec2 eye = viewer.eyeImageSize(StereoMode::SideBySide);
    ASSERT_EQ(eye, glm::ivec2(240, 240));
    auto frame = [&](double depthMm, const LensCorrection& lens) {
        ui.beginFrame(eye.x, eye.y, 1.0 / 60);
        // An opaque orange panel 80 x 60 at (60, 20) of the eye's image.
        ImGui::SetNextWindowPos(ImVec2(60, 20));
        ImGui::SetNextWindowSize(ImVec2(80, 60));
        ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(1, 0.5f, 0, 1));
        ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.f);
        ImGui::Begin("panel", nullptr, ImGuiWindowFlags_NoDecoration);
        ImGui::End();
        ImGui::PopStyleVar();
        ImGui::PopStyleColor();
        UiImage img = ui.endFrame();
        img.depthMm = depthMm;
        viewer.draw(glm::dmat4(1.0), box, tool, StereoMode::SideBySide, StereoDisplay{}, lens,
                    &img);
        return viewer.readFrame();
    };
    // On the zero-parallax plane: the same pixels in both eyes.
    Image img = frame(0, {});
    EXPECT_EQ(firstOrange(img, 50, 0, 240), 60);
    EXPECT_EQ(firstOrange(img, 50, 240, 480), 240 + 60);
    EXPECT_TRUE(orange(img.pixel(139, 79)));
    EXPECT_FALSE(orange(img.pixel(140, 50)));
    // Nearer than the plane: crossed disparity, by the projection's amount in whole pixels.
    const double depth = 0.7 * viewer.lastDisplay().focalDistanceMm;
    img = frame(depth, {});
    const StereoDisplay d = viewer.lastDisplay();
    const int left = int(std::lround(eyeShiftNdc(d, depth, Eye::Left) * eye.x / 2));
    const int right = int(std::lround(eyeShiftNdc(d, depth, Eye::Right) * eye.x / 2));
    EXPECT_GT(left, 2);
    EXPECT_EQ(right, -left);
    EXPECT_EQ(firstOrange(img, 50, 0, 240), 60 + left);
    EXPECT_EQ(firstOrange(img, 50, 240, 480), 240 + 60 + right);
    EXPECT_NEAR(viewer.lastUiShiftNdc(Eye::Left), 2.0 * left / eye.x, 1e-12);
    // The pointer over the right eye's copy of the panel's left edge is on the panel's edge.
    const glm::dvec2 p =
        viewer.pointerOnUi(240 + 60 + right + 0.5, 50, StereoMode::SideBySide, eye);
    EXPECT_NEAR(p.x, 60.5, 1e-9);
    EXPECT_NEAR(p.y, 50, 1e-9);
    // With lens correction the panel is resampled with the scene: barrel pre-distortion pulls
    // its outer edge towards the eye's centre, in both eyes.
    img = frame(0, LensCorrection{0.3, 0.1, 1, 1});
    const int warpedL = firstOrange(img, 60, 0, 240), warpedR = firstOrange(img, 60, 240, 480);
    EXPECT_GT(warpedL, 60);
    EXPECT_GT(warpedR, 240 + 60);
    EXPECT_NEAR(warpedR - 240, warpedL, 1);
}

TEST(Viewer, LensCorrectionResamplesEachEye) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 64;
    core::Sculpture s(cfg);
    core::Polygonizer poly(s, core::zoomRegion(cfg, s.levels(), 1, core::Vec3(0)),
                           core::PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    Viewer viewer(480, 240, "test", false);
    viewer.syncChunks(poly);
    ToolDraw tool;
    tool.visible = false;
    const core::Aabb box = core::meshBounds(poly.mesh());
    // The clay is lit to at least 0.18 * 255: brighter than both the background and the
    // black the correction leaves outside the lens's reach.
    auto halfCoverage = [&](const LensCorrection& lens, int channel) {
        viewer.draw(glm::dmat4(1.0), box, tool, StereoMode::SideBySide, StereoDisplay{}, lens);
        const Image img = viewer.readFrame();
        size_t n = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width / 2; ++x)
                n += img.pixel(x, y)[channel] > 42;
        return double(n) / (double(img.width / 2) * img.height);
    };
    const double plain = halfCoverage(LensCorrection{}, 1);
    // No-op correction parameters take the direct path: same picture.
    EXPECT_NEAR(halfCoverage(LensCorrection{0, 0, 1, 1}, 1), plain, 1e-12);
    // Barrel pre-distortion samples further out: the sculpture shrinks towards the centre.
    const double barrel = halfCoverage(LensCorrection{0.3, 0.1, 1, 1}, 1);
    EXPECT_LT(barrel, plain * 0.9);
    EXPECT_GT(barrel, plain * 0.2);
    // Chromatic correction scales red and blue differently from green.
    LensCorrection ca{0.3, 0.1, 0.9, 1.1};
    const double red = halfCoverage(ca, 0), blue = halfCoverage(ca, 2);
    EXPECT_GT(red, blue * 1.05);
}

}  // namespace

namespace {

// A tracked head replaces the framing camera: the framing pose itself gives the same image,
// the head turned away from the sculpture sees only background.
TEST(Viewer, TrackedHeadReplacesTheFramingCamera) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 32;
    core::Sculpture s(cfg);
    core::Polygonizer poly(s, core::zoomRegion(cfg, s.levels(), 1, core::Vec3(0)),
                           core::PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    Viewer viewer(320, 240, "test", false);
    viewer.syncChunks(poly);
    const core::Aabb box = core::meshBounds(poly.mesh());
    ToolDraw tool;
    tool.worldPos = core::Vec3(0, 0, 200);  // out of sight
    auto foregroundOf = [&] {
        viewer.draw(glm::dmat4(1.0), box, tool, StereoMode::Mono, StereoDisplay{});
        const Image img = viewer.readFrame();
        size_t fg = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x)
                fg += foreground(img.pixel(x, y), 0);
        return std::make_pair(fg, img.rgba);
    };
    const auto framed = foregroundOf();
    EXPECT_GT(framed.first, 1000u);
    StereoDisplay d;
    const glm::dmat4 head = frameFromFront(box.min, box.max, 320.0 / 240.0, d);
    viewer.setTrackedHead(head);
    EXPECT_EQ(foregroundOf().second, framed.second);
    // Turned 180 degrees about the vertical: looking away from the sculpture.
    viewer.setTrackedHead(head * glm::rotate(glm::dmat4(1.0), M_PI, glm::dvec3(0, 1, 0)));
    EXPECT_EQ(foregroundOf().first, 0u);
    viewer.setTrackedHead(std::nullopt);
    EXPECT_EQ(foregroundOf().second, framed.second);
}

}  // namespace

namespace {

// Sketch mode draws the 3D view into the window's right half: nothing lands left of it, the
// sculpture is centred in its area, and picking rays follow the area.
TEST(Viewer, ViewAreaConfinesDrawingAndPicking) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 32;
    core::Sculpture s(cfg);
    core::Polygonizer poly(s, core::zoomRegion(cfg, s.levels(), 1, core::Vec3(0)),
                           core::PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    Viewer viewer(400, 200, "test", false);
    viewer.syncChunks(poly);
    const core::Aabb box = core::meshBounds(poly.mesh());
    ToolDraw tool;
    tool.visible = false;
    // A whole-window frame first (sculpture in the middle, over both halves); drawing into the
    // right half only must leave the left half exactly as it was (no swap in between).
    viewer.draw(glm::dmat4(1.0), box, tool, StereoMode::Mono, StereoDisplay{});
    const Image full = viewer.readFrame();
    EXPECT_NEAR(coverage(full, 0, 400, 0).centroidX, 200, 8);
    EXPECT_GT(coverage(full, 0, 200, 0).fraction, 0.05);
    viewer.setViewArea(200, 200);
    viewer.draw(glm::dmat4(1.0), box, tool, StereoMode::Mono, StereoDisplay{});
    const Image img = viewer.readFrame();
    size_t same = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < 200; ++x)
            same += std::equal(img.pixel(x, y), img.pixel(x, y) + 4, full.pixel(x, y));
    EXPECT_EQ(same, size_t(200 * img.height));
    const Coverage right = coverage(img, 200, 400, 0);
    EXPECT_GT(right.fraction, 0.1);
    EXPECT_NEAR(right.centroidX, 100, 8);  // centred in its area
    // The ray through the area's centre points at the sculpture's centre.
    core::Vec3 origin, dir;
    viewer.pixelRay(299.5, 99.5, origin, dir);
    const core::Vec3 c = 0.5 * (box.min + box.max);
    const core::Vec3 toC = glm::normalize(c - origin);
    EXPECT_GT(glm::dot(toC, dir), 0.9995);
    viewer.setViewArea(0, 0);
    viewer.draw(glm::dmat4(1.0), box, tool, StereoMode::Mono, StereoDisplay{});
    EXPECT_EQ(viewer.readFrame().rgba, full.rgba);
}

}  // namespace

namespace {

/// One headset eye drawn by Viewer::drawEye into a `size` x `size` sRGB texture (the format
/// runtimes offer first), read back as RGB; `stats`, when given, gets the draw's.
ToolDraw noTool() {
    ToolDraw tool;
    tool.visible = false;
    return tool;
}

std::vector<int> eyeImage(Viewer& viewer, const EyeView& eye, int size, FrameStats* stats = nullptr,
                          const ToolDraw& tool = noTool()) {
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_SRGB8_ALPHA8, size, size);
    glBindTexture(GL_TEXTURE_2D, 0);
    const FrameStats drawn = viewer.drawEye(glm::dmat4(1.0), tool, eye, texture, size, size);
    if (stats) *stats = drawn;
    std::vector<uint8_t> rgba(size_t(size) * size * 4);
    glBindTexture(GL_TEXTURE_2D, texture);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    glDeleteTextures(1, &texture);
    std::vector<int> rgb;
    for (size_t i = 0; i < rgba.size(); i += 4)
        rgb.insert(rgb.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
    return rgb;
}

}  // namespace

// A headset shows every aliased silhouette as a shimmer when the head moves. With multisampling
// asked for, the eye's picture is resolved from 4 samples a pixel: along the silhouette it lies
// much closer to the same eye drawn at 4 x 4 the resolution and averaged (the picture an ideal
// antialiasing gives) than the aliased picture does, and it covers the same area.
/// How close an `n` x `n` picture's silhouette comes to ideal antialiasing: `fine`, the same
/// view at k times the resolution, averaged over each k x k block. The silhouette's pixels are
/// those the sculpture covers in part (some of their k x k fine pixels, not all); `distance`
/// is a picture's mean difference from the averaged one there, `covered` the share of its
/// pixels the sculpture covers. Pictures are RGB, one int a channel, rows in order.
struct Antialiasing {
    std::vector<size_t> silhouette;
    std::vector<int> ideal;
    int n = 0;
    static bool isForeground(const int* p) { return std::abs(p[0] - int(kBackground[0])) > 12; }
    Antialiasing(const std::vector<int>& fine, int n, int k) : ideal(size_t(n) * n * 3), n(n) {
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                int part = 0;
                for (int j = 0; j < k; ++j)
                    for (int i = 0; i < k; ++i)
                        part += isForeground(
                            &fine[(size_t(y * k + j) * n * k + size_t(x * k + i)) * 3]);
                if (part > 0 && part < k * k) silhouette.push_back(size_t(y) * n + x);
                for (int c = 0; c < 3; ++c) {
                    int sum = 0;
                    for (int j = 0; j < k; ++j)
                        for (int i = 0; i < k; ++i)
                            sum += fine[(size_t(y * k + j) * n * k + size_t(x * k + i)) * 3 + c];
                    ideal[(size_t(y) * n + x) * 3 + c] = (sum + k * k / 2) / (k * k);
                }
            }
    }
    double distance(const std::vector<int>& img) const {
        double d = 0;
        for (size_t p : silhouette)
            for (int c = 0; c < 3; ++c)
                d += std::abs(img[p * 3 + c] - ideal[p * 3 + c]);
        return d / double(silhouette.size());
    }
    double covered(const std::vector<int>& img) const {
        size_t c = 0;
        for (size_t i = 0; i < img.size(); i += 3)
            c += isForeground(&img[i]);
        return double(c) / (double(n) * n);
    }
};

TEST(Viewer, HeadsetEyesAreAntialiasedWhenAsked) {
    const test::SculptureView scene(32);
    const core::Polygonizer& poly = *scene.poly;
    Viewer viewer(320, 240, "test", false);
    viewer.syncChunks(poly);
    StereoDisplay display;
    const core::Aabb box = core::meshBounds(poly.mesh());
    const EyeView eye = stereoEyes(frameFromFront(box.min, box.max, 1.0, display), display)[0];
    constexpr int n = 96, k = 4;
    EXPECT_EQ(viewer.eyeSamples(), 1) << "off unless asked";
    const std::vector<int> aliased = eyeImage(viewer, eye, n);
    const std::vector<int> fine = eyeImage(viewer, eye, n * k);
    ASSERT_EQ(viewer.setEyeSamples(4), 4) << "Mesa offers 4 samples";
    const std::vector<int> smooth = eyeImage(viewer, eye, n);
    const Antialiasing aa(fine, n, k);
    const double dAliased = aa.distance(aliased), dSmooth = aa.distance(smooth);
    std::printf(
        "silhouette pixels %zu; mean distance there to the 4x4-supersampled eye: aliased "
        "%.1f, 4 samples %.1f; covered %.3f / %.3f\n",
        aa.silhouette.size(), dAliased, dSmooth, aa.covered(aliased), aa.covered(smooth));
    ASSERT_GT(aa.silhouette.size(), size_t(n));
    EXPECT_GT(aa.covered(aliased), 0.1) << "the sculpture is in the picture";
    // Measured with Mesa's llvmpipe: 16.5 against 35.1 (a ratio of 0.47; what is left is the
    // shading, taken once a pixel at its centre). Without the resolve it would be 1.
    EXPECT_LT(dSmooth, 0.6 * dAliased);
    EXPECT_NEAR(aa.covered(smooth), aa.covered(aliased), 0.01);
    // And back off: the aliased picture again, bit for bit.
    EXPECT_EQ(viewer.setEyeSamples(1), 1);
    EXPECT_EQ(eyeImage(viewer, eye, n), aliased);
}

// The desktop window, asked for 4 samples a pixel (render.msaa_samples), gets a multisampled
// framebuffer: its silhouettes come out much closer to the supersampled picture than a plain
// window's, covering the same area.
TEST(Viewer, TheWindowIsAntialiasedWhenAsked) {
    const test::SculptureView scene(32);
    const core::Aabb box = core::meshBounds(scene.poly->mesh());
    constexpr int n = 96, k = 4;
    auto frame = [&](int size, int samples, int* got = nullptr) {
        Viewer viewer(size, size, "test", false, samples);
        if (got) *got = viewer.windowSamples();
        viewer.syncChunks(*scene.poly);
        viewer.draw(glm::dmat4(1.0), box, noTool(), StereoMode::Mono, StereoDisplay{});
        const Image img = viewer.readFrame();
        std::vector<int> rgb;
        for (size_t i = 0; i < img.rgba.size(); i += 4)
            rgb.insert(rgb.end(), {img.rgba[i], img.rgba[i + 1], img.rgba[i + 2]});
        return rgb;
    };
    int plainSamples = 0, samples = 0;
    const std::vector<int> aliased = frame(n, 1, &plainSamples);
    const std::vector<int> smooth = frame(n, 4, &samples);
    EXPECT_EQ(plainSamples, 1);
    ASSERT_EQ(samples, 4) << "Xvfb with Mesa offers multisampled visuals";
    const Antialiasing aa(frame(n * k, 1), n, k);
    const double dAliased = aa.distance(aliased), dSmooth = aa.distance(smooth);
    std::printf("window: silhouette pixels %zu; aliased %.1f, 4 samples %.1f\n",
                aa.silhouette.size(), dAliased, dSmooth);
    ASSERT_GT(aa.silhouette.size(), size_t(n));
    EXPECT_GT(aa.covered(aliased), 0.1) << "the sculpture is in the picture";
    EXPECT_LT(dSmooth, 0.6 * dAliased);
    EXPECT_NEAR(aa.covered(smooth), aa.covered(aliased), 0.01);
}

// The headset's pointer: the pen's ray to the panel is a thin bright line in the eye, bluish
// where the clay is grey, and it changes no pixel away from where the segment projects.
TEST(Viewer, HeadsetEyesDrawThePensPointerRay) {
    const test::SculptureView scene(32);
    Viewer viewer(320, 240, "test", false);
    viewer.syncChunks(*scene.poly);
    StereoDisplay display;
    const core::Aabb box = core::meshBounds(scene.poly->mesh());
    const EyeView eye = stereoEyes(frameFromFront(box.min, box.max, 1.0, display), display)[0];
    constexpr int n = 128;
    const std::vector<int> plain = eyeImage(viewer, eye, n);
    // A segment across the view, halfway between the eye and the sculpture.
    const core::Vec3 mid = 0.5 * (eye.worldPosition + 0.5 * (box.min + box.max));
    const glm::dmat4 clipFromWorld = eye.clipFromView * eye.viewFromWorld;
    auto pixelOf = [&](const core::Vec3& p) {
        const glm::dvec4 c = clipFromWorld * glm::dvec4(p, 1);
        // Rows as read back (GL's bottom row first).
        return glm::dvec2((c.x / c.w * 0.5 + 0.5) * n, (c.y / c.w * 0.5 + 0.5) * n);
    };
    ToolDraw tool = noTool();
    tool.pointer = true;
    const core::Vec3 right(glm::inverse(eye.viewFromWorld)[0]),
        up(glm::inverse(eye.viewFromWorld)[1]);
    const double span = 0.25 * glm::length(box.max - box.min);
    tool.pointerFrom = mid - span * right + 0.2 * span * up;
    tool.pointerTo = mid + span * right - 0.1 * span * up;
    const std::vector<int> pointed = eyeImage(viewer, eye, n, nullptr, tool);
    const glm::dvec2 a = pixelOf(tool.pointerFrom), b = pixelOf(tool.pointerTo);
    ASSERT_GT(glm::length(b - a), 0.5 * n) << "the segment crosses the eye";
    // Distance of a pixel's centre from the projected segment.
    auto offSegment = [&](int x, int y) {
        const glm::dvec2 p(x + 0.5, y + 0.5), d = b - a;
        const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
        return glm::length(p - (a + t * d));
    };
    size_t changed = 0, onRay = 0, bluish = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const size_t i = (size_t(y) * n + size_t(x)) * 3;
            const bool differs = pointed[i] != plain[i] || pointed[i + 1] != plain[i + 1] ||
                                 pointed[i + 2] != plain[i + 2];
            if (!differs) continue;
            ++changed;
            EXPECT_LT(offSegment(x, y), 1.5) << "pixel " << x << ", " << y;
            if (offSegment(x, y) < 0.5) {
                ++onRay;
                bluish += pointed[i + 2] - pointed[i] > 20 && pointed[i + 2] > 235;
            }
        }
    // About one pixel per column the segment crosses, drawn in the ray's colour.
    EXPECT_GT(changed, size_t(0.8 * std::abs(b.x - a.x)));
    EXPECT_LT(changed, size_t(3 * std::abs(b.x - a.x)));
    EXPECT_GT(bluish, onRay / 2) << onRay << " pixels on the ray";
    tool.pointer = false;
    EXPECT_EQ(eyeImage(viewer, eye, n, nullptr, tool), plain);
}

// Chunks wholly outside an eye's view are not drawn: zoomed in on one end of the bar, the eye
// draws fewer chunks and the very same picture as with every chunk drawn; turned away from the
// sculpture, it draws none.
TEST(Viewer, ChunksOutsideAnEyesViewAreSkippedAndNoPixelChanges) {
    const test::SculptureView scene(64);
    Viewer viewer(320, 240, "test", false);
    const size_t chunks = viewer.syncChunks(*scene.poly);
    StereoDisplay display;
    // The bar's right end fills the eye; most of the sculpture lies beyond its edges.
    const EyeView close = stereoEyes(
        frameFromFront(glm::dvec3(35, -25, -5), glm::dvec3(55, -5, 15), 1.0, display), display)[0];
    FrameStats culled, all;
    const std::vector<int> picture = eyeImage(viewer, close, 128, &culled);
    viewer.setChunkCulling(false);
    EXPECT_EQ(eyeImage(viewer, close, 128, &all), picture);
    EXPECT_EQ(all.chunksDrawn, chunks);
    std::printf("close-up: %zu of %zu chunks drawn\n", culled.chunksDrawn, chunks);
    EXPECT_LT(culled.chunksDrawn, chunks / 2);
    EXPECT_GT(culled.chunksDrawn, 0u);
    viewer.setChunkCulling(true);
    // Turned half round: the sculpture is behind the eye.
    EyeView away = close;
    away.viewFromWorld =
        glm::rotate(glm::dmat4(1.0), glm::pi<double>(), glm::dvec3(0, 1, 0)) * close.viewFromWorld;
    FrameStats none;
    eyeImage(viewer, away, 64, &none);
    EXPECT_EQ(none.chunksDrawn, 0u);
}
