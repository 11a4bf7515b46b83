// SPDX-License-Identifier: MIT
// Renderer benchmarks (issue #5). They need a display: run the benchmark executable under
// `xvfb-run -a` on machines without one; without a display they are skipped. The GL
// renderer is reported in the "renderer" label. Results and commands: docs/benchmarks.md.
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/render/RayTrace.h"
#include "vsculpt/render/StereoCamera.h"
#include "vsculpt/render/Viewer.h"

#include <benchmark/benchmark.h>
#include <epoxy/gl.h>

#include <chrono>
#include <cstring>
#include <map>
#include <memory>
#include <vector>

using namespace vsculpt;
using core::Vec3;

namespace {

/// The initial sphere (r = 40 mm) polygonized finely enough for ~N triangles.
struct Scene {
    std::unique_ptr<core::Sculpture> sculpture;
    std::unique_ptr<core::Polygonizer> poly;
};

Scene& sceneWith(long triangles) {
    static std::map<long, Scene> cache;
    Scene& sc = cache[triangles];
    if (sc.poly) return sc;
    core::SculptConfig cfg;
    sc.sculpture = std::make_unique<core::Sculpture>(cfg);
    // A sphere of radius r meshed at spacing h gives about 9 * 4 pi r^2 / h^2 triangles (Kuhn
    // tetrahedra cut several triangles per surface cell).
    const double h = std::sqrt(9.0 * 4 * 3.14159 * 1600.0 / double(triangles));
    core::GridRegion r;
    r.spacingMm = h;
    r.n = int(std::ceil(90.0 / h / 16)) * 16;
    for (int a = 0; a < 3; ++a)
        r.originCell[a] = -r.n / 2;
    sc.poly = std::make_unique<core::Polygonizer>(*sc.sculpture, r,
                                                  core::PolygonizerConfig{}.rootTolerance);
    sc.poly->rebuildAll();
    return sc;
}

std::unique_ptr<render::Viewer> makeViewer(benchmark::State& state) {
    try {
        return std::make_unique<render::Viewer>(1280, 800, "bench", false);
    } catch (const std::exception& e) {
        state.SkipWithError("no display: run under xvfb-run");
        return nullptr;
    }
}

/// One frame: draw calls for every chunk and the tool, then glFinish (so llvmpipe's
/// rasterisation on the CPU is included in the wall time).
void BM_FrameDraw(benchmark::State& state) {
    auto viewer = makeViewer(state);
    if (!viewer) return;
    Scene& sc = sceneWith(state.range(0));
    viewer->syncChunks(*sc.poly);
    const core::Aabb box{Vec3(-40), Vec3(40)};
    render::ToolDraw tool;
    tool.worldPos = Vec3(0, -45, 0);
    double cpu = 0;
    size_t tris = 0;
    for (auto _ : state) {
        const render::FrameStats st =
            viewer->draw(glm::dmat4(1.0), box, tool, render::StereoMode::Mono, {});
        viewer->finish();
        cpu += st.cpuMs;
        tris = st.triangles;
    }
    state.counters["triangles"] = double(tris);
    state.counters["cpu_ms_per_frame"] = cpu / double(state.iterations());
    state.SetLabel(viewer->rendererName());
}
BENCHMARK(BM_FrameDraw)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

/// One headset frame as the OpenXR loop draws it (app/src/XrWindow.cpp): both eyes through
/// Viewer::drawEye into swapchain-sized textures (2064 x 2208 per eye, a current headset's
/// recommended size), then glFinish. The window itself stays small and hidden: a headset frame
/// never draws into it. range(1): samples a pixel (Viewer::setEyeSamples; 1: off). range(2):
/// 0 frames the whole sphere, 1 a 20 mm close-up of its front (sculpting detail: most chunks
/// lie outside the eyes' views and are culled). range(3): 0 turns the culling off
/// (Viewer::setChunkCulling), to compare.
void BM_HeadsetFrame(benchmark::State& state) {
    auto viewer = makeViewer(state);
    if (!viewer) return;
    state.counters["samples"] = viewer->setEyeSamples(int(state.range(1)));
    viewer->setChunkCulling(state.range(3) != 0);
    Scene& sc = sceneWith(state.range(0));
    viewer->syncChunks(*sc.poly);
    constexpr int width = 2064, height = 2208;
    GLuint textures[2];
    glGenTextures(2, textures);
    for (GLuint t : textures) {
        glBindTexture(GL_TEXTURE_2D, t);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_SRGB8_ALPHA8, width, height);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    render::StereoDisplay display;
    const bool close = state.range(2) != 0;
    const glm::dmat4 worldFromHead = render::frameFromFront(
        close ? glm::dvec3(-10, -45, -10) : glm::dvec3(-40),
        close ? glm::dvec3(10, -35, 10) : glm::dvec3(40), double(width) / height, display);
    const auto eyes = render::stereoEyes(worldFromHead, display);
    render::ToolDraw tool;
    tool.worldPos = Vec3(0, -45, 0);
    double cpu = 0;
    size_t tris = 0, draws = 0;
    for (auto _ : state) {
        tris = 0;
        draws = 0;
        for (int e = 0; e < 2; ++e) {
            const render::FrameStats st =
                viewer->drawEye(glm::dmat4(1.0), tool, eyes[size_t(e)], textures[e], width, height);
            cpu += st.cpuMs;
            tris += st.triangles;
            draws += st.chunksDrawn;
        }
        viewer->finish();
    }
    // What share of the left eye's picture differs from its corner (the background): a frame
    // that drew nothing would be timed as a fast one.
    std::vector<uint8_t> rgba(size_t(width) * height * 4);
    glBindTexture(GL_TEXTURE_2D, textures[0]);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    size_t covered = 0;
    for (size_t i = 0; i < rgba.size(); i += 4)
        covered += std::memcmp(&rgba[i], rgba.data(), 3) != 0;
    glDeleteTextures(2, textures);
    state.counters["covered"] = double(covered) / (double(width) * height);
    state.counters["triangles_both_eyes"] = double(tris);
    state.counters["chunks_both_eyes"] = double(draws);
    state.counters["cpu_ms_per_frame"] = cpu / double(state.iterations());
    state.SetLabel(viewer->rendererName());
}
BENCHMARK(BM_HeadsetFrame)
    ->ArgsProduct({{100000, 1000000}, {1, 4}, {0, 1}, {1}})
    ->ArgsProduct({{100000, 1000000}, {1}, {0, 1}, {0}})
    ->ArgNames({"triangles", "samples", "close", "cull"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// Re-uploading one changed chunk (its mesh built from the polygonizer's blocks, then the
/// buffer upload).
void BM_ChunkUpload(benchmark::State& state) {
    auto viewer = makeViewer(state);
    if (!viewer) return;
    Scene& sc = sceneWith(state.range(0));
    viewer->syncChunks(*sc.poly);
    size_t uploads = 0;
    bool flip = false;
    for (auto _ : state) {
        state.PauseTiming();
        // A tiny edit on the sphere's top changes a handful of chunks.
        core::StrokeBuilder stroke(*sc.sculpture, flip ? core::ToolOp::Carve : core::ToolOp::Add,
                                   1);
        const core::EditResult r = stroke.addSample(Vec3(0.3, 0.2, 40));
        sc.poly->update(r.changedPoints, r.supportMm);
        flip = !flip;
        state.ResumeTiming();
        uploads += viewer->syncChunks(*sc.poly);
        viewer->finish();
    }
    state.counters["chunks_per_edit"] = double(uploads) / double(state.iterations());
    state.counters["ms_per_chunk"] = benchmark::Counter(
        double(uploads) / 1000.0, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ChunkUpload)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

/// From a tool sample to the finished frame that shows it, as in the desktop loop:
/// placement, polygonizer update, chunk uploads, draw, glFinish. Zoom-1 grid, level 5.
void BM_SampleToFrame(benchmark::State& state) {
    auto viewer = makeViewer(state);
    if (!viewer) return;
    core::SculptConfig cfg;
    core::Sculpture s(cfg);
    core::Polygonizer poly(s, core::zoomRegion(cfg, s.levels(), 1, Vec3(0)),
                           core::PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    viewer->syncChunks(poly);
    const core::Aabb box{Vec3(-60), Vec3(60)};
    render::ToolDraw tool;
    int i = 0;
    std::vector<core::SkeletonChange> all;
    auto stroke = std::make_unique<core::StrokeBuilder>(s, core::ToolOp::Add, 5);
    for (auto _ : state) {
        const Vec3 p(-30 + (i++ % 60), -38, 10);
        const core::EditResult r = stroke->addSample(p);
        poly.update(r.changedPoints, r.supportMm);
        viewer->syncChunks(poly);
        tool.worldPos = p;
        viewer->draw(glm::dmat4(1.0), box, tool, render::StereoMode::Mono, {});
        viewer->finish();
    }
    state.SetLabel(viewer->rendererName());
}
BENCHMARK(BM_SampleToFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

/// A ray-traced still (`vsculpt render`'s default shading) of the 1e5-triangle sphere at
/// 640x480 with 16 ambient-occlusion and 8 shadow rays per pixel, through Embree in its
/// robust (watertight) mode. Needs no display. items/s = primary rays per second.
void BM_RayTraceStill(benchmark::State& state) {
    const core::Mesh mesh = sceneWith(100000).poly->mesh();
    render::RayTraceOptions o;
    o.width = 640;
    o.height = 480;
    o.aoSamples = 16;
    o.shadowSamples = 8;
    for (auto _ : state)
        benchmark::DoNotOptimize(render::rayTrace(mesh, o));
    state.SetItemsProcessed(state.iterations() * o.width * o.height);
    state.counters["triangles"] = double(mesh.triangleCount());
}
BENCHMARK(BM_RayTraceStill)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
