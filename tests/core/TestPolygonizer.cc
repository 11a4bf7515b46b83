// SPDX-License-Identifier: MIT
#include "vsculpt/core/Polygonizer.h"

#include "TestHelpers.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <set>

using namespace vsculpt::core;
using vsculpt::test::emptyConfig;
using vsculpt::test::linePath;

namespace {

double det3(const Vec3& a, const Vec3& b, const Vec3& c) {
    return glm::dot(a, glm::cross(b, c));
}

Vec3 corner(int c) {
    return Vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
}

TEST(Polygonizer, KuhnTetrahedraTileTheCube) {
    const auto& tets = Polygonizer::kuhnTetrahedra();
    double volume = 0;
    for (const auto& t : tets) {
        const double v = std::abs(det3(corner(t[1]) - corner(t[0]), corner(t[2]) - corner(t[0]),
                                       corner(t[3]) - corner(t[0]))) /
                         6;
        EXPECT_NEAR(v, 1.0 / 6, 1e-15);
        volume += v;
    }
    EXPECT_NEAR(volume, 1.0, 1e-15);
    // No overlap: random interior points lie in exactly one tetrahedron.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0, 1);
    for (int i = 0; i < 20000; ++i) {
        const Vec3 p(U(rng), U(rng), U(rng));
        int containing = 0;
        for (const auto& t : tets) {
            const Vec3 a = corner(t[0]), b = corner(t[1]), c = corner(t[2]), d = corner(t[3]);
            const double v = det3(b - a, c - a, d - a);
            const double l0 = det3(b - p, c - p, d - p) / v, l1 = det3(p - a, c - a, d - a) / v,
                         l2 = det3(b - a, p - a, d - a) / v, l3 = det3(b - a, c - a, p - a) / v;
            containing += l0 > 0 && l1 > 0 && l2 > 0 && l3 > 0;
        }
        ASSERT_EQ(containing, 1) << p.x << " " << p.y << " " << p.z;
    }
}

TEST(Polygonizer, CubeFacesAreSplitAlikeOnOppositeSides) {
    // Boundary triangles of the tetrahedra on face axis=0 must equal those on axis=1
    // shifted, so neighbouring cubes (one's +face is the other's -face) share them.
    for (int axis = 0; axis < 3; ++axis) {
        std::set<std::set<int>> low, high;  // triangles as corner sets projected to the face
        for (const auto& t : Polygonizer::kuhnTetrahedra()) {
            for (int skip = 0; skip < 4; ++skip) {
                std::set<int> face;
                for (int q = 0; q < 4; ++q)
                    if (q != skip) face.insert(t[q]);
                bool allLow = true, allHigh = true;
                for (int c : face) {
                    allLow &= !((c >> axis) & 1);
                    allHigh &= ((c >> axis) & 1) != 0;
                }
                std::set<int> projected;
                for (int c : face)
                    projected.insert(c & ~(1 << axis));
                if (allLow) low.insert(projected);
                if (allHigh) high.insert(projected);
            }
        }
        EXPECT_EQ(low.size(), 2u);
        EXPECT_EQ(low, high) << "axis " << axis;
    }
}

GridRegion regionAround(const Vec3& center, double spacing, int n) {
    GridRegion r;
    r.spacingMm = spacing;
    r.n = n;
    for (int a = 0; a < 3; ++a)
        r.originCell[a] = std::llround(center[a] / spacing) - n / 2;
    return r;
}

TEST(Polygonizer, SphereIsClosedAccurateAndConverges) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 20;
    cfg.sphereCenterMm = Vec3(0.3, -0.7, 0.2);
    const Sculpture s(cfg);
    const double r = 20, exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    double prevVolErr = 1e300, prevDev = 1e300;
    for (double spacing : {2.0, 1.0, 0.5}) {
        const int n = int(std::ceil(48 / spacing / 16)) * 16;
        Polygonizer poly(s, regionAround(cfg.sphereCenterMm, spacing, n), 1e-4);
        poly.rebuildAll();
        const Mesh m = poly.mesh();
        const MeshTopology topo = analyzeTopology(m);
        ASSERT_TRUE(topo.watertight()) << "spacing " << spacing;
        EXPECT_EQ(topo.eulerCharacteristic, 2);
        EXPECT_EQ(topo.components, 1u);
        FieldProbe probe(s);
        double maxF = 0, dev = 0;
        for (const Vec3& p : m.positions)
            maxF = std::max(maxF, std::abs(probe.value(p)));
        // |f| at a vertex is at most the slope times the bisection bracket (1e-4 spacing).
        const double slope = glm::length(probe.sample(cfg.sphereCenterMm + Vec3(r, 0, 0)).gradient);
        EXPECT_LT(maxF, slope * 1e-4 * spacing) << "spacing " << spacing;
        for (size_t t = 0; t < m.triangleCount(); ++t) {  // deviation of faces from the sphere
            const Vec3 c = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] +
                            m.positions[m.indices[3 * t + 2]]) /
                           3.0;
            dev = std::max(dev, std::abs(glm::length(c - cfg.sphereCenterMm) - r));
        }
        for (size_t i = 0; i < m.normals.size(); i += 7)  // normals point outward
            EXPECT_GT(glm::dot(m.normals[i], m.positions[i] - cfg.sphereCenterMm), 0);
        const double volErr = std::abs(meshVolume(m) - exact) / exact;
        EXPECT_LT(volErr, prevVolErr / 2.5) << "spacing " << spacing;  // ~4x per halving
        EXPECT_LT(dev, spacing);                                       // Hausdorff <= h
        EXPECT_LT(dev, prevDev / 2.5);
        prevVolErr = volErr;
        prevDev = dev;
    }
}

TEST(Polygonizer, EdgeVerticesKeepClearOfTheGridVertices) {
    // A sphere whose surface passes 1e-7 mm outside a grid vertex: the roots on the edges
    // around that vertex lie fractions of a micron from it, where a sheet or crevice of the
    // same kind would be too thin for any ray to tell its faces apart (the RayTrace tests).
    // Every vertex keeps a twentieth of the root tolerance from the grid vertices; the mesh
    // stays closed and the vertices stay within the tolerance of the surface.
    const double spacing = 1.0, tol = 0.01;
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 10 * spacing + 1e-7;
    const Sculpture s(cfg);
    FieldProbe probe(s);
    ASSERT_GT(probe.value(Vec3(10 * spacing, 0, 0)), 0);  // the grid vertex is inside, barely
    ASSERT_LT(probe.value(Vec3(10 * spacing + 1e-6, 0, 0)), 0);
    Polygonizer poly(s, regionAround(Vec3(0.0), spacing, 32), tol);
    poly.rebuildAll();
    const Mesh m = poly.mesh();
    ASSERT_TRUE(analyzeTopology(m).watertight());
    const double inset = 0.05 * tol * spacing;
    double nearest = 1e300;
    for (const Vec3& p : m.positions) {
        const Vec3 g = glm::round(p / spacing) * spacing;
        nearest = std::min(nearest, glm::length(p - g));
        EXPECT_LT(std::abs(probe.value(p)) / glm::length(probe.sample(p).gradient), tol * spacing);
    }
    EXPECT_GE(nearest, inset * (1 - 1e-9));
    EXPECT_LT(nearest, 2 * inset);  // the vertex beside (10, 0, 0) is held at the inset
}

TEST(Polygonizer, LocalFieldEqualsTheProbeBitForBit) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 15;
    Sculpture s(cfg);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> U(-25, 25);
    for (int i = 0; i < 20; ++i)
        applyStroke(s, i % 4 == 3 ? ToolOp::Carve : ToolOp::Add, 1 + i % 6,
                    linePath(Vec3(U(rng), U(rng), U(rng)), Vec3(U(rng), U(rng), U(rng)), 1.0));
    FieldProbe probe(s);
    for (int b = 0; b < 30; ++b) {
        const Vec3 lo(U(rng), U(rng), U(rng));
        const Aabb box{lo, lo + Vec3(4.5)};
        const LocalField local(s, box);
        const FieldBounds bounds = local.bounds();
        std::uniform_real_distribution<double> V(0, 4.5);
        for (int i = 0; i < 200; ++i) {
            const Vec3 p = lo + Vec3(V(rng), V(rng), V(rng));
            const FieldSample a = probe.sample(p), c = local.sample(p);
            ASSERT_EQ(a.value, c.value);
            ASSERT_EQ(a.gradient, c.gradient);
            ASSERT_EQ(local.value(p), a.value);
            ASSERT_GE(a.value, bounds.min);
            ASSERT_LE(a.value, bounds.max);
        }
    }
}

TEST(Polygonizer, GridValuesSplattedPerSkeletonAreTheFieldBitForBit) {
    // LocalField::gridValues (what blocks are built from) against value() at every vertex,
    // on clay of every level, on blocks of three spacings (zoom 1, 3 and 5 cells).
    SculptConfig cfg = emptyConfig(PlacementMode::Swept);
    cfg.sphereRadiusMm = 15;
    Sculpture s(cfg);
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> U(-20, 20);
    for (int i = 0; i < 24; ++i)
        applyStroke(s, i % 4 == 3 ? ToolOp::Carve : ToolOp::Add, 1 + i % 7,
                    linePath(Vec3(U(rng), U(rng), U(rng)), Vec3(U(rng), U(rng), U(rng)), 1.0));
    size_t nonzero = 0;
    for (double h : {2.8, 0.7, 0.175})
        for (int b = 0; b < 40; ++b) {
            const int64_t g[3] = {int64_t(std::floor(U(rng) / h)), int64_t(std::floor(U(rng) / h)),
                                  int64_t(std::floor(U(rng) / h))};
            double xs[5], ys[5], zs[5];
            for (int i = 0; i < 5; ++i) {
                xs[i] = double(g[0] + i) * h;
                ys[i] = double(g[1] + i) * h;
                zs[i] = double(g[2] + i) * h;
            }
            const LocalField local(s, Aabb{Vec3(xs[0], ys[0], zs[0]), Vec3(xs[4], ys[4], zs[4])});
            double grid[125];
            local.gridValues(xs, ys, zs, grid);
            // The fixed-point sums the polygonizer keeps: within the cut of 2^-40 per term.
            FixedSum sums[125];
            local.gridSums(xs, ys, zs, sums);
            for (int i = 0; i < 5; ++i)
                for (int j = 0; j < 5; ++j)
                    for (int k = 0; k < 5; ++k) {
                        const double v = local.value(Vec3(xs[i], ys[j], zs[k]));
                        ASSERT_EQ(grid[(i * 5 + j) * 5 + k], v) << h << " " << i << j << k;
                        ASSERT_NEAR(fixedToField(sums[(i * 5 + j) * 5 + k], cfg.iso), v, 1e-9)
                            << h << " " << i << j << k;
                        nonzero += v != -cfg.iso;
                    }
        }
    EXPECT_GT(nonzero, 2000u);  // the blocks do meet clay
}

// Polygonizer::noteWrites keeps each evaluated block's grid sums with the skeleton writes of
// every edit, so a rebuild evaluates no grid values where the sums are kept. The mesh must
// still equal a full rebuild exactly after strokes of every size, carves, undo and redo, in
// both placement modes; it must need fewer evaluations than the same updates without the
// writes; and writes that do not account for every change to the store must not be trusted.
TEST(Polygonizer, KeptGridSumsFollowTheWritesExactly) {
    for (PlacementMode mode : {PlacementMode::Swept, PlacementMode::Free}) {
        SculptConfig cfg = emptyConfig(mode);
        cfg.sphereRadiusMm = 30;
        cfg.polygonizer.gridN = 48;
        Sculpture s(cfg);
        const Vec3 focus = glm::normalize(Vec3(0.3, 0.5, 0.8)) * 30.0;
        // Clay piled up around the focus first (the case kept sums are for: many skeletons
        // per block; over a bare sphere a block is cheaper to evaluate afresh).
        std::mt19937 pile(9);
        std::uniform_real_distribution<double> P(-8, 8);
        for (int i = 0; i < 40; ++i) {
            const int level = 2 + i % 4;
            const Vec3 a = focus + Vec3(P(pile), P(pile), P(pile));
            applyStroke(s, ToolOp::Add, level,
                        linePath(a, a + Vec3(P(pile), P(pile), P(pile)),
                                 0.3 * s.levels().level(level).diameterMm));
        }
        for (int zoom : {1, 3}) {
            const GridRegion region = zoomRegion(cfg, s.levels(), zoom, focus);
            Polygonizer kept(s, region, cfg.polygonizer.rootTolerance);
            Polygonizer fresh(s, region, cfg.polygonizer.rootTolerance);  // told nothing
            kept.rebuildAll();
            fresh.rebuildAll();
            std::vector<SkeletonWrite> writes;
            s.store().logWritesTo(&writes);
            std::mt19937 rng(uint32_t(40 + zoom + 3 * int(mode)));
            const double extent = 0.25 * region.n * region.spacingMm;
            std::uniform_real_distribution<double> U(-extent, extent);
            size_t keptEvals = 0, freshEvals = 0, terms = 0;
            std::vector<std::vector<SkeletonChange>> strokes;
            for (int stroke = 0; stroke < 6; ++stroke) {
                const auto& sizes = cfg.zoom.allowedSizes[size_t(zoom - 1)];
                const int level = sizes[size_t(stroke) % sizes.size()];
                StrokeBuilder builder(s, stroke % 3 == 2 ? ToolOp::Carve : ToolOp::Add, level);
                const Vec3 a = focus + Vec3(U(rng), U(rng), U(rng)),
                           b = focus + Vec3(U(rng), U(rng), U(rng));
                auto remesh = [&](const EditResult& r) {
                    terms += kept.noteWrites(writes);
                    writes.clear();
                    keptEvals += kept.update(r.changedPoints, r.supportMm).evaluations;
                    freshEvals += fresh.update(r.changedPoints, r.supportMm).evaluations;
                };
                for (const Vec3& p : linePath(a, b, 0.4 * s.levels().level(level).diameterMm))
                    remesh(builder.addSample(p));
                remesh(builder.finish());
                strokes.push_back(builder.takeChanges());
                Polygonizer full(s, region, cfg.polygonizer.rootTolerance);
                full.rebuildAll();
                ASSERT_EQ(canonicalMeshHash(kept.mesh()), canonicalMeshHash(full.mesh()))
                    << toString(mode) << " zoom " << zoom << " stroke " << stroke << ": "
                    << firstMeshDifference(kept.mesh(), full.mesh());
            }
            // Undo the last two strokes and redo one: the box form of the update.
            for (int u = 0; u < 2; ++u) {
                const Aabb box = revertChanges(s, strokes[strokes.size() - 1 - size_t(u)]);
                kept.noteWrites(writes);
                writes.clear();
                kept.update(box);
            }
            const Aabb redo = reapplyChanges(s, strokes[strokes.size() - 2]);
            kept.noteWrites(writes);
            writes.clear();
            kept.update(redo);
            EXPECT_EQ(kept.verifyAgainstFullRebuild(), "") << toString(mode) << " zoom " << zoom;
            EXPECT_GT(terms, 0u);
            // Measured 0.25 and 0.11 of the evaluations (zoom 1, 3) in swept mode, 0.28 and
            // 0.10 in free mode. (When noteWrites still dropped the sums of blocks reached by
            // many writes, swept mode needed 0.75.)
            EXPECT_LT(double(keptEvals), 0.4 * double(freshEvals))
                << toString(mode) << " zoom " << zoom << ": kept sums saved too little";
            // One write withheld: the polygonizer must notice and start afresh, not apply
            // a partial difference.
            // (A carve and an add along the focus ray: one of them changes clay.)
            for (double at : {1.0, 1.3, 0.8}) {
                applyStroke(s, ToolOp::Carve, cfg.zoom.allowedSizes[size_t(zoom - 1)].back(),
                            linePath(at * focus, at * focus + Vec3(4, 2, 1), 1.0));
                applyStroke(s, ToolOp::Add, cfg.zoom.allowedSizes[size_t(zoom - 1)].back(),
                            linePath(at * focus, at * focus + Vec3(4, 2, 1), 1.0));
            }
            ASSERT_GT(writes.size(), 1u);
            writes.pop_back();
            kept.noteWrites(writes);
            writes.clear();
            kept.update(s.supportBounds());
            EXPECT_EQ(kept.verifyAgainstFullRebuild(), "") << toString(mode) << " zoom " << zoom;
            s.store().logWritesTo(nullptr);
        }
    }
}

// A sphere, a polygonizer over zoom 1's region built in full, and the store's writes logged
// for Polygonizer::noteWrites.
struct NotedSphere {
    Sculpture s;
    GridRegion region;
    Polygonizer kept;
    std::vector<SkeletonWrite> writes;
    static SculptConfig sized(SculptConfig cfg, double radiusMm, int gridN) {
        cfg.sphereRadiusMm = radiusMm;
        cfg.polygonizer.gridN = gridN;
        return cfg;
    }
    NotedSphere(const SculptConfig& cfg, double radiusMm, int gridN)
        : s(sized(cfg, radiusMm, gridN)),
          region(zoomRegion(s.config(), s.levels(), 1, Vec3(0.0))),
          kept(s, region, s.config().polygonizer.rootTolerance) {
        kept.rebuildAll();
        s.store().logWritesTo(&writes);
    }
    ~NotedSphere() { s.store().logWritesTo(nullptr); }
    NotedSphere(const NotedSphere&) = delete;
    NotedSphere& operator=(const NotedSphere&) = delete;
    /// Tells the polygonizer what was written since the last call.
    void note() {
        kept.noteWrites(writes);
        writes.clear();
    }
};

// Blocks no surface passes through (empty or solid) keep their bounds, widened by every noted
// write that reaches them, so meshing them again gathers no skeletons until a write could put
// surface in them. Sound bounds must stay sound: clay grown into kept-empty blocks and carved
// into kept-solid ones (the sphere's core) must still equal a full rebuild, in both modes.
TEST(Polygonizer, BlocksKeptEmptyOrSolidAreSkippedUntilAWriteReachesThem) {
    for (PlacementMode mode : {PlacementMode::Swept, PlacementMode::Free}) {
        NotedSphere n(emptyConfig(mode), 30, 48);
        Sculpture& s = n.s;
        Polygonizer& kept = n.kept;
        const GridRegion& region = n.region;
        // Every block once (rebuildAll culls whole chunks first, which keeps nothing), then
        // again with nothing written in between: nothing is gathered the second time.
        const PolygonizeStats first = kept.update(region.box());
        EXPECT_GT(first.blocksGathered, 0u) << toString(mode);
        const PolygonizeStats again = kept.update(region.box());
        EXPECT_EQ(again.blocksGathered, 0u) << toString(mode);
        EXPECT_EQ(again.blocksConsidered, first.blocksConsidered);
        // Adds from the sphere out into empty blocks, a carve through its solid core, an add
        // into empty space that leaves the blocks beyond its reach empty, and undo of all.
        struct Stroke {
            ToolOp op;
            int level;
            Vec3 a, b;
        };
        const std::array<Stroke, 4> strokes{{
            {ToolOp::Add, 4, Vec3(20, 5, 18), Vec3(36, 10, 30)},
            {ToolOp::Carve, 5, Vec3(-40, 0, 0), Vec3(40, 2, 3)},
            {ToolOp::Add, 3, Vec3(-10, 45, -10), Vec3(10, 48, -12)},
            {ToolOp::Add, 6, Vec3(0, -20, -20), Vec3(0, -36, -36)},
        }};
        std::vector<std::vector<SkeletonChange>> done;
        size_t skipped = 0;
        for (const Stroke& st : strokes) {
            StrokeBuilder builder(s, st.op, st.level);
            auto remesh = [&](const EditResult& r) {
                n.note();
                const PolygonizeStats ps = kept.update(r.changedPoints, r.supportMm);
                skipped += ps.blocksConsidered - ps.blocksGathered;
            };
            for (const Vec3& p : linePath(st.a, st.b, 0.4 * s.levels().level(st.level).diameterMm))
                remesh(builder.addSample(p));
            remesh(builder.finish());
            done.push_back(builder.takeChanges());
            ASSERT_EQ(kept.verifyAgainstFullRebuild(), "")
                << toString(mode) << " after the stroke from " << st.a.x << " " << st.a.y << " "
                << st.a.z;
        }
        EXPECT_GT(skipped, 0u) << toString(mode);
        for (size_t u = done.size(); u-- > 0;) {
            const Aabb box = revertChanges(s, done[u]);
            n.note();
            kept.update(box);
            ASSERT_EQ(kept.verifyAgainstFullRebuild(), "") << toString(mode) << " undo " << u;
        }
    }
}

// Blocks whose grid values show no sign change keep only the range of those values, not their
// grid sums: in piled-up clay most blocks its bounds could not cull are such, and updating
// their sums at every write that reached them was most of a re-mesh. Cancelling weights in the
// sphere's core loosen the bounds there (each term's own range is added); a later write that
// reaches only such blocks costs no block update and gathers nothing, and the mesh stays equal
// to a full rebuild until a write does bring a crossing.
TEST(Polygonizer, BlocksWithoutACrossingKeepNoSums) {
    // The sphere fills the region but for its corners: the blocks within a core write's reach
    // hold no surface.
    NotedSphere n(emptyConfig(PlacementMode::Swept), 40, 32);
    Sculpture& s = n.s;
    Polygonizer& kept = n.kept;
    const int level = 3;
    const double h = s.levels().level(level).spacingMm;
    const double support = s.levels().level(level).supportMm;
    // Larger than the field of the sphere's core at the block's far corner less the iso-level
    // (0.95), so the block's bounds admit a surface.
    s.store().set(level, LatticeCoord{0, 0, 0}, 1.2f);
    s.store().set(level, LatticeCoord{1, 0, 0}, -1.2f);
    n.note();
    const PolygonizeStats all = kept.update(n.region.box());
    ASSERT_EQ(kept.verifyAgainstFullRebuild(), "");
    // The core's blocks were gathered (their bounds admit a surface) and showed none.
    const Aabb coreBlock{Vec3(0.0), Vec3(Polygonizer::kBlockCells * n.region.spacingMm)};
    ASSERT_EQ(n.region.vertexPos(n.region.originCell[0] + n.region.n / 2, 0, 0).x, 0.0);
    const LocalField coreField(s, coreBlock);
    ASSERT_TRUE(coreField.bounds().mayContainSurface());
    EXPECT_GT(all.blocksGathered, 0u);

    s.store().set(level, LatticeCoord{0, 1, 0}, 0.005f);  // changes f by 0.005 at most
    EXPECT_EQ(kept.noteWrites(n.writes), 0u);
    n.writes.clear();
    const Vec3 p = Vec3(0, h, 0);
    const PolygonizeStats after = kept.update(std::span<const Vec3>(&p, 1), support);
    EXPECT_GT(after.blocksConsidered, 0u);
    EXPECT_EQ(after.blocksGathered, 0u);
    EXPECT_EQ(after.chunksChanged, 0u);
    EXPECT_EQ(kept.verifyAgainstFullRebuild(), "");

    // A write that does bring the surface into those blocks: evaluated afresh, exact.
    const Vec3 dipole(0.5 * h, 0, 0);
    s.store().set(level, LatticeCoord{0, 0, 0}, -3.0f);
    n.note();
    const PolygonizeStats carved = kept.update(std::span<const Vec3>(&dipole, 1), support);
    EXPECT_GT(carved.blocksGathered, 0u);
    EXPECT_GT(carved.chunksChanged, 0u);
    EXPECT_EQ(kept.verifyAgainstFullRebuild(), "");
}

// A grid vertex on the faces between blocks is splatted once per rebuild, by one of the blocks
// that share it, or taken from a neighbour whose sums are kept (and follow the writes): the mesh
// is the same as when each block evaluated all of its vertices itself.
TEST(Polygonizer, GridVerticesBlocksShareAreEvaluatedOnce) {
    Sculpture s(emptyConfig(PlacementMode::Free));
    const int level = 3;
    const double h = s.levels().level(level).spacingMm;
    // Slabs of skeletons of alternating sign across x: every block's bounds admit a surface,
    // and the surface (planes between the slabs) crosses every block.
    for (int x = -6; x <= 6; ++x)
        for (int y = -6; y <= 6; ++y)
            for (int z = -6; z <= 6; ++z)
                s.store().set(level, LatticeCoord{x, y, z}, (x % 2 != 0) ? -1.0f : 1.0f);
    constexpr int n = 16, V = n + 1, B = Polygonizer::kBlockCells;
    const GridRegion region = regionAround(Vec3(0.3, -0.2, 0.1), 0.45 * h, n);
    const double tol = s.config().polygonizer.rootTolerance;

    Polygonizer all(s, region, tol);
    const PolygonizeStats full = all.rebuildAll();
    constexpr int blocksPerAxis = n / B;
    ASSERT_EQ(full.blocksConsidered, size_t(blocksPerAxis * blocksPerAxis * blocksPerAxis));
    ASSERT_EQ(full.blocksCulled, 0u);               // every block was evaluated and holds surface
    EXPECT_EQ(full.gridValues, size_t(V * V * V));  // not 64 * 125 = 8000
    EXPECT_EQ(all.verifyAgainstFullRebuild(), "");

    // The high-x half first; then the rest, whose far x faces at the middle come from the
    // kept sums of the first half, after a write that the kept sums followed.
    std::vector<SkeletonWrite> writes;
    s.store().logWritesTo(&writes);
    Polygonizer halves(s, region, tol);
    Polygonizer::BlockList high, rest;
    for (int x = 0; x < blocksPerAxis; ++x)
        for (int y = 0; y < blocksPerAxis; ++y)
            for (int z = 0; z < blocksPerAxis; ++z)
                (x >= blocksPerAxis / 2 ? high : rest).push_back({x, y, z});
    const PolygonizeStats first = halves.rebuildBlocks(high);
    EXPECT_EQ(first.gridValues, size_t((V / 2 + 1) * V * V));
    s.store().set(level, LatticeCoord{0, 1, 0}, 0.5f);  // reaches the middle face
    halves.noteWrites(writes);
    writes.clear();
    const PolygonizeStats second = halves.rebuildBlocks(rest);
    EXPECT_EQ(second.gridValues, size_t((V / 2) * V * V));  // the middle layer is taken
    // Not yet consistent: the write reached the high half too; rebuilt, it equals a full
    // rebuild (which evaluates every vertex in one pass).
    halves.rebuildBlocks(high);
    EXPECT_EQ(halves.verifyAgainstFullRebuild(), "");

    // Kept sums in a scattered pattern (a vertex may be taken from a block two or three steps
    // away, diagonally), then the rest evaluated around them.
    std::mt19937 rng(5);
    for (int trial = 0; trial < 4; ++trial) {
        Polygonizer scattered(s, region, tol);
        Polygonizer::BlockList some;
        for (const auto& b : high)
            if (rng() % 2) some.push_back(b);
        for (const auto& b : rest)
            if (rng() % 2) some.push_back(b);
        std::sort(some.begin(), some.end());
        scattered.rebuildBlocks(some);
        s.store().set(level, LatticeCoord{int(rng() % 5) - 2, int(rng() % 5) - 2, 0},
                      float(rng() % 3) - 1.0f);
        scattered.noteWrites(writes);
        writes.clear();
        const PolygonizeStats after = scattered.rebuildAll();
        EXPECT_LT(after.gridValues, size_t(V * V * V));
        EXPECT_EQ(scattered.verifyAgainstFullRebuild(), "") << "trial " << trial;
    }
    s.store().logWritesTo(nullptr);
}

// Writes to the same skeleton noted together (the asynchronous mesher notes several samples at
// once, and a swept sample's fit rewrites the weights of earlier ones) update each block once,
// by their net change; the kept sums still equal a fresh evaluation, including a skeleton
// written and then restored (no net change: no update at all) and one created then removed.
TEST(Polygonizer, RepeatedWritesToASkeletonAreNotedOnce) {
    NotedSphere n(emptyConfig(PlacementMode::Swept), 20, 32);
    Sculpture& s = n.s;
    Polygonizer& kept = n.kept;
    const int level = 4;
    const double h = s.levels().level(level).spacingMm;
    const LatticeCoord onSurface{int(std::lround(20 / h)), 0, 0};
    s.store().set(level, onSurface, 0.3f);
    const size_t once = kept.noteWrites(n.writes);  // a new term into each block reached
    n.writes.clear();
    ASSERT_GT(once, 0u);

    s.store().set(level, onSurface, 0.1f);
    s.store().set(level, onSurface, -0.2f);
    s.store().set(level, onSurface, 0.25f);
    ASSERT_EQ(n.writes.size(), 3u);
    // One net change per block: the old term out, the new one in (three writes: six).
    EXPECT_EQ(kept.noteWrites(n.writes), 2 * once);
    n.writes.clear();
    kept.update(n.region.box());
    EXPECT_EQ(kept.verifyAgainstFullRebuild(), "");

    const LatticeCoord beside{onSurface.x, 1, 0};
    s.store().set(level, onSurface, 0.5f);
    s.store().set(level, onSurface, 0.25f);  // back to where it was
    s.store().set(level, beside, 0.4f);
    s.store().erase(level, beside);  // created and gone again
    EXPECT_EQ(kept.noteWrites(n.writes), 0u);
    n.writes.clear();
    kept.update(n.region.box());
    EXPECT_EQ(kept.verifyAgainstFullRebuild(), "");
}

// Swept strokes piled on clay reach weights of 1e7 and field values of 1e8 (measured on the
// benchmark's model): terms of that size do not fit 64-bit sums at 2^-40, and a wrapped sum
// made neighbouring blocks disagree about the surface ("a triangle uses an edge its owner did
// not compute"). Huge weights of both signs, cancelling near the surface, must keep the kept
// sums exact and the mesh equal to a full rebuild.
TEST(Polygonizer, KeptGridSumsHoldHugeWeights) {
    NotedSphere n(emptyConfig(PlacementMode::Swept), 20, 32);
    Sculpture& s = n.s;
    Polygonizer& kept = n.kept;
    const GridRegion& region = n.region;
    const std::array<std::pair<LatticeCoord, float>, 4> edits = {{
        {LatticeCoord{4, 0, 0}, 3.0e7f},
        {LatticeCoord{5, 0, 0}, -3.0e7f},
        {LatticeCoord{4, 1, 0}, 2.5e8f},
        {LatticeCoord{5, 1, 0}, -2.5e8f},
    }};
    const int level = 4;
    const double support = s.levels().level(level).supportMm;
    for (const auto& [coord, w] : edits) {
        s.store().set(level, coord, w);
        n.note();
        const Vec3 p = Vec3(coord.x, coord.y, coord.z) * s.levels().level(level).spacingMm;
        kept.update(std::span<const Vec3>(&p, 1), support);
        EXPECT_EQ(kept.verifyAgainstFullRebuild(), "") << "after weight " << w;
    }
    // The sums themselves: within the rounding of f's own double sum of these terms.
    const Aabb box{Vec3(5, -5, -5), Vec3(5 + 4 * region.spacingMm, -5 + 4 * region.spacingMm,
                                         -5 + 4 * region.spacingMm)};
    const LocalField local(s, box);
    double xs[5], ys[5], zs[5];
    for (int i = 0; i < 5; ++i) {
        xs[i] = box.min.x + i * region.spacingMm;
        ys[i] = box.min.y + i * region.spacingMm;
        zs[i] = box.min.z + i * region.spacingMm;
    }
    FixedSum sums[125];
    local.gridSums(xs, ys, zs, sums);
    double largest = 0;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 5; ++k) {
                const double v = local.value(Vec3(xs[i], ys[j], zs[k]));
                largest = std::max(largest, std::abs(v));
                EXPECT_NEAR(fixedToField(sums[(i * 5 + j) * 5 + k], s.config().iso), v, 1e-6)
                    << i << j << k;
            }
    EXPECT_GT(largest, 1e6);  // the huge terms do reach the block
}

/// The distance from p to the surface f = 0 along the gradient line through p (found by
/// bisection to 1e-9 mm), or -1 when no sign change lies within `reach`.
double distanceToSurface(FieldProbe& probe, const Vec3& p, double reach) {
    const FieldSample s = probe.sample(p);
    const double g = glm::length(s.gradient);
    if (s.value == 0) return 0;
    if (g == 0) return -1;
    // Uphill when outside (f < 0), downhill when inside.
    const Vec3 dir = (s.value < 0 ? 1.0 : -1.0) * s.gradient / g;
    const bool inside = s.value > 0;
    double lo = 0, hi = reach / 64;
    while ((probe.value(p + hi * dir) > 0) == inside) {
        lo = hi;
        hi *= 2;
        if (hi > reach) return -1;
    }
    while (hi - lo > 1e-9) {
        const double mid = 0.5 * (lo + hi);
        ((probe.value(p + mid * dir) > 0) == inside ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// Edge roots are refined by Illinois steps until |f| / |grad f| (the first-order distance to
// the surface) is below the tolerance: the true distance of every vertex from the surface
// must stay below it too, on sculpted clay with strokes of every size in both placement modes.
TEST(Polygonizer, EdgeVerticesLieWithinTheToleranceOfTheSurface) {
    const bool print = std::getenv("VSCULPT_PRINT_ROOTS") != nullptr;
    for (PlacementMode mode : {PlacementMode::Swept, PlacementMode::Free}) {
        SculptConfig cfg = emptyConfig(mode);
        cfg.sphereRadiusMm = 30;
        cfg.polygonizer.gridN = 48;
        Sculpture s(cfg);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> U(-28, 28);
        for (int stroke = 0; stroke < 10; ++stroke) {
            const int level = 3 + stroke % 5;
            const ToolOp op = stroke % 3 == 2 ? ToolOp::Carve : ToolOp::Add;
            const Vec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng));
            const Vec3 pa = glm::normalize(a) * 30.0, pb = glm::normalize(b) * 30.0;
            applyStroke(s, op, level, linePath(pa, pb, 0.3 * s.levels().level(level).diameterMm));
        }
        const GridRegion region = zoomRegion(cfg, s.levels(), 1, Vec3(0.0));
        for (double tol : {0.01, 0.1, 1e-3}) {
            Polygonizer poly(s, region, tol);
            const PolygonizeStats st = poly.rebuildAll();
            const Mesh m = poly.mesh();
            ASSERT_GT(m.positions.size(), 1000u);
            FieldProbe probe(s);
            std::vector<double> d;
            for (const Vec3& p : m.positions) {
                const double dist = distanceToSurface(probe, p, 2 * region.spacingMm);
                ASSERT_GE(dist, 0) << "no surface near " << p.x << " " << p.y << " " << p.z;
                d.push_back(dist / region.spacingMm);
            }
            std::sort(d.begin(), d.end());
            if (print)
                std::printf(
                    "%s tol %.3g: %zu vertices, %.2f evaluations per vertex"
                    "; distance / spacing p50 %.2e p99 %.2e max %.2e\n",
                    toString(mode), tol, d.size(), double(st.evaluations) / double(d.size()),
                    d[d.size() / 2], d[d.size() * 99 / 100], d.back());
            EXPECT_LE(d.back(), tol) << toString(mode) << " tolerance " << tol;
        }
    }
}

struct Scenario {
    PlacementMode mode;
    int zoom;
};

/// Random strokes of every size allowed at a zoom level, near the sphere's surface inside the
/// zoomed region; after every tool sample the incremental mesh is updated, after every
/// stroke it must equal a full rebuild exactly.
class PartialEqualsFull : public ::testing::TestWithParam<Scenario> {};

TEST_P(PartialEqualsFull, AfterRandomStrokes) {
    const auto [mode, zoom] = GetParam();
    SculptConfig cfg = emptyConfig(mode);
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 48;
    Sculpture s(cfg);
    const Vec3 focus = glm::normalize(Vec3(0.3, 0.5, 0.8)) * 30.0;
    const GridRegion region = zoomRegion(cfg, s.levels(), zoom, focus);
    Polygonizer poly(s, region, cfg.polygonizer.rootTolerance);
    poly.rebuildAll();
    std::mt19937 rng(100 + zoom * 7 + int(mode));
    const double extent = 0.3 * region.n * region.spacingMm;
    std::uniform_real_distribution<double> U(-extent, extent);
    const Vec3 c = zoom == 1 ? Vec3(0, 0, 0) : focus;
    for (int stroke = 0; stroke < 6; ++stroke) {
        const auto& sizes = cfg.zoom.allowedSizes[zoom - 1];
        const int level = sizes[stroke % sizes.size()];
        const ToolOp op = stroke % 3 == 2 ? ToolOp::Carve : ToolOp::Add;
        StrokeBuilder builder(s, op, level);
        const Vec3 a = c + Vec3(U(rng), U(rng), U(rng)), b = c + Vec3(U(rng), U(rng), U(rng));
        for (const Vec3& p : linePath(a, b, 0.4 * s.levels().level(level).diameterMm)) {
            const EditResult r = builder.addSample(p);
            // Alternate the box form and the tighter point form of the update.
            if (stroke % 2)
                poly.update(r.changedRegion);
            else
                poly.update(r.changedPoints, r.supportMm);
        }
        Polygonizer full(s, region, cfg.polygonizer.rootTolerance);
        full.rebuildAll();
        const Mesh inc = poly.mesh(), ref = full.mesh();
        ASSERT_EQ(canonicalMeshHash(inc), canonicalMeshHash(ref))
            << "stroke " << stroke << ": " << firstMeshDifference(inc, ref);
    }
    EXPECT_EQ(poly.verifyAgainstFullRebuild(), "");
    // When the whole sculpture lies inside the region, its mesh is closed.
    const Aabb all = s.supportBounds(), box = region.box();
    if (box.contains(all.min) && box.contains(all.max)) {
        EXPECT_TRUE(analyzeTopology(poly.mesh()).watertight());
    }
}

INSTANTIATE_TEST_SUITE_P(
    ZoomsAndModes, PartialEqualsFull,
    ::testing::Values(Scenario{PlacementMode::Free, 1}, Scenario{PlacementMode::Free, 2},
                      Scenario{PlacementMode::Free, 3}, Scenario{PlacementMode::Free, 4},
                      Scenario{PlacementMode::Free, 5}, Scenario{PlacementMode::Thesis, 1},
                      Scenario{PlacementMode::Thesis, 3}, Scenario{PlacementMode::Thesis, 5}),
    [](const auto& info) {
        return std::string(toString(info.param.mode)) + "_zoom" + std::to_string(info.param.zoom);
    });

TEST(Polygonizer, CarvingThroughSplitsIntoPiecesAndStaysExact) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    Sculpture s(cfg);
    const GridRegion region = regionAround(Vec3(0), 1.5, 64);
    Polygonizer poly(s, region, 1e-3);
    poly.rebuildAll();
    auto strokeAndUpdate = [&](ToolOp op, int level, const Vec3& a, const Vec3& b) {
        StrokeBuilder builder(s, op, level);
        for (const Vec3& p : linePath(a, b, 1.0))
            poly.update(builder.addSample(p).changedRegion);
    };
    strokeAndUpdate(ToolOp::Add, 4, Vec3(-30, 0, 0), Vec3(30, 0, 0));  // a bar
    EXPECT_EQ(analyzeTopology(poly.mesh()).components, 1u);
    strokeAndUpdate(ToolOp::Carve, 5, Vec3(0, -20, -20), Vec3(0, 20, 20));  // cut across it
    const Mesh inc = poly.mesh();
    const MeshTopology topo = analyzeTopology(inc);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.components, 2u);
    EXPECT_EQ(topo.eulerCharacteristic, 4);  // two spheres
    Polygonizer full(s, region, 1e-3);
    full.rebuildAll();
    EXPECT_EQ(canonicalMeshHash(inc), canonicalMeshHash(full.mesh()))
        << firstMeshDifference(inc, full.mesh());
}

TEST(Polygonizer, ChunksTogetherAreTheMeshAndVersionsTrackChanges) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 20;
    Sculpture s(cfg);
    Polygonizer poly(s, regionAround(Vec3(0), 1.0, 64), 1e-3);
    poly.rebuildAll();
    const int c = poly.chunksPerAxis();
    auto gather = [&] {
        Mesh all;
        for (int x = 0; x < c; ++x)
            for (int y = 0; y < c; ++y)
                for (int z = 0; z < c; ++z) {
                    const Mesh m = poly.chunkMesh(x, y, z);
                    const uint32_t base = uint32_t(all.positions.size());
                    all.positions.insert(all.positions.end(), m.positions.begin(),
                                         m.positions.end());
                    for (uint32_t i : m.indices)
                        all.indices.push_back(base + i);
                }
        return all;
    };
    EXPECT_EQ(canonicalMeshHash(gather()), canonicalMeshHash(poly.mesh()));
    std::vector<uint64_t> before;
    for (int i = 0; i < c * c * c; ++i)
        before.push_back(poly.chunkVersion(i / (c * c), i / c % c, i % c));
    StrokeBuilder stroke(s, ToolOp::Add, 2);
    const EditResult r = stroke.addSample(Vec3(0, 0, 20));
    const PolygonizeStats st = poly.update(r.changedPoints, r.supportMm);
    ASSERT_GT(st.changedChunks.size(), 0u);
    size_t bumped = 0;
    for (int i = 0; i < c * c * c; ++i) {
        const int x = i / (c * c), y = i / c % c, z = i % c;
        const bool listed = std::find(st.changedChunks.begin(), st.changedChunks.end(),
                                      std::array<int, 3>{x, y, z}) != st.changedChunks.end();
        EXPECT_EQ(poly.chunkVersion(x, y, z) != before[i], listed);
        bumped += listed;
    }
    EXPECT_EQ(bumped, st.chunksChanged);
    EXPECT_LT(bumped, size_t(c * c * c) / 4);  // a local edit touches few chunks
    EXPECT_EQ(canonicalMeshHash(gather()), canonicalMeshHash(poly.mesh()));
}

// A renderer re-uploads only chunks whose version changed: so every chunk whose mesh changed
// must have a new version, also when only a vertex it shares with a neighbour moved.
TEST(Polygonizer, EveryChangedChunkGetsANewVersion) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 12;
    Sculpture s(cfg);
    Polygonizer poly(s, regionAround(Vec3(0), 0.5, 64), 1e-3);  // chunks of 8 mm
    poly.rebuildAll();
    const int c = poly.chunksPerAxis();
    auto snapshot = [&] {
        std::vector<std::pair<uint64_t, uint64_t>> v;  // (version, mesh hash)
        for (int i = 0; i < c * c * c; ++i) {
            const int x = i / (c * c), y = i / c % c, z = i % c;
            v.push_back({poly.chunkVersion(x, y, z), canonicalMeshHash(poly.chunkMesh(x, y, z))});
        }
        return v;
    };
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> U(-14, 14);
    for (int edit = 0; edit < 12; ++edit) {
        const auto before = snapshot();
        StrokeBuilder stroke(s, edit % 3 == 2 ? ToolOp::Carve : ToolOp::Add, 1 + edit % 2);
        const EditResult r = stroke.addSample(Vec3(U(rng), U(rng), U(rng)));
        poly.update(r.changedPoints, r.supportMm);
        const auto after = snapshot();
        for (size_t i = 0; i < after.size(); ++i)
            if (after[i].second != before[i].second) {
                EXPECT_NE(after[i].first, before[i].first) << "edit " << edit << " chunk " << i;
            }
    }
}

TEST(Polygonizer, SameMeshAtAnyThreadCount) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 25;
    Sculpture s(cfg);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> U(-30, 30);
    for (int i = 0; i < 12; ++i)
        applyStroke(s, i % 3 == 2 ? ToolOp::Carve : ToolOp::Add, 3 + i % 4,
                    linePath(Vec3(U(rng), U(rng), U(rng)), Vec3(U(rng), U(rng), U(rng)), 2.0));
    const GridRegion region = zoomRegion(cfg, s.levels(), 1, Vec3(0));
    std::vector<uint64_t> hashes;
    for (int threads : {1, 2, 4}) {
        tbb::task_arena arena(threads);
        arena.execute([&] {
            Polygonizer poly(s, region, 1e-3);
            poly.rebuildAll(true);
            hashes.push_back(canonicalMeshHash(poly.mesh()));
        });
    }
    Polygonizer serial(s, region, 1e-3);
    serial.rebuildAll(false);
    hashes.push_back(canonicalMeshHash(serial.mesh()));
    for (uint64_t h : hashes)
        EXPECT_EQ(h, hashes.front());
}

// ------------------------------------------------------------------------------ zoom

TEST(Zoom, SpacingHalvesAndCellCountStays) {
    const SculptConfig cfg;
    const Sculpture s(cfg);
    for (int z = 1; z <= kZoomLevels; ++z) {
        const GridRegion r = zoomRegion(cfg, s.levels(), z, Vec3(10, -5, 30));
        EXPECT_EQ(r.n, cfg.polygonizer.gridN);
        EXPECT_DOUBLE_EQ(r.spacingMm, cfg.zoom.baseSpacingOverD6 * s.levels().level(6).diameterMm /
                                          std::pow(2.0, z - 1));
        if (z > 1) {  // centred on the selection, within one grid step
            const Aabb b = r.box();
            EXPECT_NEAR(0.5 * (b.min.x + b.max.x), 10, r.spacingMm);
            EXPECT_NEAR(0.5 * (b.min.z + b.max.z), 30, r.spacingMm);
        }
    }
}

TEST(Zoom, AllowedSizesFollowTheThesisTable) {
    const SculptConfig cfg;
    for (int z = 1; z <= kZoomLevels; ++z)
        for (int k = 1; k <= kLevelCount; ++k)
            EXPECT_EQ(toolAllowedAtZoom(cfg, z, k), k == 8 - z || k == 7 - z || k == 6 - z)
                << "zoom " << z << " level " << k;
    EXPECT_THROW(toolAllowedAtZoom(cfg, 6, 1), std::out_of_range);
}

TEST(Zoom, ZoomedMeshIsTheFullResolutionMeshClipped) {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 32;
    Sculpture s(cfg);
    applyStroke(s, ToolOp::Add, 3, linePath(Vec3(-10, 0, 29), Vec3(10, 5, 30), 1.0));
    const size_t skeletons = s.store().vertexCount();
    const Vec3 focus(0, 0, 30);
    const GridRegion small = zoomRegion(cfg, s.levels(), 4, focus);
    GridRegion big = small;  // same spacing and lattice, three times as wide
    big.n = 96;
    for (int a = 0; a < 3; ++a)
        big.originCell[a] -= 32;
    Polygonizer zoomed(s, small, 1e-3), wide(s, big, 1e-3);
    zoomed.rebuildAll();
    wide.rebuildAll();
    const Mesh zm = zoomed.mesh(), wm = wide.mesh();
    // The wide mesh's triangles whose centroids lie in the small region, as a mesh.
    Mesh clipped;
    clipped.positions = wm.positions;
    const Aabb box = small.box();
    for (size_t t = 0; t < wm.triangleCount(); ++t) {
        const Vec3 c = (wm.positions[wm.indices[3 * t]] + wm.positions[wm.indices[3 * t + 1]] +
                        wm.positions[wm.indices[3 * t + 2]]) /
                       3.0;
        if (box.contains(c))
            for (int q = 0; q < 3; ++q)
                clipped.indices.push_back(wm.indices[3 * t + q]);
    }
    ASSERT_GT(zm.triangleCount(), 100u);
    EXPECT_EQ(canonicalMeshHash(zm), canonicalMeshHash(clipped))
        << firstMeshDifference(zm, clipped);
    EXPECT_EQ(s.store().vertexCount(), skeletons);  // zooming adds no shape data
}

// The whole-mesh grid covers where the surface can be: skeletons with positive weight. A
// carve's negative weights lower the field only, so they do not widen it (found by QA: a
// vase's foot carve made "the sculpture" 210 mm across, and its finest export coarser).
TEST(Sculpture, SupportBoundsAreThoseOfWhatRaisesTheField) {
    SculptConfig cfg;
    Sculpture s(cfg);
    const Aabb sphere = s.supportBounds();
    ASSERT_FALSE(sphere.empty());
    const int level = 5;
    const double h = s.levels().level(level).spacingMm;
    const LatticeCoord far{int(std::ceil(300 / h)), 0, 0};
    s.store().set(level, far, -1.0f);
    EXPECT_EQ(s.supportBounds().max.x, sphere.max.x);
    s.store().set(level, far, 1.0f);
    EXPECT_NEAR(s.supportBounds().max.x, far.x * h + s.levels().level(level).supportMm, 1e-9);
}

}  // namespace
