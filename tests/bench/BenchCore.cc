// SPDX-License-Identifier: MIT
// vsculpt_bench: core benchmarks. Results and the command that produced them are recorded
// in docs/benchmarks.md. Run: build/tests/vsculpt_bench [--benchmark_filter=...]
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/studio/PickTool.h"
#include "vsculpt/studio/Session.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

using namespace vsculpt::core;

namespace {

/// One "motif": a small sculpted piece (a large body, medium limbs, fine detail strokes and a
/// few carves), different for every seed. Sculptures of growing size are built from more
/// motifs side by side, so the local skeleton density, and so the work per evaluation near
/// the surface, is the same at every size.
void sculptMotif(Sculpture& s, const Vec3& origin, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-1, 1);
    auto walk = [&](ToolOp op, int level, int samples, double stepMm, const Vec3& start) {
        StrokeBuilder stroke(s, op, level);
        Vec3 p = start, dir = glm::normalize(Vec3(U(rng), U(rng), U(rng)));
        for (int i = 0; i < samples; ++i) {
            stroke.addSample(origin + p);
            dir = glm::normalize(dir + 0.35 * Vec3(U(rng), U(rng), U(rng)));
            p += dir * stepMm;
        }
    };
    walk(ToolOp::Add, 7, 6, 8.0, Vec3(0));
    for (int i = 0; i < 2; ++i)
        walk(ToolOp::Add, 5, 10, 4.0, Vec3(U(rng), U(rng), U(rng)) * 15.0);
    for (int i = 0; i < 3; ++i)
        walk(ToolOp::Add, 3, 14, 2.0, Vec3(U(rng), U(rng), U(rng)) * 20.0);
    for (int i = 0; i < 2; ++i)
        walk(ToolOp::Carve, 2, 14, 1.5, Vec3(U(rng), U(rng), U(rng)) * 18.0);
    walk(ToolOp::Add, 1, 20, 1.0, Vec3(U(rng), U(rng), U(rng)) * 20.0);
}

struct Fixture {
    std::unique_ptr<Sculpture> sculpture;
    std::vector<Vec3> queries;  // points near skeletons, within their support
    int motifs = 0;
};

Fixture& sculptureWith(size_t skeletons) {
    static std::map<size_t, Fixture> cache;
    Fixture& f = cache[skeletons];
    if (f.sculpture) return f;
    SculptConfig cfg;
    cfg.sphereRadiusMm = 0;
    f.sculpture = std::make_unique<Sculpture>(cfg);
    Sculpture& s = *f.sculpture;
    const double pitch = 110.0;  // mm between motifs: they do not touch
    while (s.store().vertexCount() < skeletons) {
        const int i = f.motifs++;
        const Vec3 origin = Vec3(i % 16, (i / 16) % 16, i / 256) * pitch;
        sculptMotif(s, origin, unsigned(i) * 7919u + 1u);
    }
    // Queries: around random skeletons, uniformly in their support ball.
    std::vector<SkeletonEntry> entries;
    s.store().forEach([&](const SkeletonEntry& e) { entries.push_back(e); });
    std::mt19937 rng(42);
    std::uniform_int_distribution<size_t> pick(0, entries.size() - 1);
    std::uniform_real_distribution<double> U(-1, 1);
    while (f.queries.size() < (1u << 16)) {
        const SkeletonEntry& e = entries[pick(rng)];
        const ToolLevel& l = s.levels().level(e.level);
        const Vec3 d(U(rng), U(rng), U(rng));
        if (glm::dot(d, d) > 1) continue;
        f.queries.push_back(Vec3(e.coord.x, e.coord.y, e.coord.z) * l.spacingMm + d * l.supportMm);
    }
    return f;
}

/// Field evaluation the way the polygonizer asks for it: blocks of 4x4x4 points 1 mm apart
/// around random places on the sculpture (one block per skeleton drawn at random).
void BM_FieldEval(benchmark::State& state) {
    Fixture& f = sculptureWith(size_t(state.range(0)));
    FieldProbe probe(*f.sculpture);
    size_t i = 0;
    double sink = 0;
    for (auto _ : state) {
        const Vec3 c = f.queries[i++ & (f.queries.size() - 1)];
        for (int x = 0; x < 4; ++x)
            for (int y = 0; y < 4; ++y)
                for (int z = 0; z < 4; ++z)
                    sink += probe.value(c + Vec3(x, y, z));
    }
    benchmark::DoNotOptimize(sink);
    const Sculpture& s = *f.sculpture;
    state.SetItemsProcessed(state.iterations() * 64);
    state.counters["skeletons"] = double(s.counts().total());
    state.counters["bytes_per_skeleton"] = double(s.store().memoryBytes()) / s.counts().total();
    state.counters["ns_per_eval"] = benchmark::Counter(
        double(state.iterations()) * 64, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_FieldEval)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMicrosecond);

/// Single points in random order all over the sculpture: every query is a cache miss, the
/// worst case for memory latency, not for the algorithm.
void BM_FieldEvalRandomOrder(benchmark::State& state) {
    Fixture& f = sculptureWith(size_t(state.range(0)));
    FieldProbe probe(*f.sculpture);
    size_t i = 0;
    double sink = 0;
    for (auto _ : state) {
        sink += probe.value(f.queries[i++ & (f.queries.size() - 1)]);
    }
    benchmark::DoNotOptimize(sink);
    const Sculpture& s = *f.sculpture;
    state.SetItemsProcessed(state.iterations());
    state.counters["skeletons"] = double(s.counts().total());
    state.counters["motifs"] = f.motifs;
    state.counters["bytes_per_skeleton"] = double(s.store().memoryBytes()) / s.counts().total();
    for (int k = 1; k <= kLevelCount; ++k) {
        const auto st = s.store().stats(k);
        state.counters["L" + std::to_string(k) + "_B_per_skel"] =
            double(st.bytes) / std::max<size_t>(1, st.vertices);
        state.counters["L" + std::to_string(k) + "_skel_per_leaf"] =
            double(st.vertices) / std::max<size_t>(1, st.blocks);
    }
}
BENCHMARK(BM_FieldEvalRandomOrder)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kNanosecond);

void BM_FieldEvalWithGradient(benchmark::State& state) {
    Fixture& f = sculptureWith(size_t(state.range(0)));
    FieldProbe probe(*f.sculpture);
    size_t i = 0;
    double sink = 0;
    for (auto _ : state)
        sink += probe.sample(f.queries[i++ & (f.queries.size() - 1)]).gradient.x;
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FieldEvalWithGradient)->Arg(1000)->Arg(1000000)->Unit(benchmark::kNanosecond);

/// Placement throughput: one stroke of 100 tool samples, 0.25 D apart, through the middle
/// of a sculpted motif of the 1e4 sculpture; undone between iterations (not timed).
void BM_StrokePlacement(benchmark::State& state) {
    const int level = int(state.range(0));
    const ToolOp op = state.range(1) == 0 ? ToolOp::Add : ToolOp::Carve;
    Fixture& f = sculptureWith(10000);
    Sculpture& s = *f.sculpture;
    const ToolLevel& l = s.levels().level(level);
    std::vector<Vec3> path;
    for (int i = 0; i < 100; ++i)
        path.push_back(Vec3(-12, 3, 1) + Vec3(0.25 * l.diameterMm * i, 0.1 * i, 0));
    size_t vertices = 0;
    for (auto _ : state) {
        std::vector<SkeletonChange> changes;
        const EditResult r = applyStroke(s, op, level, path, &changes);
        vertices += size_t(r.changedVertices);
        state.PauseTiming();
        revertChanges(s, changes);
        state.ResumeTiming();
    }
    state.counters["samples_per_s"] =
        benchmark::Counter(100.0 * state.iterations(), benchmark::Counter::kIsRate);
    state.counters["skeletons_per_s"] =
        benchmark::Counter(double(vertices), benchmark::Counter::kIsRate);
    state.counters["skeletons_per_stroke"] = double(vertices) / state.iterations();
}
BENCHMARK(BM_StrokePlacement)
    ->ArgsProduct({{1, 3, 5, 7}, {0, 1}})
    ->ArgNames({"level", "carve"})
    ->Unit(benchmark::kMicrosecond);

// The window's pointer pick, once a frame (studio/PickTool.h): outside a stroke it marches the
// live field along the ray; during one, the field as it was before the stroke (the stroke's
// changed weights taken off at each step), so the tool never climbs the clay it adds.
// in_stroke:1 is after 40 samples of a size-7 add along the sphere's front, under the ray.
void BM_PickTool(benchmark::State& state) {
    vsculpt::studio::Session s{SculptConfig{}};
    const bool inStroke = state.range(0) != 0;
    const double radius = 0.5 * s.sculpture().levels().level(7).diameterMm;
    if (inStroke) {
        s.beginStroke();
        for (int i = 0; i < 40; ++i)
            s.strokeSample(Vec3(-20 + i, -40 - radius, 0), false);
    }
    const Vec3 origin(0, -300, 0), dir(0, 1, 0), down(0, 0, -1);
    for (auto _ : state)
        benchmark::DoNotOptimize(vsculpt::studio::pickTool(s, origin, dir, radius, 0, down));
    if (inStroke) s.endStroke();
}
BENCHMARK(BM_PickTool)->Arg(0)->Arg(1)->ArgName("in_stroke")->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
