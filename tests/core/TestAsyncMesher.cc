// SPDX-License-Identifier: MIT
// The asynchronous mesher (AsyncMesher.h): every set it publishes as complete equals a full
// rebuild of the sculpture after the edits it claims; edits posted during a rebuild are
// coalesced; a region change supersedes the one before; a cancelled rebuild leaves exactly
// the blocks it did not reach.
#include "vsculpt/core/AsyncMesher.h"

#include "vsculpt/core/Polygonizer.h"

#include "TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <thread>

using namespace vsculpt::core;
using vsculpt::test::emptyConfig;
using vsculpt::test::linePath;

namespace {

SculptConfig sphereConfig() {
    SculptConfig cfg = emptyConfig(PlacementMode::Free);
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 48;
    return cfg;
}

uint64_t fullRebuildHash(const Sculpture& s, const GridRegion& region) {
    Polygonizer full(s, region, s.config().polygonizer.rootTolerance);
    full.rebuildAll();
    return canonicalMeshHash(full.mesh());
}

/// What the mesher published, as seen from its thread.
struct Seen {
    std::mutex m;
    struct Set {
        uint64_t edits;
        bool complete, preview;
        GridRegion region;
        uint64_t hash;
    };
    std::vector<Set> sets;
    AsyncMesher::Options options() {
        AsyncMesher::Options o;
        o.onPublish = [this](const MeshChunks& c) {
            const uint64_t h = canonicalMeshHash(c.merged());
            std::lock_guard lock(m);
            sets.push_back({c.edits, c.complete, c.preview, c.region, h});
        };
        return o;
    }
};

TEST(AsyncMesher, EveryCompleteSetEqualsAFullRebuildAtItsEdit) {
    const SculptConfig cfg = sphereConfig();
    Sculpture s(cfg);
    std::vector<SkeletonWrite> writes;
    s.store().logWritesTo(&writes);
    GridRegion region = zoomRegion(cfg, s.levels(), 1, Vec3(0.0));
    Seen seen;
    AsyncMesher mesher(s, region, cfg.polygonizer.rootTolerance, seen.options());
    EXPECT_TRUE(mesher.published()->complete);
    EXPECT_EQ(canonicalMeshHash(mesher.published()->merged()), fullRebuildHash(s, region));

    // The reference: the mesh a full rebuild gives after every edit (the incremental
    // polygonizer equals it: TestPolygonizer's PartialEqualsFull).
    auto ref = std::make_unique<Polygonizer>(s, region, cfg.polygonizer.rootTolerance);
    ref->rebuildAll();
    std::map<uint64_t, uint64_t> refHash;
    std::map<uint64_t, GridRegion> refRegion;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-12, 12);
    const Vec3 focus = glm::normalize(Vec3(0.3, 0.5, 0.8)) * 30.0;
    for (int stroke = 0; stroke < 8; ++stroke) {
        if (stroke == 3 || stroke == 6) {  // zoom in, then back out
            region = zoomRegion(cfg, s.levels(), stroke == 3 ? 3 : 1, focus);
            const uint64_t e = mesher.setRegion(region);
            ref = std::make_unique<Polygonizer>(s, region, cfg.polygonizer.rootTolerance);
            ref->rebuildAll();
            refHash[e] = canonicalMeshHash(ref->mesh());
            refRegion[e] = region;
        }
        const int level = stroke >= 3 && stroke < 6 ? 4 : 6;
        const ToolOp op = stroke % 3 == 2 ? ToolOp::Carve : ToolOp::Add;
        StrokeBuilder builder(s, op, level);
        const Vec3 a = focus + Vec3(U(rng), U(rng), U(rng)) * (level == 4 ? 0.3 : 1.0);
        const Vec3 b = focus + Vec3(U(rng), U(rng), U(rng)) * (level == 4 ? 0.3 : 1.0);
        for (const Vec3& p : linePath(a, b, 0.4 * s.levels().level(level).diameterMm)) {
            const EditResult r = builder.addSample(p);
            const uint64_t e = mesher.post(std::exchange(writes, {}), r.changedPoints, r.supportMm);
            ref->update(r.changedPoints, r.supportMm);
            refHash[e] = canonicalMeshHash(ref->mesh());
            refRegion[e] = region;
        }
    }
    mesher.waitIdle();
    EXPECT_EQ(mesher.verifyAgainstFullRebuild(), "");
    const auto last = mesher.published();
    EXPECT_EQ(last->edits, mesher.lastPosted());
    EXPECT_EQ(canonicalMeshHash(last->merged()), fullRebuildHash(s, region));
    s.store().logWritesTo(nullptr);

    std::lock_guard lock(seen.m);
    size_t complete = 0, previews = 0;
    for (const auto& set : seen.sets) {
        ASSERT_TRUE(refRegion.count(set.edits)) << set.edits;
        if (set.preview) {
            ++previews;
            EXPECT_FALSE(set.complete);
            EXPECT_EQ(set.region.spacingMm, 2 * refRegion[set.edits].spacingMm);
            continue;
        }
        ASSERT_TRUE(set.complete);
        ++complete;
        EXPECT_EQ(set.region, refRegion[set.edits]) << "edit " << set.edits;
        EXPECT_EQ(set.hash, refHash[set.edits]) << "edit " << set.edits;
    }
    EXPECT_GE(complete, 3u);
    EXPECT_LE(previews, 2u);
    // Sets are published in edit order.
    for (size_t i = 1; i < seen.sets.size(); ++i)
        EXPECT_LE(seen.sets[i - 1].edits, seen.sets[i].edits);
}

/// Each chunk's mesh hash (0: no triangles), chunk index order.
std::vector<uint64_t> chunkHashes(const MeshChunks& c) {
    std::vector<uint64_t> out(c.meshes.size(), 0);
    for (size_t i = 0; i < c.meshes.size(); ++i)
        if (c.meshes[i]) out[i] = canonicalMeshHash(*c.meshes[i]);
    return out;
}

std::vector<uint64_t> chunkHashes(const Polygonizer& p) {
    const int c = p.chunksPerAxis();
    std::vector<uint64_t> out;
    for (int x = 0; x < c; ++x)
        for (int y = 0; y < c; ++y)
            for (int z = 0; z < c; ++z) {
                const Mesh m = p.chunkMesh(x, y, z);
                out.push_back(m.triangleCount() ? canonicalMeshHash(m) : 0);
            }
    return out;
}

TEST(AsyncMesher, TheSurfaceAroundTheToolIsPublishedFirstAndCompleteSetsStayExact) {
    // Zoomed in on the sphere's top: the blocks a partial set must rebuild reach a chunk and
    // a block beyond the focus, which at zoom 1 on the test grid is the whole sphere.
    SculptConfig cfg = sphereConfig();
    cfg.polygonizer.gridN = 96;
    Sculpture s(cfg);
    std::vector<SkeletonWrite> writes;
    s.store().logWritesTo(&writes);
    const GridRegion region = zoomRegion(cfg, s.levels(), 3, Vec3(0, 0, 30));
    struct Set {
        uint64_t edits;
        bool complete, partial;
        std::vector<uint64_t> chunks;
    };
    std::mutex m;
    std::vector<Set> sets;
    AsyncMesher::Options o;
    o.focusFirst = true;
    o.onPublish = [&](const MeshChunks& c) {
        std::vector<uint64_t> h = chunkHashes(c);
        std::lock_guard lock(m);
        sets.push_back({c.edits, c.complete, c.partial, std::move(h)});
    };
    AsyncMesher mesher(s, region, cfg.polygonizer.rootTolerance, o);
    Polygonizer ref(s, region, cfg.polygonizer.rootTolerance);
    ref.rebuildAll();
    std::map<uint64_t, std::vector<uint64_t>> refChunks;
    std::map<uint64_t, AsyncMesher::Focus> focusOf;
    const int c = ref.chunksPerAxis();
    const double chunkMm = Polygonizer::kChunkCells * region.spacingMm;
    // Chunks that touch the focus ball: the ones a partial set must show current.
    auto chunksAround = [&](const AsyncMesher::Focus& f) {
        std::vector<size_t> out;
        for (int x = 0; x < c; ++x)
            for (int y = 0; y < c; ++y)
                for (int z = 0; z < c; ++z) {
                    const Vec3 lo = Vec3(region.originCell[0] + x * Polygonizer::kChunkCells,
                                         region.originCell[1] + y * Polygonizer::kChunkCells,
                                         region.originCell[2] + z * Polygonizer::kChunkCells) *
                                    region.spacingMm;
                    const Vec3 d = f.centre - glm::clamp(f.centre, lo, lo + Vec3(chunkMm));
                    if (glm::length(d) < f.radiusMm) out.push_back((size_t(x) * c + y) * c + z);
                }
        return out;
    };
    // A stroke posted as it is made (whatever the mesher's timing); then, held so that one
    // pass takes them together, an edit posted without a focus (the held-back changes a
    // stroke posts at its end are) and a stroke 40 mm from it: that pass's blocks around the
    // stroke's samples are fewer than all of its blocks, and a partial set must come first.
    struct Stroke {
        Vec3 a, b;
        int level;
        bool focused;
    };
    const std::vector<Stroke> strokes = {{Vec3(-16, -4, 25), Vec3(16, 5, 25), 4, true},
                                         {Vec3(-25, -10, 14), Vec3(-25, 10, 14), 4, false},
                                         {Vec3(14, -10, 23), Vec3(22, 2, 20), 3, true}};
    size_t heldFrom = 0;
    for (size_t k = 0; k < strokes.size(); ++k) {
        if (k == 1) {
            mesher.waitIdle();
            std::lock_guard lock(m);
            heldFrom = sets.size();
            mesher.hold(true);
        }
        StrokeBuilder builder(s, k == 2 ? ToolOp::Carve : ToolOp::Add, strokes[k].level);
        const double d = s.levels().level(strokes[k].level).diameterMm;
        for (const Vec3& p : linePath(strokes[k].a, strokes[k].b, 0.3 * d)) {
            const EditResult r = builder.addSample(p);
            const AsyncMesher::Focus f{p, 0.5 * d};
            const uint64_t e = mesher.post(std::exchange(writes, {}), r.changedPoints, r.supportMm,
                                           strokes[k].focused ? std::optional(f) : std::nullopt);
            ref.update(r.changedPoints, r.supportMm);
            refChunks[e] = chunkHashes(ref);
            if (strokes[k].focused) focusOf[e] = f;
        }
    }
    mesher.hold(false);
    mesher.waitIdle();
    EXPECT_EQ(mesher.verifyAgainstFullRebuild(), "");
    s.store().logWritesTo(nullptr);

    std::lock_guard lock(m);
    size_t partials = 0, heldPartials = 0, checkedChunks = 0;
    for (size_t i = 0; i < sets.size(); ++i) {
        const Set& set = sets[i];
        ASSERT_TRUE(refChunks.count(set.edits)) << set.edits;
        const std::vector<uint64_t>& want = refChunks[set.edits];
        if (set.complete) {
            EXPECT_FALSE(set.partial);
            EXPECT_EQ(set.chunks, want) << "complete set at edit " << set.edits;
            continue;
        }
        ASSERT_TRUE(set.partial) << "a set neither complete nor partial, edit " << set.edits;
        ++partials;
        heldPartials += i >= heldFrom;
        ASSERT_TRUE(focusOf.count(set.edits)) << "a partial set for an edit without a focus";
        for (size_t chunk : chunksAround(focusOf[set.edits])) {
            EXPECT_EQ(set.chunks[chunk], want[chunk])
                << "partial set at edit " << set.edits << ": chunk " << chunk;
            ++checkedChunks;
        }
    }
    EXPECT_GE(heldPartials, 1u);
    EXPECT_GT(checkedChunks, 0u);
    // The last set is complete and holds every edit.
    ASSERT_FALSE(sets.empty());
    EXPECT_TRUE(sets.back().complete);
    EXPECT_EQ(sets.back().edits, mesher.lastPosted());
    EXPECT_EQ(mesher.takeFocusDelaysMs().size(), focusOf.size());
    std::printf("%zu sets, %zu partial (%zu in the held pass), %zu chunks checked\n", sets.size(),
                partials, heldPartials, checkedChunks);
}

TEST(AsyncMesher, EditsPostedDuringARebuildAreCoalescedIntoOnePass) {
    const SculptConfig cfg = sphereConfig();
    Sculpture s(cfg);
    std::vector<SkeletonWrite> writes;
    s.store().logWritesTo(&writes);
    const GridRegion region = zoomRegion(cfg, s.levels(), 1, Vec3(0.0));
    AsyncMesher mesher(s, region, cfg.polygonizer.rootTolerance);
    const size_t passesBefore = mesher.passes();
    mesher.hold(true);  // as if a long rebuild were running: the edits queue up
    StrokeBuilder builder(s, ToolOp::Add, 6);
    int edits = 0;
    for (const Vec3& p : linePath(Vec3(-20, 0, 28), Vec3(20, 5, 28), 3.0)) {
        const EditResult r = builder.addSample(p);
        mesher.post(std::exchange(writes, {}), r.changedPoints, r.supportMm);
        ++edits;
    }
    ASSERT_GT(edits, 5);
    EXPECT_EQ(mesher.published()->edits, 0u);  // nothing of it published yet
    mesher.hold(false);
    mesher.waitIdle();
    EXPECT_EQ(mesher.passes(), passesBefore + 1);
    EXPECT_EQ(mesher.published()->edits, uint64_t(edits));
    EXPECT_EQ(canonicalMeshHash(mesher.published()->merged()), fullRebuildHash(s, region));
    EXPECT_EQ(mesher.takePublishDelaysMs().size(), size_t(edits));
    EXPECT_TRUE(mesher.takePublishDelaysMs().empty());
    s.store().logWritesTo(nullptr);
}

TEST(AsyncMesher, PublishDelaysNobodyTakesStayBounded) {
    // A host that never takes the delays (a headset session of hours) keeps at most
    // maxKeptDelays of them, the latest.
    const SculptConfig cfg = sphereConfig();
    Sculpture s(cfg);
    std::vector<SkeletonWrite> writes;
    s.store().logWritesTo(&writes);
    AsyncMesher::Options o;
    o.maxKeptDelays = 8;
    AsyncMesher mesher(s, zoomRegion(cfg, s.levels(), 1, Vec3(0.0)), cfg.polygonizer.rootTolerance,
                       o);
    StrokeBuilder builder(s, ToolOp::Add, 6);
    int edits = 0;
    for (const Vec3& p : linePath(Vec3(-20, 0, 28), Vec3(20, 5, 28), 2.0)) {
        const EditResult r = builder.addSample(p);
        mesher.post(std::exchange(writes, {}), r.changedPoints, r.supportMm);
        mesher.waitIdle();  // one published set, one delay, per edit
        ++edits;
    }
    ASSERT_GT(edits, 16);
    const size_t kept = mesher.takePublishDelaysMs().size();
    EXPECT_LE(kept, 8u);
    EXPECT_GE(kept, 4u);
    s.store().logWritesTo(nullptr);
}

TEST(AsyncMesher, ARegionChangeSupersedesTheOneBefore) {
    const SculptConfig cfg = sphereConfig();
    Sculpture s(cfg);
    const GridRegion zoom1 = zoomRegion(cfg, s.levels(), 1, Vec3(0.0));
    const GridRegion a = zoomRegion(cfg, s.levels(), 2, Vec3(0, 0, 30));
    const GridRegion b = zoomRegion(cfg, s.levels(), 3, Vec3(30, 0, 0));
    Seen seen;
    AsyncMesher mesher(s, zoom1, cfg.polygonizer.rootTolerance, seen.options());
    mesher.hold(true);
    mesher.setRegion(a);
    mesher.setRegion(b);
    EXPECT_EQ(mesher.targetRegion(), b);
    mesher.hold(false);
    mesher.waitIdle();
    EXPECT_EQ(mesher.published()->region, b);
    EXPECT_EQ(canonicalMeshHash(mesher.published()->merged()), fullRebuildHash(s, b));
    std::lock_guard lock(seen.m);
    ASSERT_EQ(seen.sets.size(), 2u);  // b's preview, then b; nothing of a
    EXPECT_TRUE(seen.sets[0].preview);
    EXPECT_EQ(seen.sets[0].region.spacingMm, 2 * b.spacingMm);
    EXPECT_TRUE(seen.sets[1].complete);
    EXPECT_EQ(seen.sets[1].region, b);
}

TEST(AsyncMesher, ClosingWhileBusyNeitherHangsNorLosesTheCallersSculpture) {
    const SculptConfig cfg = sphereConfig();
    Sculpture s(cfg);
    std::vector<SkeletonWrite> writes;
    s.store().logWritesTo(&writes);
    const size_t before = s.store().vertexCount();
    {
        AsyncMesher mesher(s, zoomRegion(cfg, s.levels(), 1, Vec3(0.0)),
                           cfg.polygonizer.rootTolerance);
        StrokeBuilder builder(s, ToolOp::Add, 5);
        for (const Vec3& p : linePath(Vec3(-20, 0, 29), Vec3(20, 0, 29), 1.0)) {
            const EditResult r = builder.addSample(p);
            mesher.post(std::exchange(writes, {}), r.changedPoints, r.supportMm);
        }
        mesher.setRegion(zoomRegion(cfg, s.levels(), 5, Vec3(0, 0, 30)));
    }  // destroyed with work queued or running
    EXPECT_GT(s.store().vertexCount(), before);
    s.store().logWritesTo(nullptr);
}

TEST(Polygonizer, ACancelledRebuildLeavesExactlyTheBlocksItDidNotReach) {
    const SculptConfig cfg = sphereConfig();
    Sculpture s(cfg);
    const GridRegion region = zoomRegion(cfg, s.levels(), 1, Vec3(0.0));
    Polygonizer poly(s, region, cfg.polygonizer.rootTolerance);
    poly.rebuildAll();
    StrokeBuilder builder(s, ToolOp::Add, 5);
    Polygonizer::BlockList dirty;
    for (const Vec3& p : linePath(Vec3(-20, 0, 29), Vec3(20, 0, 29), 1.0)) {
        const EditResult r = builder.addSample(p);
        const Polygonizer::BlockList near = poly.blocksNear(r.changedPoints, r.supportMm);
        // The box form rebuilds at least what the tighter point form does.
        const Polygonizer::BlockList boxed = poly.blocksTouching(r.changedRegion);
        EXPECT_TRUE(std::includes(boxed.begin(), boxed.end(), near.begin(), near.end()));
        Polygonizer::BlockList merged;
        std::set_union(dirty.begin(), dirty.end(), near.begin(), near.end(),
                       std::back_inserter(merged));
        dirty = std::move(merged);
    }
    ASSERT_GT(dirty.size(), 20u);
    const int c = poly.chunksPerAxis();
    std::vector<uint64_t> versions;
    for (int x = 0; x < c; ++x)
        for (int y = 0; y < c; ++y)
            for (int z = 0; z < c; ++z)
                versions.push_back(poly.chunkVersion(x, y, z));
    // Cancelled before the first block: nothing rebuilt, nothing changed, all still dirty.
    const std::atomic<bool> cancelled{true};
    PolygonizeStats st = poly.rebuildBlocks(dirty, true, &cancelled);
    EXPECT_EQ(st.unfinished, dirty);
    EXPECT_EQ(st.chunksChanged, 0u);
    for (int x = 0, i = 0; x < c; ++x)
        for (int y = 0; y < c; ++y)
            for (int z = 0; z < c; ++z)
                EXPECT_EQ(poly.chunkVersion(x, y, z), versions[size_t(i++)]);
    // Rebuilt in two parts (as a pass cancelled half-way and the next one): exact.
    const Polygonizer::BlockList first(dirty.begin(), dirty.begin() + dirty.size() / 2),
        rest(dirty.begin() + dirty.size() / 2, dirty.end());
    const std::atomic<bool> running{false};
    st = poly.rebuildBlocks(first, true, &running);
    EXPECT_TRUE(st.unfinished.empty());
    EXPECT_GT(st.blocksConsidered - st.blocksCulled, 0u);
    poly.rebuildBlocks(rest);
    EXPECT_EQ(poly.verifyAgainstFullRebuild(), "");
    EXPECT_THROW(poly.rebuildBlocks({{0, 0, region.n / Polygonizer::kBlockCells}}),
                 std::out_of_range);
}

// A cancel can land anywhere in a rebuild: between a block's gathering and its sums (the
// sums of a slice are made in three steps), between the sums and the meshes, mid-slice. Whatever
// it hit, rebuilding what the rebuild reports unfinished must give a full rebuild's mesh. The
// cancel is raised by another thread after delays spread over a rebuild's length; which step
// each one hits varies from run to run, the property checked does not.
TEST(Polygonizer, ACancelAnywhereInARebuildLeavesItExactOnceTheRestIsRebuilt) {
    SculptConfig cfg = sphereConfig();
    cfg.polygonizer.gridN = 128;
    Sculpture s(cfg);
    const GridRegion region = zoomRegion(cfg, s.levels(), 1, Vec3(0.0));
    applyStroke(s, ToolOp::Add, 6, linePath(Vec3(-20, -5, 25), Vec3(20, 5, 30), 1.0));
    // A rebuild cancelled after `delayUs` by another thread, then the rest.
    auto cancelledAfter = [](int delayUs, auto&& rebuild) {
        std::atomic<bool> cancel{false};
        std::thread raiser([&] {
            std::this_thread::sleep_for(std::chrono::microseconds(delayUs));
            cancel.store(true);
        });
        PolygonizeStats st = rebuild(&cancel);
        raiser.join();
        return st;
    };
    size_t partial = 0, rebuilds = 0;
    for (int delayUs = 0; delayUs <= 6000; delayUs += delayUs < 1000 ? 100 : 500) {
        // A whole region from nothing: every block's sums are made in this rebuild.
        Polygonizer poly(s, region, cfg.polygonizer.rootTolerance);
        const PolygonizeStats st = cancelledAfter(
            delayUs, [&](const std::atomic<bool>* c) { return poly.rebuildAll(true, c); });
        partial += !st.unfinished.empty();
        ++rebuilds;
        poly.rebuildBlocks(st.unfinished);
        ASSERT_EQ(poly.verifyAgainstFullRebuild(), "")
            << "rebuildAll cancelled after " << delayUs << " us";
    }
    // An edit noted as writes (kept sums updated, the blocks it brings a crossing to evaluated
    // afresh), its blocks rebuilt with a cancel, then the rest; then undone (no cancel). Such a
    // rebuild takes a few milliseconds: the delays are short and many.
    Polygonizer poly(s, region, cfg.polygonizer.rootTolerance);
    poly.rebuildAll();
    for (int delayUs = 0; delayUs <= 1000; delayUs += delayUs < 200 ? 10 : 100) {
        std::vector<SkeletonWrite> writes;
        s.store().logWritesTo(&writes);
        StrokeBuilder builder(s, ToolOp::Carve, 5);
        Polygonizer::BlockList dirty;
        for (const Vec3& p : linePath(Vec3(-15, 10, 22), Vec3(15, -10, 27), 2.0)) {
            const EditResult r = builder.addSample(p);
            Polygonizer::mergeBlocks(dirty, poly.blocksNear(r.changedPoints, r.supportMm));
        }
        const EditResult end = builder.finish();
        Polygonizer::mergeBlocks(dirty, poly.blocksNear(end.changedPoints, end.supportMm));
        poly.noteWrites(writes);
        writes.clear();
        const PolygonizeStats st = cancelledAfter(delayUs, [&](const std::atomic<bool>* c) {
            return poly.rebuildBlocks(dirty, true, c);
        });
        partial += !st.unfinished.empty();
        ++rebuilds;
        poly.rebuildBlocks(st.unfinished);
        ASSERT_EQ(poly.verifyAgainstFullRebuild(), "")
            << "edit cancelled after " << delayUs << " us";
        const Aabb undone = revertChanges(s, builder.takeChanges());
        poly.noteWrites(writes);
        s.store().logWritesTo(nullptr);
        poly.update(undone);
        ASSERT_EQ(poly.verifyAgainstFullRebuild(), "") << "undo after " << delayUs << " us";
    }
    // How many cancels left blocks depends on the machine's speed: reported, not asserted.
    std::printf("rebuilds cancelled with blocks left: %zu of %zu\n", partial, rebuilds);
}

TEST(Polygonizer, UpdatesCountTheBlocksTheyCull) {
    const SculptConfig cfg = sphereConfig();
    Sculpture s(cfg);
    const GridRegion region = zoomRegion(cfg, s.levels(), 1, Vec3(0.0));
    Polygonizer poly(s, region, cfg.polygonizer.rootTolerance);
    poly.rebuildAll();
    // A box around the whole region: blocks deep inside and far outside the sphere cannot
    // hold the surface, and the update says how many it skipped.
    const PolygonizeStats st = poly.update(region.box());
    EXPECT_EQ(st.blocksConsidered, size_t(std::pow(region.n / Polygonizer::kBlockCells, 3)));
    EXPECT_GT(st.blocksCulled, st.blocksConsidered / 2);
    EXPECT_LT(st.blocksCulled, st.blocksConsidered);
}

}  // namespace
