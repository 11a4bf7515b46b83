// SPDX-License-Identifier: MIT
/// @file BenchEditLatency.cc
/// @brief Edit latency on piled-up clay (issue #14): vsculpt's synchronous placement and
/// dirty-block rebuild against an OpenVDB narrow-band level set stamping the same spheres,
/// a headless frame loop, and memory at 1e5/1e6 skeletons. Results and commands:
/// docs/benchmarks.md.
#include "vsculpt/core/AsyncMesher.h"
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/History.h"
#include "vsculpt/core/MeshChunks.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/ToolLevels.h"
#include "vsculpt/studio/Session.h"

#include <benchmark/benchmark.h>
#include <malloc.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/parallel_for.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <tuple>

using namespace vsculpt::core;

namespace {

using Clock = std::chrono::steady_clock;

// Strokes hold back their small weight changes until their end, as the session places them
// (StrokeBuilder::holdBackChangesBelow); VSCULPT_BENCH_NO_HOLD=1 writes every change at once
// (the rule before, for the A/B in docs/benchmarks.md).
bool holdBack() {
    static const bool hold = !std::getenv("VSCULPT_BENCH_NO_HOLD");
    return hold;
}

double msSince(Clock::time_point t0, Clock::time_point t1) {
    return std::chrono::duration<double, std::milli>(t1 - t0).count();
}

double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// q-quantile (0..1) by nearest rank; 0 for an empty list.
double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

void reportPercentiles(benchmark::State& state, const std::string& prefix,
                       const std::vector<double>& ms) {
    state.counters[prefix + "p50_ms"] = quantile(ms, 0.5);
    state.counters[prefix + "p99_ms"] = quantile(ms, 0.99);
    state.counters[prefix + "max_ms"] = quantile(ms, 1.0);
}

/// Where the clay piles up: on top of the initial sphere (r = 40 mm at the origin).
const Vec3 kPileCenter(0, 0, 40);
constexpr double kPileRadiusMm = 45;    // pile strokes wander within this of kPileCenter
constexpr double kPileKeepOutMm = 110;  // scattered strokes stay this far from it
constexpr int kPileStrokes = 1400;

/// A model of (at least) n skeletons: a pile of kPileStrokes strokes of every size, adds and
/// carves, crossing each other within 45 mm of the top of the initial sphere (the piled-up
/// clay of issue #14: zoom-1 blocks there gather 70-100 skeletons, up to ~340), and strokes
/// scattered in a ball around it until the count is reached. The pile is the same in every
/// model. Every stroke is recorded in `history`, as a session would keep it.
struct DenseModel {
    std::unique_ptr<Sculpture> sculpture;
    History history;
    size_t pileSkeletons = 0;
    double buildSeconds = 0;
};

DenseModel& denseModel(size_t n) {
    static std::map<size_t, DenseModel> cache;
    DenseModel& m = cache[n];
    if (m.sculpture) return m;
    const auto t0 = Clock::now();
    // The models are built in `free` mode, as the tables in docs/benchmarks.md were measured;
    // VSCULPT_BENCH_PLACEMENT=swept builds them (and sculpts) in the default mode.
    SculptConfig cfg;
    const char* mode = std::getenv("VSCULPT_BENCH_PLACEMENT");
    cfg.placement =
        mode && std::string(mode) == "swept" ? PlacementMode::Swept : PlacementMode::Free;
    // VSCULPT_BENCH_FINER_LEVELS=k: placement.finer_lattice_levels (swept mode only).
    if (const char* finer = std::getenv("VSCULPT_BENCH_FINER_LEVELS"))
        cfg.finerLatticeLevels = std::atoi(finer);
    m.sculpture = std::make_unique<Sculpture>(cfg);
    Sculpture& s = *m.sculpture;
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> U(-1, 1);
    auto randomUnit = [&] {
        for (;;) {
            const Vec3 d(U(rng), U(rng), U(rng));
            const double l = glm::length(d);
            if (l > 0.1 && l <= 1) return d / l;
        }
    };
    // One random walk that turns back where `keep` says no (samples it refuses are skipped).
    auto walk = [&](ToolOp op, int level, Vec3 p, int samples, auto keep) {
        const double step = 0.3 * s.levels().level(level).diameterMm;
        StrokeRecord record;
        record.op = op;
        record.level = level;
        StrokeBuilder stroke(s, op, level);
        Vec3 dir = randomUnit();
        for (int k = 0; k < samples; ++k) {
            if (keep(p)) {
                stroke.addSample(p);
                record.samples.push_back(p);
            }
            dir = glm::normalize(dir + 0.5 * randomUnit());
            if (!keep(p + dir * step)) dir = -dir;
            p += dir * step;
        }
        stroke.finish();
        record.changes = stroke.takeChanges();
        m.history.push(std::move(record));
    };
    for (int i = 0; i < kPileStrokes; ++i) {
        const int level = 1 + i % 7;
        const ToolOp op = i % 6 == 5 ? ToolOp::Carve : ToolOp::Add;
        const Vec3 start = kPileCenter + randomUnit() * (kPileRadiusMm * std::abs(U(rng)));
        walk(op, level, start, 30,
             [&](const Vec3& p) { return glm::length(p - kPileCenter) < kPileRadiusMm; });
    }
    m.pileSkeletons = s.store().vertexCount();
    // Scattered clay: walks starting anywhere in a ball that grows with n (at most 170 mm,
    // inside the zoom-1 region), away from the pile.
    const double ball = std::min(170.0, 60.0 + 110.0 * std::cbrt(double(n) / 1e6));
    for (int i = 0; s.store().vertexCount() < n; ++i) {
        const int level = 1 + i % 7;
        const ToolOp op = i % 5 == 4 ? ToolOp::Carve : ToolOp::Add;
        const Vec3 start = randomUnit() * (ball * std::cbrt(std::abs(U(rng))));
        walk(op, level, start, 60, [&](const Vec3& p) {
            return glm::length(p - kPileCenter) > kPileKeepOutMm && glm::length(p) < ball;
        });
    }
    m.buildSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return m;
}

/// The smallest model: the pile alone (its ~17 k skeletons are more than the 1e4 asked).
constexpr size_t kPileOnly = 10000;

/// The pile's top surface above (x, y): the first point with f > 0 going down.
Vec3 surfaceAbove(FieldProbe& probe, double x, double y) {
    for (double z = kPileCenter.z + 80; z > kPileCenter.z - 80; z -= 0.125)
        if (probe.value(Vec3(x, y, z)) > 0) return Vec3(x, y, z);
    return Vec3(x, y, kPileCenter.z);
}

/// The measured strokes: straight (in plan) through the top of the pile, following its
/// surface (the tool centre on the pre-stroke surface: half the ball in dense clay), samples
/// 0.25 D apart, as long as fits the zoom region (min(6 D, 0.35 N spacing)). Stroke r of
/// `count` crosses at an angle of r * 180° / count, so the repetitions meet different clay.
struct Strokes {
    GridRegion region;
    std::vector<std::vector<Vec3>> paths;
};

Strokes measuredStrokes(int zoom, int level, int minSamples) {
    // Found on the pile alone, so that every model gets the same strokes and region.
    const Sculpture& s = *denseModel(kPileOnly).sculpture;
    FieldProbe probe(s);
    const Vec3 top = surfaceAbove(probe, kPileCenter.x, kPileCenter.y);
    Strokes out;
    out.region = zoomRegion(s.config(), s.levels(), zoom, top);
    const double d = s.levels().level(level).diameterMm;
    const double length = std::min(6 * d, 0.35 * out.region.n * out.region.spacingMm);
    const int samples = std::max(2, int(length / (0.25 * d)) + 1);
    const int count = std::max(3, (minSamples + samples - 2) / (samples - 1));
    for (int r = 0; r < count; ++r) {
        const double a = 3.14159265358979 * r / count;
        const Vec3 dir(std::cos(a), std::sin(a), 0);
        std::vector<Vec3> path;
        for (int i = 0; i < samples; ++i) {
            const Vec3 p = top + dir * ((i - 0.5 * (samples - 1)) * 0.25 * d);
            path.push_back(surfaceAbove(probe, p.x, p.y));
        }
        out.paths.push_back(std::move(path));
    }
    return out;
}

constexpr int kMinSamples = 60;  // non-first samples per benchmark run, at least

/// Mean and max number of skeletons a block's LocalField gathers along the strokes (the
/// blocks the tool centres lie in): the pile-up the issue is about.
std::pair<double, double> localSkeletonsAlong(const Sculpture& s, const Strokes& st) {
    const double h = st.region.spacingMm * Polygonizer::kBlockCells;
    double sum = 0, max = 0;
    size_t n = 0;
    for (const auto& path : st.paths)
        for (const Vec3& p : path) {
            const Vec3 lo = glm::floor(p / h) * h;
            const double k = double(LocalField(s, Aabb{lo, lo + Vec3(h)}).skeletonCount());
            sum += k;
            max = std::max(max, k);
            ++n;
        }
    return {n ? sum / double(n) : 0, max};
}

/// Diagnostic (untimed): of the blocks within D/2 + R_k of the middle sample of the first
/// stroke (about what a sample rebuilds), the fraction whose LocalField bounds do not rule
/// the surface out, i.e. that get evaluated (PolygonizeStats::blocksCulled counts only the
/// chunk-level cull of full rebuilds).
double boundsPassFraction(const Sculpture& s, const Strokes& st, int level) {
    const GridRegion& r = st.region;
    const Vec3 c = st.paths[0][st.paths[0].size() / 2];
    const double reach =
        0.5 * s.levels().level(level).diameterMm + s.levels().level(level).supportMm;
    const double h = r.spacingMm * Polygonizer::kBlockCells;
    size_t near = 0, pass = 0;
    const int nb = r.n / Polygonizer::kBlockCells;
    for (int x = 0; x < nb; ++x)
        for (int y = 0; y < nb; ++y)
            for (int z = 0; z < nb; ++z) {
                const Vec3 lo = r.vertexPos(r.originCell[0], r.originCell[1], r.originCell[2]) +
                                Vec3(x, y, z) * h;
                const Vec3 q = glm::clamp(c, lo, lo + Vec3(h));
                if (glm::length(q - c) > reach) continue;
                ++near;
                pass += LocalField(s, Aabb{lo, lo + Vec3(h)}).bounds().mayContainSurface();
            }
    return near ? double(pass) / double(near) : 0;
}

/// vsculpt: one tool sample end to end, as the frame does it today: placement, the
/// polygonizer's update of the blocks within R_k of the changed vertices, and building the
/// upload meshes of the changed chunks. The first sample of each stroke ("first contact":
/// the whole tool ball at once) is reported apart from the others.
void BM_EditLatency(benchmark::State& state) {
    const size_t skeletons = size_t(state.range(0));
    const int zoom = int(state.range(1));
    const int level = int(state.range(2));
    DenseModel& model = denseModel(skeletons);
    Sculpture& s = *model.sculpture;
    if (!toolAllowedAtZoom(s.config(), zoom, level)) {
        state.SkipWithError("size not allowed at this zoom");
        return;
    }
    const Strokes st = measuredStrokes(zoom, level, kMinSamples);
    Polygonizer poly(s, st.region, s.config().polygonizer.viewRootTolerance);
    poly.rebuildAll();
    std::vector<double> first, rest, placeMs, updateMs, publishMs, endMs;
    size_t evaluations = 0, blocks = 0, gathered = 0, chunks = 0, terms = 0;
    // The writes of each sample go to the polygonizer as the asynchronous mesher passes them
    // (Polygonizer::noteWrites): its kept grid sums follow the edit.
    std::vector<SkeletonWrite> writes;
    // VSCULPT_BENCH_NO_SUMS=1: not told, so every rebuilt block is evaluated afresh (the A/B
    // in docs/benchmarks.md).
    const bool noteWrites = !std::getenv("VSCULPT_BENCH_NO_SUMS");
    s.store().logWritesTo(&writes);
    // The mesh follows one edit: the writes noted, the dirty blocks rebuilt (timed to t2), the
    // changed chunks' upload meshes built and published as the asynchronous mesher does
    // (publishChunks, in parallel; this loop built them one after another until stop 38, so
    // its publish time was a serial one the windows never had).
    std::shared_ptr<const MeshChunks> shown = publishChunks(poly, nullptr);
    std::vector<double> noteMs;
    auto remesh = [&](const EditResult& r, Clock::time_point& t2) {
        const auto n0 = Clock::now();
        if (noteWrites) terms += poly.noteWrites(writes);
        noteMs.push_back(msSince(n0, Clock::now()));
        writes.clear();
        const PolygonizeStats ps = poly.update(r.changedPoints, r.supportMm);
        t2 = Clock::now();
        shown = publishChunks(poly, shown.get());
        benchmark::DoNotOptimize(shown);
        return ps;
    };
    for (auto _ : state) {
        for (const auto& path : st.paths) {
            std::vector<SkeletonChange> changes;
            {
                StrokeBuilder stroke(s, ToolOp::Add, level);
                if (holdBack()) stroke.holdBackChangesBelow(kInteractiveHoldBelow);
                for (size_t i = 0; i < path.size(); ++i) {
                    const auto t0 = Clock::now();
                    const EditResult r = stroke.addSample(path[i]);
                    const auto t1 = Clock::now();
                    Clock::time_point t2;
                    const PolygonizeStats ps = remesh(r, t2);
                    const auto t3 = Clock::now();
                    (i == 0 ? first : rest).push_back(msSince(t0, t3));
                    placeMs.push_back(msSince(t0, t1));
                    updateMs.push_back(msSince(t1, t2));
                    publishMs.push_back(msSince(t2, t3));
                    evaluations += ps.evaluations;
                    blocks += ps.blocksConsidered;
                    gathered += ps.blocksGathered;
                    chunks += ps.chunksChanged;
                }
                // The stroke's end: the small changes its samples held back, as the session
                // writes them (timed apart: it follows the last sample, not every one).
                const auto t0 = Clock::now();
                Clock::time_point t2;
                remesh(stroke.finish(), t2);
                endMs.push_back(msSince(t0, Clock::now()));
                changes = stroke.takeChanges();
            }
            state.PauseTiming();
            const Aabb reverted = revertChanges(s, changes);
            if (noteWrites) poly.noteWrites(writes);
            writes.clear();
            poly.update(reverted);
            shown = publishChunks(poly, shown.get());
            state.ResumeTiming();
        }
    }
    s.store().logWritesTo(nullptr);
    reportPercentiles(state, "", rest);
    state.counters["first_mean_ms"] = std::accumulate(first.begin(), first.end(), 0.0) /
                                      double(std::max<size_t>(1, first.size()));
    state.counters["first_max_ms"] = quantile(first, 1.0);
    state.counters["end_mean_ms"] = std::accumulate(endMs.begin(), endMs.end(), 0.0) /
                                    double(std::max<size_t>(1, endMs.size()));
    state.counters["place_p99_ms"] = quantile(placeMs, 0.99);
    state.counters["update_p99_ms"] = quantile(updateMs, 0.99);
    state.counters["note_p50_ms"] = quantile(noteMs, 0.5);  // noteWrites, part of update
    state.counters["note_p99_ms"] = quantile(noteMs, 0.99);
    state.counters["publish_p99_ms"] = quantile(publishMs, 0.99);
    const double samples = double(first.size() + rest.size());
    state.counters["samples"] = samples;
    state.counters["evals_per_sample"] = double(evaluations) / samples;
    state.counters["block_splats_per_sample"] = double(terms) / samples;
    state.counters["blocks_per_sample"] = double(blocks) / samples;
    state.counters["gathered_per_sample"] = double(gathered) / samples;
    state.counters["bounds_pass"] = boundsPassFraction(s, st, level);
    state.counters["chunks_per_sample"] = double(chunks) / samples;
    const auto [localMean, localMax] = localSkeletonsAlong(s, st);
    state.counters["local_skel_mean"] = localMean;
    state.counters["local_skel_max"] = localMax;
    state.counters["skeletons"] = double(s.counts().total());
}

/// Sizes 1-7, each at every zoom that offers it (zoom z: 8-z, 7-z, 6-z).
/// 1e6 (slow to build: about a minute): only the largest size at each zoom.
void editLatencyArgs(benchmark::internal::Benchmark* b) {
    b->ArgNames({"skeletons", "zoom", "level"});
    for (long n : {10000L, 100000L, 1000000L})
        for (int zoom = 1; zoom <= 5; ++zoom)
            for (int level = 8 - zoom; level >= (n > 100000 ? 8 : 6) - zoom; --level)
                b->Args({n, zoom, level});
}
BENCHMARK(BM_EditLatency)->Apply(editLatencyArgs)->Unit(benchmark::kMillisecond)->Iterations(1);

/// The zoom region's surface as an OpenVDB narrow-band level set (voxel = the grid spacing,
/// voxel centres on the polygonizer's grid vertices, half width 3 voxels): in every block
/// the surface may cross, the first-order distance -f / |grad f| clamped to the band;
/// blocks proven inside are filled with -band. Cached per model and region: setup, not the
/// measured edit.
openvdb::FloatGrid::Ptr levelSetOf(const Sculpture& s, const GridRegion& region) {
    using Key = std::tuple<const Sculpture*, double, int64_t, int64_t, int64_t>;
    static std::map<Key, openvdb::FloatGrid::Ptr> cache;
    auto& slot = cache[Key{&s, region.spacingMm, region.originCell[0], region.originCell[1],
                           region.originCell[2]}];
    if (slot) return slot;
    constexpr int B = Polygonizer::kBlockCells, V = B + 1;
    const float band = float(3 * region.spacingMm);
    const int nb = region.n / B;
    struct Block {
        openvdb::Coord lo;
        int state = 0;  // 0 outside, 1 inside, 2 sampled
        std::array<float, V * V * V> v{};
    };
    std::vector<Block> blocks(size_t(nb) * nb * nb);
    tbb::parallel_for(size_t(0), blocks.size(), [&](size_t i) {
        Block& b = blocks[i];
        const int x = int(i / (size_t(nb) * nb)), y = int(i / nb % nb), z = int(i % nb);
        const int64_t g[3] = {region.originCell[0] + B * x, region.originCell[1] + B * y,
                              region.originCell[2] + B * z};
        b.lo = openvdb::Coord(int(g[0]), int(g[1]), int(g[2]));
        const Vec3 lo = region.vertexPos(g[0], g[1], g[2]);
        const LocalField f(s, Aabb{lo, lo + Vec3(B * region.spacingMm)});
        const FieldBounds fb = f.bounds();
        if (!fb.mayContainSurface()) {
            b.state = fb.min > 0 ? 1 : 0;
            return;
        }
        b.state = 2;
        int n = 0;
        for (int a = 0; a < V; ++a)
            for (int j = 0; j < V; ++j)
                for (int k = 0; k < V; ++k) {
                    const FieldSample fs = f.sample(region.vertexPos(g[0] + a, g[1] + j, g[2] + k));
                    const double slope = glm::length(fs.gradient);
                    const double phi =
                        slope > 1e-9 ? -fs.value / slope : (fs.value > 0 ? -band : band);
                    b.v[size_t(n++)] = float(std::clamp(phi, double(-band), double(band)));
                }
    });
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(band);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(region.spacingMm));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    for (const Block& b : blocks) {
        if (b.state == 1)
            grid->tree().fill(openvdb::CoordBBox(b.lo, b.lo.offsetBy(B)), -band, false);
        if (b.state != 2) continue;
        int n = 0;
        for (int a = 0; a < V; ++a)
            for (int j = 0; j < V; ++j)
                for (int k = 0; k < V; ++k)
                    acc.setValueOn(b.lo.offsetBy(a, j, k), b.v[size_t(n++)]);
    }
    slot = grid;
    return slot;
}

/// OpenVDB: the same spheres (radius D/2) stamped at the same samples into a narrow-band
/// level set (union: min with the sphere's signed distance within the band), then only the
/// touched chunks (the same 8^3-cell chunks) re-meshed: each chunk's voxels, one voxel of
/// overlap around it, copied into a small grid and given to volumeToMesh, chunks in parallel.
void BM_EditLatencyOpenVDB(benchmark::State& state) {
    openvdb::initialize();
    const size_t skeletons = size_t(state.range(0));
    const int zoom = int(state.range(1));
    const int level = int(state.range(2));
    const bool perChunkMeshing = state.range(3) != 0;
    DenseModel& model = denseModel(skeletons);
    Sculpture& s = *model.sculpture;
    if (!toolAllowedAtZoom(s.config(), zoom, level)) {
        state.SkipWithError("size not allowed at this zoom");
        return;
    }
    const Strokes st = measuredStrokes(zoom, level, kMinSamples);
    const GridRegion& region = st.region;
    const openvdb::FloatGrid::Ptr original = levelSetOf(s, region);
    const double h = region.spacingMm;
    const float band = original->background();  // half width, world units (mm)
    const double radius = 0.5 * s.levels().level(level).diameterMm;
    const int chunks = region.n / Polygonizer::kChunkCells;
    std::vector<double> first, rest, stampMs, meshMs;
    size_t touchedChunks = 0, polygons = 0;
    for (auto _ : state) {
        for (const auto& path : st.paths) {
            state.PauseTiming();
            openvdb::FloatGrid::Ptr grid = original->deepCopy();  // the stroke is undone
            state.ResumeTiming();
            for (size_t i = 0; i < path.size(); ++i) {
                const auto t0 = Clock::now();
                const Vec3 c = path[i];
                const double reach = radius + band;
                openvdb::Coord lo, hi;
                for (int a = 0; a < 3; ++a) {
                    lo[a] = int(std::floor((c[a] - reach) / h));
                    hi[a] = int(std::ceil((c[a] + reach) / h));
                }
                {
                    auto acc = grid->getAccessor();
                    for (int x = lo.x(); x <= hi.x(); ++x)
                        for (int y = lo.y(); y <= hi.y(); ++y)
                            for (int z = lo.z(); z <= hi.z(); ++z) {
                                const double dx = x * h - c.x, dy = y * h - c.y, dz = z * h - c.z;
                                const float d =
                                    float(std::sqrt(dx * dx + dy * dy + dz * dz) - radius);
                                if (d >= band) continue;
                                const openvdb::Coord ijk(x, y, z);
                                if (d <= -band)
                                    acc.setValueOff(ijk, -band);
                                else if (d < acc.getValue(ijk))
                                    acc.setValueOn(ijk, d);
                            }
                }
                const auto t1 = Clock::now();
                // Chunks whose cells (plus one voxel) meet the stamped box.
                std::array<int, 3> clo{}, chi{};
                for (int a = 0; a < 3; ++a) {
                    const int64_t o = region.originCell[a];
                    clo[a] = std::max<int>(0, int((lo[a] - 1 - o) / Polygonizer::kChunkCells));
                    chi[a] =
                        std::min<int>(chunks - 1, int((hi[a] + 1 - o) / Polygonizer::kChunkCells));
                }
                // Copies the voxels of the chunk box [c0, c1] (chunk indices), one voxel of
                // overlap around it, into a small grid and meshes it.
                auto meshChunks = [&](const std::array<int, 3>& c0, const std::array<int, 3>& c1) {
                    openvdb::Coord from, to;
                    for (int a = 0; a < 3; ++a) {
                        from[a] = int(region.originCell[a] + c0[a] * Polygonizer::kChunkCells) - 1;
                        to[a] =
                            int(region.originCell[a] + (c1[a] + 1) * Polygonizer::kChunkCells) + 1;
                    }
                    openvdb::FloatGrid sub(band);
                    sub.setTransform(grid->transform().copy());
                    sub.setGridClass(openvdb::GRID_LEVEL_SET);
                    // Leaf by leaf in parallel (8^3-voxel leaves), then linked in.
                    using Leaf = openvdb::FloatTree::LeafNodeType;
                    std::vector<openvdb::Coord> origins;
                    auto floor8 = [](int v) { return v & ~7; };
                    for (int x = floor8(from.x()); x <= to.x(); x += 8)
                        for (int y = floor8(from.y()); y <= to.y(); y += 8)
                            for (int z = floor8(from.z()); z <= to.z(); z += 8)
                                origins.emplace_back(x, y, z);
                    std::vector<std::unique_ptr<Leaf>> leaves(origins.size());
                    tbb::parallel_for(size_t(0), origins.size(), [&](size_t k) {
                        auto leaf = std::make_unique<Leaf>(origins[k], band, false);
                        auto src = grid->getConstAccessor();
                        const openvdb::Coord lo = openvdb::Coord::maxComponent(origins[k], from);
                        const openvdb::Coord hi =
                            openvdb::Coord::minComponent(origins[k].offsetBy(7), to);
                        for (int x = lo.x(); x <= hi.x(); ++x)
                            for (int y = lo.y(); y <= hi.y(); ++y)
                                for (int z = lo.z(); z <= hi.z(); ++z) {
                                    const openvdb::Coord ijk(x, y, z);
                                    float v;
                                    if (src.probeValue(ijk, v) || v < 0) leaf->setValueOn(ijk, v);
                                }
                        if (!leaf->isEmpty()) leaves[k] = std::move(leaf);
                    });
                    for (auto& leaf : leaves)
                        if (leaf) sub.tree().addLeaf(leaf.release());
                    std::vector<openvdb::Vec3s> points;
                    std::vector<openvdb::Vec3I> tris;
                    std::vector<openvdb::Vec4I> quads;
                    openvdb::tools::volumeToMesh(sub, points, tris, quads, 0.0, 0.0);
                    // Publishing: each polygon to the chunk of its first vertex.
                    std::vector<uint32_t> perChunk(size_t(c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) *
                                                   (c1[2] - c0[2] + 1));
                    auto chunkOf = [&](uint32_t vi) {
                        size_t idx = 0;
                        for (int a = 0; a < 3; ++a) {
                            const int g =
                                int(std::floor(points[vi][a])) - int(region.originCell[a]);
                            const int c = std::clamp(g / Polygonizer::kChunkCells, c0[a], c1[a]);
                            idx = idx * size_t(c1[a] - c0[a] + 1) + size_t(c - c0[a]);
                        }
                        return idx;
                    };
                    for (const auto& t : tris)
                        ++perChunk[chunkOf(t[0])];
                    for (const auto& q : quads)
                        perChunk[chunkOf(q[0])] += 2;
                    return std::accumulate(perChunk.begin(), perChunk.end(), size_t(0));
                };
                size_t touched = 0;
                if (clo[0] > chi[0] || clo[1] > chi[1] || clo[2] > chi[2]) {
                    // The stamp lies outside the region: nothing on show to re-mesh.
                } else if (perChunkMeshing) {
                    std::vector<std::array<int, 3>> list;
                    for (int x = clo[0]; x <= chi[0]; ++x)
                        for (int y = clo[1]; y <= chi[1]; ++y)
                            for (int z = clo[2]; z <= chi[2]; ++z)
                                list.push_back({x, y, z});
                    std::vector<size_t> chunkPolygons(list.size());
                    tbb::parallel_for(size_t(0), list.size(), [&](size_t k) {
                        chunkPolygons[k] = meshChunks(list[k], list[k]);
                    });
                    touched = list.size();
                    for (size_t p : chunkPolygons)
                        polygons += p;
                } else {
                    touched =
                        size_t(chi[0] - clo[0] + 1) * (chi[1] - clo[1] + 1) * (chi[2] - clo[2] + 1);
                    polygons += meshChunks(clo, chi);
                }
                const auto t2 = Clock::now();
                (i == 0 ? first : rest).push_back(msSince(t0, t2));
                stampMs.push_back(msSince(t0, t1));
                meshMs.push_back(msSince(t1, t2));
                touchedChunks += touched;
            }
        }
    }
    reportPercentiles(state, "", rest);
    state.counters["first_mean_ms"] = std::accumulate(first.begin(), first.end(), 0.0) /
                                      double(std::max<size_t>(1, first.size()));
    state.counters["first_max_ms"] = quantile(first, 1.0);
    state.counters["stamp_p99_ms"] = quantile(stampMs, 0.99);
    state.counters["mesh_p99_ms"] = quantile(meshMs, 0.99);
    const double samples = double(first.size() + rest.size());
    state.counters["samples"] = samples;
    state.counters["chunks_per_sample"] = double(touchedChunks) / samples;
    state.counters["triangles_per_sample"] = double(polygons) / samples;
    state.counters["skeletons"] = double(s.counts().total());
}
/// Sizes 1-7 at their zooms; last argument 1: every touched chunk meshed on its own (in
/// parallel), 0: their bounding box meshed by one volumeToMesh call (faster: less overhead
/// per call), then the polygons split by chunk.
void openVdbArgs(benchmark::internal::Benchmark* b) {
    b->ArgNames({"skeletons", "zoom", "level", "per_chunk"});
    for (long n : {10000L, 100000L, 1000000L})
        for (int zoom = 1; zoom <= 5; ++zoom)
            for (int level = 8 - zoom; level >= (n > 100000 ? 8 : 6) - zoom; --level)
                b->Args({n, zoom, level, 0});
    for (int zoom = 1; zoom <= 5; ++zoom)
        b->Args({100000L, zoom, 8 - zoom, 1});
}
BENCHMARK(BM_EditLatencyOpenVDB)->Apply(openVdbArgs)->Unit(benchmark::kMillisecond)->Iterations(1);

/// The frame loops' three strokes across the pile's top (0°, 60°, 120°), one sample per
/// 90 Hz frame, 0.1 D apart, each on the pre-stroke surface.
constexpr int kFrames = 36;
std::vector<std::vector<Vec3>> frameLoopPaths(FieldProbe& probe, const Vec3& top, double d) {
    std::vector<std::vector<Vec3>> paths;
    for (int r = 0; r < 3; ++r) {
        const double a = 3.14159265358979 * r / 3;
        std::vector<Vec3> path;
        for (int i = 0; i < kFrames; ++i) {
            const Vec3 p =
                top + Vec3(std::cos(a), std::sin(a), 0) * ((i - 0.5 * kFrames) * 0.1 * d);
            path.push_back(surfaceAbove(probe, p.x, p.y));
        }
        paths.push_back(std::move(path));
    }
    return paths;
}

/// Headless frame loop: a level-7 stroke at zoom 1 crossing the pile at about 300 mm/s
/// (0.1 D per 90 Hz frame), one tool sample per frame, stamped with the frame's start. The
/// frame thread does what the frame does today minus GL: applies the sample (placement and
/// the polygonizer's update), then, as the renderer, scans every chunk's version and builds
/// the upload mesh of each changed chunk. Reported: the frame thread's CPU time per frame
/// (CLOCK_THREAD_CPUTIME_ID, GL draw excluded: no GL here) and the delay from a sample's
/// timestamp to the end of the frame that shows it (the "published" mesh). With today's
/// synchronous design the two are the same work; an asynchronous mesher moves the rebuild
/// off the frame thread, and this loop measures it by replacing applySample / the scan.
void BM_FrameLoop(benchmark::State& state) {
    const size_t skeletons = size_t(state.range(0));
    DenseModel& model = denseModel(skeletons);
    Sculpture& s = *model.sculpture;
    constexpr int kLevel = 7;
    const double d = s.levels().level(kLevel).diameterMm;
    FieldProbe probe(*denseModel(kPileOnly).sculpture);  // the same path in every model
    const Vec3 top = surfaceAbove(probe, kPileCenter.x, kPileCenter.y);
    const GridRegion region = zoomRegion(s.config(), s.levels(), 1, top);
    Polygonizer poly(s, region, s.config().polygonizer.viewRootTolerance);
    poly.rebuildAll();
    const int c = poly.chunksPerAxis();
    std::vector<uint64_t> shown(size_t(c) * c * c);  // the renderer's chunk versions
    for (int x = 0, i = 0; x < c; ++x)
        for (int y = 0; y < c; ++y)
            for (int z = 0; z < c; ++z)
                shown[size_t(i++)] = poly.chunkVersion(x, y, z);
    const std::vector<std::vector<Vec3>> paths = frameLoopPaths(probe, top, d);
    const auto period = std::chrono::nanoseconds(11'111'111);
    std::vector<double> frameCpu, frameWall, delay;
    int missed = 0;
    for (auto _ : state) {
        for (const auto& path : paths) {
            std::vector<SkeletonChange> changes;
            {
                StrokeBuilder stroke(s, ToolOp::Add, kLevel);
                const auto start = Clock::now();
                for (int f = 0; f < kFrames; ++f) {
                    const auto sampleTime = start + f * period;  // the input's timestamp
                    std::this_thread::sleep_until(sampleTime);
                    const auto w0 = Clock::now();
                    const double c0 = threadCpuMs();
                    const EditResult r = stroke.addSample(path[size_t(f)]);
                    poly.update(r.changedPoints, r.supportMm);
                    size_t uploaded = 0;
                    for (int x = 0, i = 0; x < c; ++x)
                        for (int y = 0; y < c; ++y)
                            for (int z = 0; z < c; ++z, ++i) {
                                const uint64_t v = poly.chunkVersion(x, y, z);
                                if (v == shown[size_t(i)]) continue;
                                shown[size_t(i)] = v;
                                uploaded += poly.chunkMesh(x, y, z).indices.size();
                            }
                    benchmark::DoNotOptimize(uploaded);
                    const double c1 = threadCpuMs();
                    const auto w1 = Clock::now();
                    frameCpu.push_back(c1 - c0);
                    frameWall.push_back(msSince(w0, w1));
                    delay.push_back(msSince(sampleTime, w1));
                    missed += w1 - sampleTime > period;
                }
                // The stroke's end (after the frames measured).
                const EditResult end = stroke.finish();
                poly.update(end.changedPoints, end.supportMm);
                changes = stroke.takeChanges();
            }
            state.PauseTiming();
            poly.update(revertChanges(s, changes));
            for (int x = 0, i = 0; x < c; ++x)
                for (int y = 0; y < c; ++y)
                    for (int z = 0; z < c; ++z)
                        shown[size_t(i++)] = poly.chunkVersion(x, y, z);
            state.ResumeTiming();
        }
    }
    reportPercentiles(state, "frame_cpu_", frameCpu);
    state.counters["frame_wall_p99_ms"] = quantile(frameWall, 0.99);
    reportPercentiles(state, "sample_to_mesh_", delay);
    state.counters["frames"] = double(frameCpu.size());
    state.counters["frames_over_11ms"] = missed;
    state.counters["skeletons"] = double(s.counts().total());
}
BENCHMARK(BM_FrameLoop)
    ->ArgName("skeletons")
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

/// BM_FrameLoop with the asynchronous mesher (AsyncMesher.h, as the windows run it): the
/// frame thread places the sample, posts its writes and takes the last published chunk set;
/// the mesher thread rebuilds and extracts chunk meshes. Reported: the frame thread's CPU
/// per frame (GL upload and draw excluded, as above), the delay from post() to the first
/// published set holding the sample, the delay to the first set showing the surface around
/// the tool current (post_to_tool_published_: a partial set, AsyncMesher::Focus), and how many
/// rebuild passes the stroke took (fewer than samples: coalesced). VSCULPT_BENCH_FOCUS_FIRST=1
/// turns the tool-first order on (AsyncMesher::Options::focusFirst; A/B).
/// The mesher's threads for A/B runs: VSCULPT_BENCH_MESHER_THREADS=N (the mesher's own
/// included; stop 21 used every core but one), VSCULPT_BENCH_MESHER_NICE=N (the helpers' nice
/// steps below the frame; default AsyncMesher::kHelperNice, 0 = the same priority).
AsyncMesher::Options benchMesherOptions() {
    AsyncMesher::Options o;
    if (const char* n = std::getenv("VSCULPT_BENCH_MESHER_THREADS")) o.threads = std::atoi(n);
    if (const char* n = std::getenv("VSCULPT_BENCH_MESHER_NICE")) o.helperNice = std::atoi(n);
    if (const char* n = std::getenv("VSCULPT_BENCH_FOCUS_FIRST")) o.focusFirst = std::atoi(n) != 0;
    return o;
}

void BM_FrameLoopAsync(benchmark::State& state) {
    const size_t skeletons = size_t(state.range(0));
    DenseModel& model = denseModel(skeletons);
    Sculpture& s = *model.sculpture;
    // The largest size the zoom offers (7 at zoom 1, 3 at zoom 5), at 0.1 D per frame.
    const int zoom = int(state.range(1));
    const int kLevel = 8 - zoom;
    const double d = s.levels().level(kLevel).diameterMm;
    FieldProbe probe(*denseModel(kPileOnly).sculpture);
    const Vec3 top = surfaceAbove(probe, kPileCenter.x, kPileCenter.y);
    const GridRegion region = zoomRegion(s.config(), s.levels(), zoom, top);
    std::vector<SkeletonWrite> writes;
    s.store().logWritesTo(&writes);
    AsyncMesher mesher(s, region, s.config().polygonizer.viewRootTolerance, benchMesherOptions());
    const std::vector<std::vector<Vec3>> paths = frameLoopPaths(probe, top, d);
    const auto period = std::chrono::nanoseconds(11'111'111);
    std::vector<double> frameCpu, frameWall, delay, endDelay, focusDelay;
    bool flushed = false;
    size_t flushes = 0;
    std::vector<uint64_t> shown = mesher.published()->versions;
    int missed = 0;
    size_t chunkUploads = 0, samples = 0;
    const size_t passes0 = mesher.passes();
    for (auto _ : state) {
        for (const auto& path : paths) {
            std::vector<SkeletonChange> changes;
            {
                StrokeBuilder stroke(s, ToolOp::Add, kLevel);
                if (holdBack()) stroke.holdBackChangesBelow(kInteractiveHoldBelow);
                const auto start = Clock::now();
                for (int f = 0; f < kFrames; ++f) {
                    const auto sampleTime = start + f * period;
                    std::this_thread::sleep_until(sampleTime);
                    const auto w0 = Clock::now();
                    const double c0 = threadCpuMs();
                    const EditResult r = stroke.addSample(path[size_t(f)]);
                    // As the session posts a sample: the tool's surroundings first.
                    mesher.post(std::exchange(writes, {}), r.changedPoints, r.supportMm,
                                AsyncMesher::Focus{path[size_t(f)], 0.5 * d});
                    const std::shared_ptr<const MeshChunks> set = mesher.published();
                    // What the renderer would upload this frame (the meshes exist already).
                    for (size_t i = 0; i < set->versions.size(); ++i)
                        if (set->versions[i] != shown[i]) {
                            shown[i] = set->versions[i];
                            ++chunkUploads;
                        }
                    const double c1 = threadCpuMs();
                    const auto w1 = Clock::now();
                    frameCpu.push_back(c1 - c0);
                    frameWall.push_back(msSince(w0, w1));
                    missed += w1 - sampleTime > period;
                    ++samples;
                }
                // The stroke's end: what its samples held back (the session posts it then).
                const EditResult r = stroke.finish();
                flushed = !r.changedPoints.empty();
                flushes += flushed;
                if (flushed) mesher.post(std::exchange(writes, {}), r.changedPoints, r.supportMm);
                changes = stroke.takeChanges();
            }
            state.PauseTiming();
            mesher.waitIdle();
            std::vector<double> delays = mesher.takePublishDelaysMs();
            if (flushed && !delays.empty()) {
                endDelay.push_back(delays.back());
                delays.pop_back();
            }
            for (double ms : delays)
                delay.push_back(ms);
            for (double ms : mesher.takeFocusDelaysMs())
                focusDelay.push_back(ms);
            mesher.post(std::exchange(writes, {}), revertChanges(s, changes));
            mesher.waitIdle();
            mesher.takePublishDelaysMs();
            shown = mesher.published()->versions;
            state.ResumeTiming();
        }
    }
    s.store().logWritesTo(nullptr);
    reportPercentiles(state, "frame_cpu_", frameCpu);
    state.counters["frame_wall_p99_ms"] = quantile(frameWall, 0.99);
    reportPercentiles(state, "post_to_published_", delay);
    reportPercentiles(state, "post_to_tool_published_", focusDelay);
    reportPercentiles(state, "stroke_end_to_published_", endDelay);
    state.counters["frames"] = double(frameCpu.size());
    state.counters["frames_over_11ms"] = missed;
    state.counters["passes_per_sample"] =
        double(mesher.passes() - passes0 - paths.size() - flushes) / double(samples);
    state.counters["chunk_uploads_per_frame"] = double(chunkUploads) / double(samples);
    state.counters["skeletons"] = double(s.counts().total());
}
BENCHMARK(BM_FrameLoopAsync)
    ->ArgNames({"skeletons", "zoom"})
    ->Args({100000, 1})
    ->Args({100000, 5})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

/// What a zoom change costs before its region is complete: a new polygonizer over the zoom's
/// region, centred above the pile as the frame-loop benchmarks are, built whole on 2 threads
/// (`Session::catchUpView` does this synchronously in `play`; the windows show the previous
/// mesh meanwhile).
void BM_ZoomChange(benchmark::State& state) {
    DenseModel& model = denseModel(size_t(state.range(0)));
    const Sculpture& s = *model.sculpture;
    FieldProbe probe(*denseModel(kPileOnly).sculpture);
    const GridRegion region = zoomRegion(s.config(), s.levels(), int(state.range(1)),
                                         surfaceAbove(probe, kPileCenter.x, kPileCenter.y));
    PolygonizeStats stats;
    for (auto _ : state) {
        Polygonizer poly(s, region, s.config().polygonizer.viewRootTolerance);
        stats = poly.rebuildAll(true);
    }
    state.counters["skeletons"] = double(s.counts().total());
    state.counters["grid_values"] = double(stats.gridValues);
    state.counters["evaluations"] = double(stats.evaluations);
    state.counters["blocks_meshed"] = double(stats.blocksConsidered - stats.blocksCulled);
}
BENCHMARK(BM_ZoomChange)
    ->ArgNames({"skeletons", "zoom"})
    ->ArgsProduct({{100000, 1000000}, {1, 3, 5}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// Heap bytes a callable leaves allocated (glibc's main arena: run it on this thread only).
template <class F>
size_t heapBytesKept(F&& f) {
    const size_t before = mallinfo2().uordblks;
    f();
    const size_t after = mallinfo2().uordblks;
    return after > before ? after - before : 0;
}

/// Memory at n skeletons: the skeleton store (memoryBytes()), the undo history of every
/// stroke that built the model (History::memoryBytes()), and the polygonizer's heap after a
/// full rebuild at zoom 1 and at zoom 3 over the pile (no memoryBytes() there: measured as
/// the growth of glibc's allocated bytes, rebuilt on this thread so that everything lands in
/// the main arena; includes the Polygonizer object's vectors and block meshes).
void BM_Memory(benchmark::State& state) {
    DenseModel& model = denseModel(size_t(state.range(0)));
    const Sculpture& s = *model.sculpture;
    size_t poly1 = 0, poly3 = 0;
    for (auto _ : state) {
        for (int zoom : {1, 3}) {
            FieldProbe probe(*denseModel(kPileOnly).sculpture);
            const GridRegion region = zoomRegion(s.config(), s.levels(), zoom,
                                                 surfaceAbove(probe, kPileCenter.x, kPileCenter.y));
            std::unique_ptr<Polygonizer> poly;
            const size_t bytes = heapBytesKept([&] {
                poly = std::make_unique<Polygonizer>(s, region,
                                                     s.config().polygonizer.viewRootTolerance);
                poly->rebuildAll(false);
            });
            (zoom == 1 ? poly1 : poly3) = bytes;
        }
    }
    const double n = double(s.counts().total());
    state.counters["skeletons"] = n;
    state.counters["pile_skeletons"] = double(model.pileSkeletons);
    state.counters["build_s"] = model.buildSeconds;
    state.counters["store_MB"] = double(s.store().memoryBytes()) / 1e6;
    state.counters["history_MB"] = double(model.history.memoryBytes()) / 1e6;
    state.counters["history_B_per_skel"] = double(model.history.memoryBytes()) / n;
    state.counters["strokes"] = double(model.history.done().size());
    state.counters["poly_zoom1_MB"] = double(poly1) / 1e6;
    state.counters["poly_zoom3_MB"] = double(poly3) / 1e6;
}
/// What a window's export key costs the frame (the snapshot the export thread takes,
/// Sculpture::clone) against what it cost when the frame meshed and wrote the file itself
/// (studio::wholeMeshOf at the zoom-1 spacing and a .glb written, now the export thread's).
void BM_ExportRequest(benchmark::State& state) {
    DenseModel& model = denseModel(size_t(state.range(0)));
    const Sculpture& s = *model.sculpture;
    const auto path = std::filesystem::temp_directory_path() /
                      ("vsculpt-bench-export-" + std::to_string(::getpid()) + ".glb");
    std::vector<double> cloneMs, meshMs, writeMs;
    size_t triangles = 0;
    for (auto _ : state) {
        const auto t0 = Clock::now();
        std::unique_ptr<const Sculpture> snapshot = s.clone();
        const auto t1 = Clock::now();
        const Mesh mesh = vsculpt::studio::wholeMeshOf(*snapshot);
        const auto t2 = Clock::now();
        exportMesh(mesh, path);
        const auto t3 = Clock::now();
        cloneMs.push_back(msSince(t0, t1));
        meshMs.push_back(msSince(t1, t2));
        writeMs.push_back(msSince(t2, t3));
        triangles = mesh.triangleCount();
    }
    std::filesystem::remove(path);
    state.counters["frame_before_ms"] = quantile(meshMs, 0.5) + quantile(writeMs, 0.5);
    state.counters["frame_now_ms"] = quantile(cloneMs, 0.5);
    state.counters["mesh_ms"] = quantile(meshMs, 0.5);
    state.counters["write_ms"] = quantile(writeMs, 0.5);
    state.counters["triangles"] = double(triangles);
    state.counters["skeletons"] = double(s.counts().total());
}
/// What a save (F5, and a window's close) costs the frame thread: saveProject on the same
/// models with their whole undo history (a new project folder each time, then one that
/// already has a snapshot, as a second save finds it).
void BM_SaveRequest(benchmark::State& state) {
    DenseModel& model = denseModel(size_t(state.range(0)));
    const auto dir = std::filesystem::temp_directory_path() /
                     ("vsculpt-bench-save-" + std::to_string(::getpid()));
    std::vector<double> firstMs, againMs, cloneMs, historyMs;
    size_t bytes = 0;
    for (auto _ : state) {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
        JournalWriter journal(journalPath(dir), 0);
        for (std::vector<double>* into : {&firstMs, &againMs}) {
            const auto t0 = Clock::now();
            saveProject(dir, "{}", 1, *model.sculpture, model.history, journal);
            into->push_back(msSince(t0, Clock::now()));
        }
        bytes = std::filesystem::file_size(snapshotPath(dir));
        const auto c0 = Clock::now();
        std::unique_ptr<Sculpture> copy = model.sculpture->clone();
        const auto c1 = Clock::now();
        History historyCopy = model.history;
        const auto c2 = Clock::now();
        benchmark::DoNotOptimize(copy);
        benchmark::DoNotOptimize(historyCopy);
        cloneMs.push_back(msSince(c0, c1));
        historyMs.push_back(msSince(c1, c2));
    }
    std::filesystem::remove_all(dir);
    state.counters["first_save_ms"] = quantile(firstMs, 0.5);
    state.counters["save_ms"] = quantile(againMs, 0.5);
    state.counters["snapshot_MB"] = double(bytes) / 1e6;
    state.counters["clone_ms"] = quantile(cloneMs, 0.5);
    state.counters["history_copy_ms"] = quantile(historyMs, 0.5);
    state.counters["skeletons"] = double(model.sculpture->counts().total());
}
/// What the end of a stroke costs the frame thread in the journal: JournalWriter::append of a
/// size-7 stroke's record (90 samples, a second of stroke at 90 Hz), 40 strokes per iteration.
/// `disk_us` adds that many microseconds to every flush (a laptop's disk: this machine's
/// fdatasync takes about 15 us); `wait:1` also waits for the flush after each append, which is
/// what append() cost before the flusher thread took the flush off the caller (stop 32).
void BM_JournalAppend(benchmark::State& state) {
    const auto diskDelay = std::chrono::microseconds(state.range(0));
    const bool wait = state.range(1) != 0;
    const auto dir = std::filesystem::temp_directory_path() /
                     ("vsculpt-bench-journal-" + std::to_string(::getpid()));
    std::vector<double> appendMs;
    for (auto _ : state) {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
        JournalWriter journal(journalPath(dir), 0, [diskDelay](int fd) {
            std::this_thread::sleep_for(diskDelay);
            return ::fdatasync(fd);
        });
        JournalRecord r;
        r.level = 7;
        for (int i = 0; i < 90; ++i)
            r.samples.push_back(Vec3(0.5 * i, 10 * std::sin(0.1 * i), 40));
        for (uint64_t seq = 1; seq <= 40; ++seq) {
            r.sequence = seq;
            const auto t0 = Clock::now();
            journal.append(r);
            if (wait) journal.waitDurable();
            appendMs.push_back(msSince(t0, Clock::now()));
        }
    }
    std::filesystem::remove_all(dir);
    state.counters["append_p50_ms"] = quantile(appendMs, 0.5);
    state.counters["append_p99_ms"] = quantile(appendMs, 0.99);
    state.counters["append_max_ms"] = *std::max_element(appendMs.begin(), appendMs.end());
}
BENCHMARK(BM_JournalAppend)
    ->ArgNames({"disk_us", "wait"})
    ->ArgsProduct({{0, 2000, 8000}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

BENCHMARK(BM_SaveRequest)
    ->ArgName("skeletons")
    ->Arg(10000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

BENCHMARK(BM_ExportRequest)
    ->ArgName("skeletons")
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

BENCHMARK(BM_Memory)
    ->ArgName("skeletons")
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// What a smooth stroke's pen lift costs the frame thread (Session::setAsyncStrokeFinish):
// the bumpy arm of examples/smooth-bumpy-arm.vsc (a size-3 arm, 14 size-1 dabs) under a size-4
// smooth stroke along it, samples 0.25 D apart, in a session with the asynchronous mesher as
// the windows run it. Reported: the frame thread's wall time in endStroke() (`lift_ms`), in
// the frame's poll that completes the stroke (`complete_ms`: its weights written, posted to
// the mesher, journaled), and from the lift to the step (`lift_to_step_ms`, polled every
// 11.1 ms frame as Rig::pollBackgroundWork does). async:0 is endStroke() completing the
// stroke itself (the estimate on the frame), as before stop 43. Medians over the iterations;
// each is undone (waiting for nothing) before the next.
void penLift(benchmark::State& state, vsculpt::studio::ToolKind tool, int refineLevels) {
    const bool async = state.range(0) != 0;
    SculptConfig cfg;
    cfg.refineLevels = refineLevels;
    vsculpt::studio::Session s{cfg};
    s.setAsyncMeshing(true);
    s.setAsyncStrokeFinish(async);
    s.setZoom(3, Vec3(54, 0, 0));
    s.setSize(3);
    s.stroke({Vec3(36, 0, 0), Vec3(50, 0, 0), Vec3(72, 0, 0)}, false);
    s.setZoom(5, Vec3(54, 0, 0));
    s.setSize(1);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> angle(0, 6.283185307179586);
    for (double x = 42; x <= 68; x += 2) {
        const double a = angle(rng);
        s.stroke({Vec3(x, 3.3 * std::cos(a), 3.3 * std::sin(a))}, false);
    }
    s.setZoom(4, Vec3(54, 0, 0));
    s.setSize(4);
    s.setTool(tool);
    const double spacing = 0.25 * s.sculpture().levels().level(4).diameterMm;
    // A smooth runs along the arm's flank; a carve cuts 3 mm into its side (60 % of its radius).
    const double y = tool == vsculpt::studio::ToolKind::Smooth ? 3.4 : 5.3;
    std::vector<double> lift, complete, toStep;
    for (auto _ : state) {
        s.beginStroke();
        for (double x = 40; x <= 68; x += spacing)
            s.strokeSample(Vec3(x, y, 0), false);
        const auto t0 = Clock::now();
        s.endStroke();
        const auto t1 = Clock::now();
        lift.push_back(msSince(t0, t1));
        if (!async) {
            complete.push_back(0);
            toStep.push_back(msSince(t0, t1));
        } else {
            for (auto frame = t1;;) {
                frame += std::chrono::nanoseconds(11'111'111);
                std::this_thread::sleep_until(frame);
                const auto p0 = Clock::now();
                const bool done = s.pollStrokeFinish();
                const auto p1 = Clock::now();
                if (!done) continue;
                complete.push_back(msSince(p0, p1));
                toStep.push_back(msSince(t0, p1));
                break;
            }
        }
        state.PauseTiming();
        s.waitForMesh();
        s.undo();
        s.waitForMesh();
        state.ResumeTiming();
    }
    state.counters["lift_ms"] = quantile(lift, 0.5);
    state.counters["lift_max_ms"] = quantile(lift, 1.0);
    state.counters["complete_ms"] = quantile(complete, 0.5);
    state.counters["complete_max_ms"] = quantile(complete, 1.0);
    state.counters["lift_to_step_ms"] = quantile(toStep, 0.5);
}

void BM_SmoothPenLift(benchmark::State& state) {
    penLift(state, vsculpt::studio::ToolKind::Smooth, 0);
}
BENCHMARK(BM_SmoothPenLift)
    ->ArgName("async")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(10)
    ->UseRealTime();

// The same for a size-4 carve along the top of the arm with placement.refine_levels (docs/
// placement.md "Refining strokes"): its refinement is the pen lift's work. refine:0 is the
// carve without it.
void BM_RefinedCarvePenLift(benchmark::State& state) {
    penLift(state, vsculpt::studio::ToolKind::Carve, int(state.range(1)));
}
BENCHMARK(BM_RefinedCarvePenLift)
    ->ArgNames({"async", "refine"})
    ->Args({0, 0})
    ->Args({0, 2})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(10)
    ->UseRealTime();

}  // namespace
