// SPDX-License-Identifier: MIT
// Sketch to clay (issue #8): how long a sketched solid takes to become clay and to show.
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/Zoom.h"
#include "vsculpt/sketch/SketchSolid.h"
#include "vsculpt/studio/Script.h"
#include "vsculpt/studio/Studio.h"

#include "../TestSolids.h"

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

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

/// What a pen stroke costs the sketch window's frame in a project: Studio::apply of one `pen`
/// command of 120 samples on a page that already holds range(0) strokes of 120 samples, 20
/// strokes timed per iteration. `wait:1` also waits for sketch.json after each step, as the
/// step did before the file went to its writer thread (stop 32; the step then also printed
/// the document twice, so before it cost more than this).
void BM_SketchStepInAProject(benchmark::State& state) {
    const size_t before = size_t(state.range(0));
    const bool wait = state.range(1) != 0;
    const auto dir = std::filesystem::temp_directory_path() /
                     ("vsculpt-bench-sketch-" + std::to_string(::getpid()));
    auto penLine = [](size_t k) {
        std::string line = "pen";
        for (int i = 0; i < 120; ++i) {
            const double a = 0.06 * i;
            line += " " + std::to_string(double(k % 40) * 3 + 20 * std::cos(a) + 0.1 * i) + "," +
                    std::to_string(double(k % 23) * 4 + 15 * std::sin(a));
        }
        return line + "\n";
    };
    std::vector<double> stepMs;
    for (auto _ : state) {
        state.PauseTiming();
        std::filesystem::remove_all(dir);
        auto studio = studio::Studio::openProject(dir, SculptConfig{});
        std::string setup = "page body Figure\nmode draft\n";
        for (size_t k = 0; k < before; ++k)
            setup += penLine(k);
        for (const studio::ScriptCommand& c : studio::parseScript(setup, "setup.vsc").commands)
            studio->apply(c);
        studio->waitForSketchFile();
        const auto steps = studio::parseScript(
            [&] {
                std::string t;
                for (size_t k = 0; k < 20; ++k)
                    t += penLine(before + k);
                return t;
            }(),
            "steps.vsc");
        state.ResumeTiming();
        for (const studio::ScriptCommand& c : steps.commands) {
            const auto t0 = std::chrono::steady_clock::now();
            studio->apply(c);
            if (wait) studio->waitForSketchFile();
            stepMs.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count());
        }
        state.PauseTiming();
        studio.reset();
        state.ResumeTiming();
    }
    std::filesystem::remove_all(dir);
    std::sort(stepMs.begin(), stepMs.end());
    state.counters["step_p50_ms"] = stepMs[stepMs.size() / 2];
    state.counters["step_max_ms"] = stepMs.back();
}
BENCHMARK(BM_SketchStepInAProject)
    ->ArgNames({"strokes", "wait"})
    ->ArgsProduct({{100, 600}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

/// What importing a large mesh costs the frame (the windows' import dialog): a ball of
/// about range(0) triangles, r = 80 mm over the initial sphere, as a binary STL, into a project
/// with asynchronous meshing as the windows run it. `frame_before_ms`: Studio::importMesh, which
/// the frame ran until stop 33. Now: Studio::importMeshInBackground (the check and the
/// sculpture's copy) and then a poll every 11.1 ms frame (90 Hz) until it lands; the frames'
/// largest poll is the one that commits it (the copy's after-states set here, journaled).
void BM_ImportRequest(benchmark::State& state) {
    const int rings = int(std::lround(std::sqrt(double(state.range(0)) / 4)));
    const auto dir = std::filesystem::temp_directory_path() /
                     ("vsculpt-bench-import-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto file = dir / "ball.stl";
    exportMesh(sphereMesh(Vec3(0), 80, rings, 2 * rings), file);
    SculptConfig cfg;
    (void)solidCalibration(Sculpture(cfg).levels());  // the one-off calibration, kept out
    auto fresh = [&](const char* name) {
        std::filesystem::remove_all(dir / name);
        auto studio = studio::Studio::openProject(dir / name, cfg);
        studio->setAsyncMeshing(true);
        return studio;
    };
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    double beforeMs = 0, startMs = 0, commitMs = 0, otherFramesMs = 0, landS = 0;
    size_t frames = 0, changed = 0;
    for (auto _ : state) {
        {
            auto studio = fresh("waited");
            const auto t0 = Clock::now();
            studio->importMesh(file);
            beforeMs = ms(t0, Clock::now());
            changed = studio->session().history().done().back().changes.size();
        }
        auto studio = fresh("background");
        const auto t0 = Clock::now();
        studio->importMeshInBackground(file);
        startMs = ms(t0, Clock::now());
        frames = 0;
        otherFramesMs = 0;
        for (auto next = t0;;) {
            next += std::chrono::microseconds(11111);
            std::this_thread::sleep_until(next);
            const auto f0 = Clock::now();
            const bool landed = studio->pollImport().has_value();
            const double frameMs = ms(f0, Clock::now());
            ++frames;
            if (landed) {
                commitMs = frameMs;
                landS = ms(t0, Clock::now()) / 1000;
                break;
            }
            otherFramesMs = std::max(otherFramesMs, frameMs);
        }
    }
    std::filesystem::remove_all(dir);
    state.counters["frame_before_ms"] = beforeMs;
    state.counters["start_ms"] = startMs;
    state.counters["commit_ms"] = commitMs;
    state.counters["max_other_frame_ms"] = otherFramesMs;
    state.counters["land_s"] = landS;
    state.counters["frames"] = double(frames);
    state.counters["vertices_changed"] = double(changed);
}
BENCHMARK(BM_ImportRequest)
    ->Arg(200000)
    ->Arg(2000000)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace vsculpt::core
