// SPDX-License-Identifier: MIT
/// @file Polygonizer.h
/// @brief Parallel, incremental tetrahedral polygonizer of a sculpture's field over a grid
/// region (thesis §3.2.1), kept as versioned chunks so a renderer re-uploads only what
/// changed.
///
/// Each grid cube is split into the 6 Kuhn tetrahedra around its (0,0,0)-(1,1,1) diagonal,
/// the same way in every cube, so neighbouring cubes share faces exactly. Field signs at the
/// tetrahedron corners (inside: f > 0) give 0, 1 or 2 triangles; edge crossings are found by
/// Illinois steps until the vertex lies within a tolerance of the surface; triangles face outward;
/// vertices are shared per grid edge and carry normals from the field gradient.
///
/// Work is organised in blocks of 4^3 cells (the unit of rebuilding) and chunks of 8^3
/// cells (the unit of publishing). Blocks the field provably cannot cross (LocalField
/// bounds) cost no evaluations, so the cost follows the surface, not N^3. After an edit
/// only the blocks touching the changed region are rebuilt, and the result equals a full
/// rebuild exactly: every value is computed by the same operations in the same order.
#pragma once

#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/core/SkeletonStore.h"
#include "vsculpt/core/WorkerPool.h"
#include "vsculpt/core/Zoom.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace vsculpt::core {

class Sculpture;

struct PolygonizeStats {
    size_t blocksConsidered = 0;  ///< blocks in the rebuilt range
    size_t blocksCulled = 0;      ///< skipped: no surface passes through them or their grid edges
    size_t evaluations = 0;       ///< field evaluations (grid vertices, bisection, gradients)
    size_t gridValues = 0;        ///< of those, grid vertices (a vertex blocks share counts once)
    size_t blocksGathered = 0;    ///< blocks whose skeletons were gathered (a LocalField each)
    size_t chunksChanged = 0;     ///< chunks whose mesh differs from before
    std::vector<std::array<int, 3>> changedChunks;  ///< their indices, for re-upload
    /// Blocks a cancelled rebuild did not reach (Polygonizer::rebuildBlocks): still stale.
    std::vector<std::array<int, 3>> unfinished;
};

class Polygonizer {
  public:
    static constexpr int kBlockCells = 4;
    static constexpr int kChunkCells = 8;

    /// @param relTolerance how far a vertex may lie from the surface (first-order estimate
    ///        |f| / |grad f|), as a fraction of the grid spacing
    /// @pre region.n is a multiple of 16; the grid's integer coordinates fit in +-2^19.
    Polygonizer(const Sculpture& sculpture, const GridRegion& region, double relTolerance);

    /// Polygonizes every block. `threaded`: spread blocks over oneTBB or the useWorkers pool (the
    /// result is the same either way). `cancel`: as in rebuildBlocks.
    PolygonizeStats rebuildAll(bool threaded = true, const std::atomic<bool>* cancel = nullptr);
    /// Rebuilds the blocks whose cells touch `changedRegion` (object space, e.g. the union
    /// of EditResult::changedRegion since the last call).
    PolygonizeStats update(const Aabb& changedRegion, bool threaded = true);
    /// Tighter form: f changed only within `radius` of the given points (EditResult's
    /// changedPoints and supportMm), so only blocks within that distance are rebuilt.
    PolygonizeStats update(std::span<const Vec3> changedPoints, double radius,
                           bool threaded = true);

    // Split form of update(), for a mesher that merges edits and may stop half-way
    // (AsyncMesher.h). Block indices are (bx, by, bz), 0 .. n / kBlockCells - 1.
    using BlockList = std::vector<std::array<int, 3>>;
    /// Blocks update(points, radius) would rebuild, sorted.
    BlockList blocksNear(std::span<const Vec3> changedPoints, double radius) const;
    /// Blocks update(box) would rebuild, sorted.
    BlockList blocksTouching(const Aabb& changedRegion) const;
    /// Adds `more` to `into` (both sorted, no duplicates; the result too): the dirty blocks
    /// of edits taken together.
    static void mergeBlocks(BlockList& into, BlockList more);
    /// Rebuilds the given blocks (sorted, no duplicates). `cancel` is read between blocks:
    /// once it is true the remaining blocks are skipped and listed in stats.unfinished.
    /// Every block that was rebuilt is exact; the mesh is consistent (mesh(), chunkMesh(),
    /// verifyAgainstFullRebuild()) only after the unfinished ones are rebuilt too.
    PolygonizeStats rebuildBlocks(const BlockList& blocks, bool threaded = true,
                                  const std::atomic<bool>* cancel = nullptr);

    /// Tells the polygonizer the skeleton writes (SkeletonStore::logWritesTo) that took the
    /// sculpture to its current state since the last call. Each block that was evaluated
    /// keeps its grid values as fixed-point sums of terms (EvalField.h); the writes' old terms
    /// are subtracted and new ones added there, so rebuilding a block after an edit costs no
    /// grid evaluations, whatever the number of skeletons piled up on it. Without this call
    /// (or when the writes do not account for every write the store saw) the kept sums are
    /// dropped at the next rebuild and evaluated afresh: same mesh, more work.
    /// Writes to the same skeleton count once, as their net change (the sums telescope).
    /// Returns the number of block updates made (one skeleton's term over one block).
    size_t noteWrites(std::span<const SkeletonWrite> writes);

    const GridRegion& region() const { return mRegion; }

    /// Runs this polygonizer's parallel loops on `pool` (not owned; must outlive its use)
    /// instead of oneTBB's shared workers; nullptr: back to oneTBB. The async mesher hands its
    /// idle-priority pool here.
    void useWorkers(WorkerPool* pool) { mWorkers = pool; }
    WorkerPool* workers() const { return mWorkers; }

    /// Validation mode (`vsculpt play --check`): polygonizes everything afresh and compares
    /// with the incrementally maintained mesh. Empty when identical, else the first
    /// difference (a triangle present in only one of them, with its coordinates).
    std::string verifyAgainstFullRebuild() const;

    /// The whole mesh, vertices welded per grid edge (deterministic order).
    Mesh mesh() const;

    int chunksPerAxis() const { return mRegion.n / kChunkCells; }
    /// Incremented every time the chunk's mesh changes; 0 = never had triangles.
    uint64_t chunkVersion(int cx, int cy, int cz) const;
    /// One chunk's triangles as a self-contained indexed mesh (for upload).
    Mesh chunkMesh(int cx, int cy, int cz) const;

    /// Grid cells of one tetrahedron of the Kuhn split: corner indices (bit 0 = +x,
    /// bit 1 = +y, bit 2 = +z) of tetrahedron t in 0..5.
    static const std::array<std::array<int, 4>, 6>& kuhnTetrahedra();

  private:
    struct EdgeVertex {
        uint64_t key;
        Vec3 position, normal;
        friend bool operator==(const EdgeVertex&, const EdgeVertex&) = default;
    };
    struct BlockMesh {
        std::vector<EdgeVertex> vertices;                // sorted by key
        std::vector<std::array<uint64_t, 3>> triangles;  // edge keys, outward order
        friend bool operator==(const BlockMesh&, const BlockMesh&) = default;
    };

    /// The vertex on grid edge `key`, from the block that owns the edge (the one holding its
    /// start vertex). Throws std::logic_error if missing: an invariant of the mesh.
    const EdgeVertex& findVertex(uint64_t key) const;
    void appendBlock(const BlockMesh& b, Mesh& m,
                     std::unordered_map<uint64_t, uint32_t>& index) const;
    size_t blockIndex(int bx, int by, int bz) const {
        return (size_t(bx) * mBlocksPerAxis + by) * mBlocksPerAxis + bz;
    }
    std::array<int, 3> blockAt(size_t index) const {
        const size_t n = size_t(mBlocksPerAxis);
        return {int(index / (n * n)), int(index / n % n), int(index % n)};
    }
    Aabb blockBox(int bx, int by, int bz, int cells) const;
    /// Meshes one block from its grid sums, which it must have (rebuild evaluates missing
    /// ones first). Returns false when no grid edge of the block crosses the surface.
    /// `field`: the block's skeletons if gathered already, else gathered here when a root
    /// needs them. `evaluations` and `gathered` (blocks whose skeletons it gathered) are
    /// added to.
    bool buildBlock(int bx, int by, int bz, BlockMesh& out, std::unique_ptr<LocalField>& field,
                    size_t& evaluations, size_t& gathered) const;
    /// A rebuild works through its blocks in slices of at most this many.
    static constexpr size_t kSliceBlocks = 2048;
    /// Rebuild's first step: grid sums for the blocks [begin, end) of `blocks` that have none and
    /// whose bounds may hold surface; the others are marked in `culled`. A grid vertex that
    /// several blocks share is splatted once (by one of them, or taken from a block whose sums
    /// are kept). `fields` gets each evaluated block's skeletons, for its roots. Blocks that
    /// `cancel` stopped are cleared in `finished`. Counts go to `stats`.
    void evaluateMissingSums(const BlockList& blocks, size_t begin, size_t end,
                             std::vector<char>& culled, std::vector<char>& finished,
                             std::vector<std::unique_ptr<LocalField>>& fields, bool threaded,
                             const std::atomic<bool>* cancel, PolygonizeStats& stats) const;
    /// Whether block (bx, by, bz) lies in the region and has grid sums.
    bool hasSums(int bx, int by, int bz) const {
        return bx < mBlocksPerAxis && by < mBlocksPerAxis && bz < mBlocksPerAxis &&
               sumsOf(bx, by, bz) != nullptr;
    }
    /// `culled`: blocks known to hold no surface (empty: none known), one per block.
    PolygonizeStats rebuild(const std::vector<std::array<int, 3>>& blocks, bool threaded,
                            std::vector<char> culled, const std::atomic<bool>* cancel = nullptr);
    /// Per chunk: 1 when its LocalField bounds show that no surface passes through it.
    std::vector<char> cullChunks(bool threaded) const;

    const Sculpture& mSculpture;
    GridRegion mRegion;
    WorkerPool* mWorkers = nullptr;
    double mTolerance;  // mm
    int mBlocksPerAxis;
    std::vector<uint64_t> mChunkVersions;
    // Each evaluated block's (kBlockCells + 1)^3 grid values as fixed-point sums of terms,
    // current for the store's write count mSumsAt (noteWrites). Absent for blocks never
    // evaluated. Written during a rebuild only by the thread building that block.
    struct BlockSums {
        std::array<FixedSum, (kBlockCells + 1) * (kBlockCells + 1) * (kBlockCells + 1)> values;
        // The block's mesh (mBlocks) was built with these sums, and `touched` holds the support
        // balls (centre, squared radius with a rounding margin) of every write that reached the
        // block since: an edge that none of them reaches has the same field along it, bit for
        // bit, so its old root is kept instead of solved again. Cleared when the block is
        // rebuilt; past kMaxTouched balls the block solves every edge afresh.
        bool meshFromSums = false;
        std::vector<std::pair<Vec3, double>> touched;
    };
    static constexpr size_t kMaxTouched = 64;
    // For blocks without sums whose bounds showed that no surface passes through them (empty
    // or solid), or whose grid values showed that none crosses their grid edges: those bounds,
    // or the values' range, widened by every write noteWrites saw reach the block since, so
    // that a block a write reaches but leaves empty (or solid) is skipped without gathering its
    // skeletons again. Sound bounds stay sound under widening, so what is skipped is exactly
    // what a full rebuild culls or meshes to nothing. kUnknownBounds where not kept; current
    // for mSumsAt, like the sums.
    static constexpr FieldBounds kUnknownBounds{1, -1};
    uint64_t mSumsAt = 0;

    // What is kept per block (its mesh, its grid sums, its no-surface bounds) lives in one page
    // per chunk, made when one of the chunk's blocks is first evaluated: a region's memory then
    // follows the chunks that may hold surface, not the whole box (a whole-sculpture grid of
    // 1024^3 cells over clay far apart held 72 bytes for each of its 16.7 M blocks, 1.2 GB).
    // Pages are made only by the serial parts of a rebuild (makePages), so the parallel parts
    // find every page they write to; no page means an empty mesh, no sums and unknown bounds.
    static constexpr int kBlocksPerChunkAxis = kChunkCells / kBlockCells;
    static_assert(kBlocksPerChunkAxis == 2, "a page's slot is one bit per axis");
    struct ChunkPage {
        std::array<BlockMesh, 8> meshes;
        std::array<std::unique_ptr<BlockSums>, 8> sums;
        std::array<FieldBounds, 8> noSurface;
        ChunkPage() { noSurface.fill(kUnknownBounds); }
    };
    mutable std::vector<std::unique_ptr<ChunkPage>> mPages;  // by chunk index
    size_t chunkIndexOf(int bx, int by, int bz) const {
        const size_t c = size_t(chunksPerAxis());
        return (size_t(bx / 2) * c + size_t(by / 2)) * c + size_t(bz / 2);
    }
    static int pageSlot(int bx, int by, int bz) { return (bx & 1) | (by & 1) << 1 | (bz & 1) << 2; }
    ChunkPage* pageOf(int bx, int by, int bz) const {
        return mPages[chunkIndexOf(bx, by, bz)].get();
    }
    /// Makes the pages of blocks [begin, end) of `blocks` not marked in `skip`. Serial.
    void makePages(const BlockList& blocks, size_t begin, size_t end,
                   const std::vector<char>& skip) const;
    /// The block's mesh (empty without a page).
    const BlockMesh& blockMesh(int bx, int by, int bz) const;
    /// The block's sums, or nullptr.
    BlockSums* sumsOf(int bx, int by, int bz) const {
        const ChunkPage* p = pageOf(bx, by, bz);
        return p ? p->sums[size_t(pageSlot(bx, by, bz))].get() : nullptr;
    }
    void dropSums();
    /// Block indices whose closed boxes may touch `box` (one block of slack each side),
    /// clamped to the region; false when none.
    bool blockRange(const Aabb& box, std::array<int, 3>& lo, std::array<int, 3>& hi) const;
    /// The x, y and z coordinates of a block's (kBlockCells + 1) grid planes.
    void blockAxes(int bx, int by, int bz, double* xs, double* ys, double* zs) const;
};

}  // namespace vsculpt::core
