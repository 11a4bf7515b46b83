// SPDX-License-Identifier: MIT
// Polygonizer benchmarks (issue #3). Results and commands: docs/benchmarks.md.
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"

#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <random>

using namespace vsculpt::core;

namespace {

/// A sculpted model around the initial sphere: 80 strokes of levels 3-7 over its surface,
/// adds and carves, deterministic. "Not a sphere": limbs, grooves, bumps at several sizes.
Sculpture& sculptedModel() {
    static std::unique_ptr<Sculpture> model = [] {
        SculptConfig cfg;
        auto s = std::make_unique<Sculpture>(cfg);
        std::mt19937 rng(2001);
        std::normal_distribution<double> N(0, 1);
        std::uniform_real_distribution<double> U(0, 1);
        for (int i = 0; i < 80; ++i) {
            const int level = 3 + i % 5;
            const ToolOp op = i % 4 == 3 ? ToolOp::Carve : ToolOp::Add;
            Vec3 p = glm::normalize(Vec3(N(rng), N(rng), N(rng))) * (40.0 + 8 * U(rng));
            Vec3 dir = glm::normalize(glm::cross(p, Vec3(N(rng), N(rng), N(rng))));
            StrokeBuilder stroke(*s, op, level);
            for (int k = 0; k < 30; ++k) {
                stroke.addSample(p);
                p += dir * 1.5;
                dir = glm::normalize(dir + 0.15 * Vec3(N(rng), N(rng), N(rng)));
            }
        }
        return s;
    }();
    return *model;
}

GridRegion modelRegion(int zoom) {
    Sculpture& s = sculptedModel();
    return zoomRegion(s.config(), s.levels(), zoom, Vec3(0, 0, 45));
}

void BM_FullPolygonize(benchmark::State& state) {
    Sculpture& s = sculptedModel();
    const GridRegion region = modelRegion(1);
    PolygonizeStats stats;
    size_t triangles = 0;
    for (auto _ : state) {
        const double tol = state.range(1) > 0 ? 1.0 / double(state.range(1))
                                              : s.config().polygonizer.bisectionTolerance;
        Polygonizer poly(s, region, tol);
        stats = poly.rebuildAll(state.range(0) != 0);
        state.PauseTiming();
        triangles = poly.mesh().triangleCount();
        state.ResumeTiming();
    }
    state.counters["N"] = region.n;
    state.counters["triangles"] = double(triangles);
    state.counters["evaluations"] = double(stats.evaluations);
    state.counters["skeletons"] = double(s.counts().total());
    state.counters["blocks_meshed"] = double(stats.blocksConsidered - stats.blocksCulled);
}
// Second argument: 1 / bisection tolerance (fraction of the spacing); 0 = the config's.
BENCHMARK(BM_FullPolygonize)
    ->ArgNames({"threaded", "inv_tol"})
    ->ArgsProduct({{1, 0}, {0}})
    ->ArgsProduct({{1}, {1000, 64, 8, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// The field alone at the grid vertices of the blocks the polygonizer meshes (LocalField per
/// block, as the polygonizer builds them): the per-evaluation cost to compare against.
void BM_FieldAtPolygonizerBlocks(benchmark::State& state) {
    Sculpture& s = sculptedModel();
    const GridRegion region = modelRegion(1);
    const int nb = region.n / Polygonizer::kBlockCells;
    std::vector<std::array<int, 3>> blocks;
    for (int x = 0; x < nb; ++x)
        for (int y = 0; y < nb; ++y)
            for (int z = 0; z < nb; ++z) {
                const Vec3 lo =
                    region.vertexPos(region.originCell[0] + 4 * x, region.originCell[1] + 4 * y,
                                     region.originCell[2] + 4 * z);
                const LocalField f(s, Aabb{lo, lo + Vec3(4 * region.spacingMm)});
                if (f.bounds().mayContainSurface()) blocks.push_back({x, y, z});
            }
    size_t evals = 0;
    double sink = 0;
    for (auto _ : state) {
        for (const auto& b : blocks) {
            const int64_t gx = region.originCell[0] + 4 * b[0],
                          gy = region.originCell[1] + 4 * b[1],
                          gz = region.originCell[2] + 4 * b[2];
            const Vec3 lo = region.vertexPos(gx, gy, gz);
            const LocalField f(s, Aabb{lo, lo + Vec3(4 * region.spacingMm)});
            for (int i = 0; i < 5; ++i)
                for (int j = 0; j < 5; ++j)
                    for (int k = 0; k < 5; ++k)
                        sink += f.value(region.vertexPos(gx + i, gy + j, gz + k));
            evals += 125;
        }
    }
    benchmark::DoNotOptimize(sink);
    state.counters["ns_per_eval"] = benchmark::Counter(
        double(evals), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["blocks"] = double(blocks.size());
}
BENCHMARK(BM_FieldAtPolygonizerBlocks)->Unit(benchmark::kMillisecond);

/// The same field sampled into an OpenVDB FloatGrid at the same spacing (only the blocks a
/// surface can pass, interior blocks filled as inside), then meshed by volumeToMesh.
void BM_FullPolygonizeOpenVDB(benchmark::State& state) {
    openvdb::initialize();
    Sculpture& s = sculptedModel();
    const GridRegion region = modelRegion(1);
    const int nb = region.n / Polygonizer::kBlockCells;
    double sampleMs = 0, meshMs = 0;
    size_t polygons = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        // Parallel sampling per block, then serial insertion (grids are not thread-safe).
        struct Block {
            std::array<int64_t, 3> g;
            int state = 0;  // 0 outside, 1 inside, 2 sampled
            std::array<float, 125> v{};
        };
        std::vector<Block> blocks(size_t(nb) * nb * nb);
        tbb::parallel_for(size_t(0), blocks.size(), [&](size_t i) {
            Block& b = blocks[i];
            const int x = int(i / (size_t(nb) * nb)), y = int(i / nb % nb), z = int(i % nb);
            b.g = {region.originCell[0] + 4 * x, region.originCell[1] + 4 * y,
                   region.originCell[2] + 4 * z};
            const Vec3 lo = region.vertexPos(b.g[0], b.g[1], b.g[2]);
            const LocalField f(s, Aabb{lo, lo + Vec3(4 * region.spacingMm)});
            const FieldBounds fb = f.bounds();
            if (!fb.mayContainSurface()) {
                b.state = fb.min > 0 ? 1 : 0;
                return;
            }
            b.state = 2;
            int n = 0;
            for (int i2 = 0; i2 < 5; ++i2)
                for (int j = 0; j < 5; ++j)
                    for (int k = 0; k < 5; ++k)  // OpenVDB level sets are negative inside
                        b.v[n++] =
                            float(-f.value(region.vertexPos(b.g[0] + i2, b.g[1] + j, b.g[2] + k)));
        });
        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(float(s.levels().iso()));
        grid->setTransform(openvdb::math::Transform::createLinearTransform(region.spacingMm));
        auto acc = grid->getAccessor();
        for (const Block& b : blocks) {
            if (b.state == 0) continue;
            const openvdb::Coord lo(int(b.g[0]), int(b.g[1]), int(b.g[2]));
            if (b.state == 1) {
                grid->tree().fill(openvdb::CoordBBox(lo, lo.offsetBy(4)), -1.0f, false);
                continue;
            }
            int n = 0;
            for (int i = 0; i < 5; ++i)
                for (int j = 0; j < 5; ++j)
                    for (int k = 0; k < 5; ++k)
                        acc.setValueOn(lo.offsetBy(i, j, k), b.v[n++]);
        }
        const auto t1 = std::chrono::steady_clock::now();
        std::vector<openvdb::Vec3s> points;
        std::vector<openvdb::Vec3I> tris;
        std::vector<openvdb::Vec4I> quads;
        openvdb::tools::volumeToMesh(*grid, points, tris, quads, 0.0, 0.0);
        const auto t2 = std::chrono::steady_clock::now();
        sampleMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
        meshMs += std::chrono::duration<double, std::milli>(t2 - t1).count();
        polygons = tris.size() + 2 * quads.size();
    }
    state.counters["sample_ms"] = sampleMs / state.iterations();
    state.counters["mesh_ms"] = meshMs / state.iterations();
    state.counters["triangles"] = double(polygons);
}
BENCHMARK(BM_FullPolygonizeOpenVDB)->Unit(benchmark::kMillisecond)->UseRealTime();

/// One tool sample end to end: skeleton placement, dirty-block rebuild and publishing the
/// changed chunks (building their upload meshes). The sculpture is the initial sphere
/// sculpted with strokes of every size until it holds the requested number of skeletons,
/// spread so that the skeleton density stays that of a sculpture (the sculpted shell grows
/// with the count). The measured stroke: 60 samples 0.25 D apart, skimming the surface, at
/// every size allowed at the zoom level. Reports p50/p99/max per sample.
Sculpture& modelWithSkeletons(size_t n) {
    static std::map<size_t, std::unique_ptr<Sculpture>> cache;
    auto& slot = cache[n];
    if (slot) return *slot;
    SculptConfig cfg;
    slot = std::make_unique<Sculpture>(cfg);
    Sculpture& s = *slot;
    std::mt19937 rng(7);
    std::normal_distribution<double> N(0, 1);
    // ~1000 skeletons per 60 mm x 60 mm patch of surface: the shell radius grows with n.
    const double radius = std::max(40.0, std::sqrt(double(n) / 1000.0 * 3600.0 / (4 * 3.14159)));
    int i = 0;
    while (s.store().vertexCount() < n) {
        const int level = 1 + i % 7;
        const ToolOp op = i % 5 == 4 ? ToolOp::Carve : ToolOp::Add;
        Vec3 p = glm::normalize(Vec3(N(rng), N(rng), N(rng))) * radius;
        Vec3 dir = glm::normalize(glm::cross(p, Vec3(N(rng), N(rng), N(rng))));
        StrokeBuilder stroke(s, op, level);
        const double step = 0.3 * s.levels().level(level).diameterMm;
        for (int k = 0; k < 25; ++k) {
            stroke.addSample(p);
            p += dir * step;
            p = glm::normalize(p) * radius;
            dir = glm::normalize(dir + 0.2 * Vec3(N(rng), N(rng), N(rng)));
        }
        ++i;
    }
    return s;
}

void BM_EditLatency(benchmark::State& state) {
    const size_t skeletons = size_t(state.range(0));
    const int zoom = int(state.range(1));
    const int level = int(state.range(2));
    Sculpture& s = modelWithSkeletons(skeletons);
    if (!toolAllowedAtZoom(s.config(), zoom, level)) {
        state.SkipWithError("size not allowed at this zoom");
        return;
    }
    // The surface straight above the centre: the first point outside going up.
    FieldProbe probe(s);
    Vec3 focus(0, 0, 0);
    while (probe.value(focus) > 0 && focus.z < 1e4)
        focus.z += 0.25;
    const GridRegion region = zoomRegion(s.config(), s.levels(), zoom, focus);
    Polygonizer poly(s, region, s.config().polygonizer.bisectionTolerance);
    poly.rebuildAll();
    const ToolLevel& l = s.levels().level(level);
    std::vector<Vec3> path;
    for (int i = 0; i < 60; ++i)
        path.push_back(focus + Vec3((i - 30) * 0.25 * l.diameterMm, 0, 0.25 * l.diameterMm));
    std::vector<double> ms, updateMs, publishMs;
    size_t evaluations = 0, blocks = 0, chunks = 0;
    for (auto _ : state) {
        std::vector<SkeletonChange> changes;
        {
            StrokeBuilder stroke(s, ToolOp::Add, level);
            for (const Vec3& p : path) {
                const auto t0 = std::chrono::steady_clock::now();
                const EditResult r = stroke.addSample(p);
                const PolygonizeStats st = poly.update(r.changedPoints, r.supportMm);
                const auto t1 = std::chrono::steady_clock::now();
                size_t uploaded = 0;
                for (const auto& c : st.changedChunks)
                    uploaded += poly.chunkMesh(c[0], c[1], c[2]).indices.size();
                benchmark::DoNotOptimize(uploaded);
                const auto t2 = std::chrono::steady_clock::now();
                ms.push_back(std::chrono::duration<double, std::milli>(t2 - t0).count());
                updateMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
                publishMs.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
                evaluations += st.evaluations;
                blocks += st.blocksConsidered;
                chunks += st.chunksChanged;
            }
            changes = stroke.takeChanges();
        }
        state.PauseTiming();
        poly.update(revertChanges(s, changes));
        state.ResumeTiming();
    }
    auto pct = [](std::vector<double> v, double q) {
        std::sort(v.begin(), v.end());
        return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
    };
    state.counters["p50_ms"] = pct(ms, 0.5);
    state.counters["p99_ms"] = pct(ms, 0.99);
    state.counters["max_ms"] = pct(ms, 1.0);
    state.counters["place_poly_p50_ms"] = pct(updateMs, 0.5);
    state.counters["publish_p50_ms"] = pct(publishMs, 0.5);
    state.counters["evals_per_sample"] = double(evaluations) / double(ms.size());
    state.counters["blocks_per_sample"] = double(blocks) / double(ms.size());
    state.counters["chunks_per_sample"] = double(chunks) / double(ms.size());
    state.counters["skeletons"] = double(s.counts().total());
}
BENCHMARK(BM_EditLatency)
    ->ArgNames({"skeletons", "zoom", "level"})
    ->ArgsProduct({{1000, 10000, 100000}, {1}, {7, 6, 5}})
    ->ArgsProduct({{1000, 10000, 100000}, {3}, {5, 4, 3}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace
