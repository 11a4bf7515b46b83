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
                                              : s.config().polygonizer.viewRootTolerance;
        Polygonizer poly(s, region, tol);
        stats = poly.rebuildAll(state.range(0) != 0);
        state.PauseTiming();
        triangles = poly.mesh().triangleCount();
        state.ResumeTiming();
    }
    state.counters["N"] = region.n;
    state.counters["triangles"] = double(triangles);
    state.counters["evaluations"] = double(stats.evaluations);
    state.counters["grid_values"] = double(stats.gridValues);
    state.counters["skeletons"] = double(s.counts().total());
    state.counters["blocks_meshed"] = double(stats.blocksConsidered - stats.blocksCulled);
}
// Second argument: 1 / root tolerance (fraction of the spacing); 0 = the config's for the mesh
// on show (a zoom change's rebuild), 100 = the exports' default.
BENCHMARK(BM_FullPolygonize)
    ->ArgNames({"threaded", "inv_tol"})
    ->ArgsProduct({{1, 0}, {0, 100}})
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

/// The same field sampled into an OpenVDB FloatGrid at the same spacing, then meshed by
/// volumeToMesh. The same pre-cull as Polygonizer::rebuildAll: one bounds test per chunk,
/// then per block in the chunks that may hold surface; only blocks the surface may cross
/// are sampled (chunks and blocks proven inside are filled as inside, which the dual
/// method needs for the sign). Sampled as the polygonizer samples its blocks: each skeleton
/// splatted onto the vertices it reaches, and a vertex that sampled blocks share sampled once
/// (a block leaves its far face on an axis to the next block when that one is sampled too),
/// so both sides pay the same per grid value. The per-block sample buffer is allocated once,
/// outside the timed loop (it used to be 17 MB allocated and zeroed in every iteration).
void BM_FullPolygonizeOpenVDB(benchmark::State& state) {
    openvdb::initialize();
    Sculpture& s = sculptedModel();
    const GridRegion region = modelRegion(1);
    constexpr int B = Polygonizer::kBlockCells, per = Polygonizer::kChunkCells / B;
    const int nb = region.n / B, nc = region.n / Polygonizer::kChunkCells;
    struct Block {
        Block(const std::array<int, 3>& at, const std::array<int64_t, 3>& g) : b(at), g(g) {}
        std::array<int, 3> b;  // block index
        std::array<int64_t, 3> g;
        int state = 0;                // 0 outside, 1 inside, 2 sampled
        std::array<int, 3> extent{};  // vertices sampled per axis (4 or 5)
        std::unique_ptr<LocalField> field;
        std::array<float, 125> v;  // left unset, not zeroed
    };
    std::vector<int> chunkState(size_t(nc) * nc * nc);  // 0 outside, 1 inside, 2 may cross
    std::vector<Block> blocks;
    blocks.reserve(size_t(nb) * nb * nb);
    std::vector<int> blockAt(size_t(nb) * nb * nb, -1);  // index into blocks
    double cullMs = 0, sampleMs = 0, meshMs = 0;
    size_t polygons = 0, sampled = 0, values = 0;
    auto boxAt = [&](int64_t gx, int64_t gy, int64_t gz, int cells) {
        const Vec3 lo = region.vertexPos(gx, gy, gz);
        return Aabb{lo, lo + Vec3(cells * region.spacingMm)};
    };
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        tbb::parallel_for(size_t(0), chunkState.size(), [&](size_t i) {
            const int64_t x = int64_t(i / (size_t(nc) * nc)), y = int64_t(i / nc % nc),
                          z = int64_t(i % nc);
            const LocalField f(s, boxAt(region.originCell[0] + 8 * x, region.originCell[1] + 8 * y,
                                        region.originCell[2] + 8 * z, 8));
            const FieldBounds fb = f.bounds();
            chunkState[i] = fb.mayContainSurface() ? 2 : fb.min > 0 ? 1 : 0;
        });
        blocks.clear();
        std::fill(blockAt.begin(), blockAt.end(), -1);
        for (size_t i = 0; i < chunkState.size(); ++i) {
            if (chunkState[i] != 2) continue;
            const int x = int(i / (size_t(nc) * nc)), y = int(i / nc % nc), z = int(i % nc);
            for (int bx = x * per; bx < (x + 1) * per; ++bx)
                for (int by = y * per; by < (y + 1) * per; ++by)
                    for (int bz = z * per; bz < (z + 1) * per; ++bz) {
                        blockAt[(size_t(bx) * nb + by) * nb + bz] = int(blocks.size());
                        blocks.emplace_back(std::array<int, 3>{bx, by, bz},
                                            std::array<int64_t, 3>{region.originCell[0] + B * bx,
                                                                   region.originCell[1] + B * by,
                                                                   region.originCell[2] + B * bz});
                    }
        }
        const auto t1 = std::chrono::steady_clock::now();
        tbb::parallel_for(size_t(0), blocks.size(), [&](size_t i) {
            Block& b = blocks[i];
            b.field = std::make_unique<LocalField>(s, boxAt(b.g[0], b.g[1], b.g[2], B));
            const FieldBounds fb = b.field->bounds();
            b.state = fb.mayContainSurface() ? 2 : fb.min > 0 ? 1 : 0;
            if (b.state != 2) b.field.reset();
        });
        auto sampledAt = [&](std::array<int, 3> n) {
            if (n[0] >= nb || n[1] >= nb || n[2] >= nb) return false;
            const int k = blockAt[(size_t(n[0]) * nb + n[1]) * nb + n[2]];
            return k >= 0 && blocks[size_t(k)].state == 2;
        };
        tbb::parallel_for(size_t(0), blocks.size(), [&](size_t i) {
            Block& b = blocks[i];
            if (b.state != 2) return;
            for (size_t a = 0; a < 3; ++a) {
                std::array<int, 3> n = b.b;
                ++n[a];
                b.extent[a] = sampledAt(n) ? B : B + 1;
            }
            double xs[5], ys[5], zs[5], v[125];
            for (int q = 0; q < 5; ++q) {
                const Vec3 p = region.vertexPos(b.g[0] + q, b.g[1] + q, b.g[2] + q);
                xs[q] = p.x;
                ys[q] = p.y;
                zs[q] = p.z;
            }
            b.field->gridValues(std::span(xs, size_t(b.extent[0])),
                                std::span(ys, size_t(b.extent[1])),
                                std::span(zs, size_t(b.extent[2])), v);
            for (int n = 0; n < b.extent[0] * b.extent[1] * b.extent[2]; ++n)
                b.v[size_t(n)] = float(-v[n]);  // OpenVDB level sets are negative inside
            b.field.reset();
        });
        // Serial insertion (grids are not thread-safe): the inside fills first, so that they
        // do not overwrite the faces of sampled blocks next to them.
        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(float(s.levels().iso()));
        grid->setTransform(openvdb::math::Transform::createLinearTransform(region.spacingMm));
        for (size_t i = 0; i < chunkState.size(); ++i) {
            if (chunkState[i] != 1) continue;
            const int x = int(i / (size_t(nc) * nc)), y = int(i / nc % nc), z = int(i % nc);
            const openvdb::Coord lo(int(region.originCell[0] + 8 * x),
                                    int(region.originCell[1] + 8 * y),
                                    int(region.originCell[2] + 8 * z));
            grid->tree().fill(openvdb::CoordBBox(lo, lo.offsetBy(8)), -1.0f, false);
        }
        for (const Block& b : blocks)
            if (b.state == 1) {
                const openvdb::Coord lo(int(b.g[0]), int(b.g[1]), int(b.g[2]));
                grid->tree().fill(openvdb::CoordBBox(lo, lo.offsetBy(4)), -1.0f, false);
            }
        auto acc = grid->getAccessor();
        sampled = values = 0;
        for (const Block& b : blocks) {
            if (b.state != 2) continue;
            ++sampled;
            const openvdb::Coord lo(int(b.g[0]), int(b.g[1]), int(b.g[2]));
            int n = 0;
            for (int i = 0; i < b.extent[0]; ++i)
                for (int j = 0; j < b.extent[1]; ++j)
                    for (int k = 0; k < b.extent[2]; ++k)
                        acc.setValueOn(lo.offsetBy(i, j, k), b.v[size_t(n++)]);
            values += size_t(n);
        }
        const auto t2 = std::chrono::steady_clock::now();
        std::vector<openvdb::Vec3s> points;
        std::vector<openvdb::Vec3I> tris;
        std::vector<openvdb::Vec4I> quads;
        openvdb::tools::volumeToMesh(*grid, points, tris, quads, 0.0, 0.0);
        const auto t3 = std::chrono::steady_clock::now();
        cullMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
        sampleMs += std::chrono::duration<double, std::milli>(t2 - t1).count();
        meshMs += std::chrono::duration<double, std::milli>(t3 - t2).count();
        polygons = tris.size() + 2 * quads.size();
    }
    state.counters["chunk_cull_ms"] = cullMs / double(state.iterations());
    state.counters["sample_ms"] = sampleMs / double(state.iterations());
    state.counters["mesh_ms"] = meshMs / double(state.iterations());
    state.counters["triangles"] = double(polygons);
    state.counters["blocks_sampled"] = double(sampled);
    state.counters["grid_values"] = double(values);
}
BENCHMARK(BM_FullPolygonizeOpenVDB)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
