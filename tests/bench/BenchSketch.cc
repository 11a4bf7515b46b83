// SPDX-License-Identifier: MIT
// Sketch to clay (issue #8): how long a sketched solid takes to become clay and to show.
#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/Zoom.h"
#include "vsculpt/sketch/SketchSolid.h"

#include "../TestSolids.h"

#include <benchmark/benchmark.h>

#include <cmath>

namespace vsculpt::core {
namespace {

/// placeSolid of a sphere (48 x 96 UV mesh) of radius range(0) mm at its default level,
/// beside the initial sphere; undone between iterations (untimed). The first call per process
/// pays the one-off calibration (about 0.8 s), kept out by a warm-up.
void BM_PlaceSolid(benchmark::State& state) {
    const double r = double(state.range(0));
    SculptConfig cfg;
    Sculpture s(cfg);
    const Mesh solid = sphereMesh(Vec3(60 + r, 0, 0), r);
    revertChanges(s, placeSolid(s, solid, 0).changes);  // warm-up: calibration
    size_t changed = 0;
    int level = 0;
    for (auto _ : state) {
        const SolidPlacement p = placeSolid(s, solid, 0);
        changed += p.changes.size();
        level = p.level;
        state.PauseTiming();
        revertChanges(s, p.changes);
        state.ResumeTiming();
    }
    state.counters["level"] = level;
    state.counters["vertices"] = double(changed) / double(state.iterations());
}
BENCHMARK(BM_PlaceSolid)->Arg(10)->Arg(25)->Arg(50)->Unit(benchmark::kMillisecond);

/// The whole step a designer waits for after pressing "inflate": Teddy inflation of a circle
/// outline (r = range(0) mm, 120 points), triangulation, placeSolid and the polygonizer's
/// incremental update of the zoom-1 view (N = 128).
void BM_SketchToClay(benchmark::State& state) {
    const double r = double(state.range(0));
    SculptConfig cfg;
    Sculpture s(cfg);
    Polygonizer view(s, zoomRegion(cfg, s.levels(), 1, Vec3(0)),
                     PolygonizerConfig{}.viewRootTolerance);
    view.rebuildAll();
    sketch::SketchSolidInput in;
    in.construction = sketch::SolidConstruction::Inflate;
    sketch::SketchCurve outline;
    outline.closed = true;
    for (int i = 0; i < 120; ++i) {
        const double a = 2 * M_PI * i / 120;
        outline.points.push_back({60 + r + r * std::cos(a), r * std::sin(a)});
    }
    in.outline = outline;
    {
        const sketch::SketchSolid warm = sketch::buildSketchSolid(in);
        Mesh m;
        m.positions.assign(warm.triangles.positions.begin(), warm.triangles.positions.end());
        m.indices = warm.triangles.indices;
        revertChanges(s, placeSolid(s, m, 0).changes);
    }
    for (auto _ : state) {
        const sketch::SketchSolid built = sketch::buildSketchSolid(in);
        Mesh m;
        m.positions.assign(built.triangles.positions.begin(), built.triangles.positions.end());
        m.indices = built.triangles.indices;
        const SolidPlacement p = placeSolid(s, m, 0);
        view.update(p.edit.changedPoints, p.edit.supportMm);
        state.PauseTiming();
        view.update(revertChanges(s, p.changes));
        state.ResumeTiming();
    }
}
BENCHMARK(BM_SketchToClay)->Arg(15)->Arg(30)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vsculpt::core
