// SPDX-License-Identifier: MIT
#include "vsculpt/core/Polygonizer.h"

#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Sculpture.h"

#include <tbb/combinable.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <unordered_map>

namespace vsculpt::core {

namespace {

constexpr int64_t kCoordLimit = int64_t(1) << 19;
/// Illinois steps per edge root at most: it converges superlinearly, so this is only a guard
/// against a field that is flat where it crosses zero.
constexpr int kMaxRootSteps = 40;
/// The first-order distance |f| / |grad f| underestimates the true distance where f curves
/// (by up to 12 %, measured on sculpted clay over the initial sphere's steep core; 8 % over
/// the one-skeleton sphere): roots stop at this fraction of the tolerance, which leaves room
/// for the inset below too.
constexpr double kFirstOrderMargin = 0.85;
/// Edge vertices keep at least this fraction of the root tolerance from the edge's grid
/// vertices. Where the surface passes a hair from a grid vertex, the roots on the edges around
/// it would lie that hair from it and from each other: triangles with edges of a fraction of a
/// micron (1e-7 mm for a grid value 1e-7 above zero), which tools that weld close vertices
/// (slicers, mesh repair) collapse into non-manifold edges. The vertex stays on its edge, so in
/// the same tetrahedra: no topology changes, no cracks; it moves by at most this fraction of
/// the tolerance, within the bound the roots keep (docs/polygonizer.md).
constexpr double kVertexInsetOverTolerance = 0.05;

/// body(i) for i in [begin, end): on `pool` (or oneTBB) in ranges of at least `grain` when
/// `threaded`, else in order.
template <typename Body>
void forEachIndex(WorkerPool* pool, bool threaded, size_t begin, size_t end, Body&& body,
                  size_t grain = 2) {
    if (!threaded) {
        for (size_t i = begin; i < end; ++i)
            body(i);
        return;
    }
    parallelFor(pool, end - begin, grain, [&](size_t i0, size_t i1) {
        for (size_t i = begin + i0; i < begin + i1; ++i)
            body(i);
    });
}

/// Grid edge from vertex g (the componentwise smaller end) along dir (bits x, y, z).
uint64_t edgeKey(int64_t gx, int64_t gy, int64_t gz, int dir) {
    constexpr uint64_t m = (uint64_t(1) << 20) - 1;
    return (uint64_t(gx) & m) | ((uint64_t(gy) & m) << 20) | ((uint64_t(gz) & m) << 40) |
           (uint64_t(dir) << 60);
}

/// The inverse of edgeKey for one axis (0..2): the start vertex's grid coordinate.
int64_t edgeKeyCoord(uint64_t key, int axis) {
    constexpr uint64_t m = (uint64_t(1) << 20) - 1;
    const int64_t g = int64_t((key >> (20 * axis)) & m);
    return g >= (int64_t(1) << 19) ? g - (int64_t(1) << 20) : g;  // sign-extend 20 bits
}

Vec3 cornerOffset(int c) {
    return Vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
}

/// What a tetrahedron of the Kuhn split emits for one choice of inside corners: the crossed
/// edges (corner pairs, smaller corner first) in the order the triangles use them, and whether
/// the triangles' order must flip to face outward. The same in every cell, so it is worked out
/// once per tetrahedron and sign mask instead of for every crossed tetrahedron of every block.
struct TetCase {
    int edges = 0;  // 0: no crossing, 3: one triangle, 4: a quad (two triangles)
    std::array<std::array<int, 2>, 4> edge{};
    bool flip = false;
};

/// Indexed by tetrahedron and mask (bit q: the tetrahedron's corner q is inside).
const std::array<std::array<TetCase, 16>, 6>& tetrahedronCases() {
    static const auto cases = [] {
        std::array<std::array<TetCase, 16>, 6> out{};
        const auto& tets = Polygonizer::kuhnTetrahedra();
        for (size_t t = 0; t < tets.size(); ++t)
            for (int mask = 1; mask < 15; ++mask) {
                int in[4], out4[4], nIn = 0, nOut = 0;
                for (int q = 0; q < 4; ++q)
                    ((mask >> q) & 1 ? in[nIn++] : out4[nOut++]) = tets[t][size_t(q)];
                // Outward: from the inside corners towards the outside ones.
                Vec3 g(0.0);
                for (int q = 0; q < nOut; ++q)
                    g += cornerOffset(out4[q]);
                for (int q = 0; q < nIn; ++q)
                    g -= cornerOffset(in[q]);
                std::array<std::pair<int, int>, 4> e{};
                int ne = 0;
                if (nIn == 1) {
                    for (int q = 0; q < 3; ++q)
                        e[size_t(ne++)] = {in[0], out4[q]};
                } else if (nOut == 1) {
                    for (int q = 0; q < 3; ++q)
                        e[size_t(ne++)] = {in[q], out4[0]};
                } else {  // two and two: a quad, cyclic through shared corners
                    e = {{{in[0], out4[0]}, {in[0], out4[1]}, {in[1], out4[1]}, {in[1], out4[0]}}};
                    ne = 4;
                }
                // Orientation from the exact edge midpoints (never the roots, which can
                // coincide), so it is consistent even for degenerate triangles.
                auto mid = [](const std::pair<int, int>& ab) {
                    return 0.5 * (cornerOffset(ab.first) + cornerOffset(ab.second));
                };
                const Vec3 m0 = mid(e[0]), m1 = mid(e[1]), m2 = mid(e[2]);
                TetCase& c = out[t][size_t(mask)];
                c.edges = ne;
                c.flip = glm::dot(glm::cross(m1 - m0, m2 - m0), g) < 0;
                for (int q = 0; q < ne; ++q)
                    c.edge[size_t(q)] = {std::min(e[size_t(q)].first, e[size_t(q)].second),
                                         std::max(e[size_t(q)].first, e[size_t(q)].second)};
            }
        return out;
    }();
    return cases;
}

/// The net change of each skeleton `writes` touch, one write each (ordered by level and
/// coordinate): from the first write's `before` to the last one's weight. A swept sample's fit
/// rewrites the weights around earlier samples again, and the asynchronous mesher notes several
/// samples' writes at once (about 30 % of two consecutive samples' writes are to the same
/// skeletons). Kept sums follow the net change to the same bits: their integer terms telescope.
std::vector<SkeletonWrite> netWrites(std::span<const SkeletonWrite> writes) {
    std::vector<uint32_t> order(writes.size());
    for (uint32_t i = 0; i < order.size(); ++i)
        order[i] = i;
    auto key = [&](uint32_t i) { return std::pair(writes[i].level, writes[i].coord); };
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    std::vector<SkeletonWrite> net;
    net.reserve(writes.size());
    for (size_t i = 0; i < order.size();) {
        size_t j = i + 1;
        while (j < order.size() && key(order[j]) == key(order[i]))
            ++j;
        SkeletonWrite w = writes[order[j - 1]];
        w.before = writes[order[i]].before;
        net.push_back(w);
        i = j;
    }
    return net;
}

}  // namespace

const std::array<std::array<int, 4>, 6>& Polygonizer::kuhnTetrahedra() {
    // One tetrahedron per order of the axes: 0 -> +first -> +second -> (1,1,1).
    static const std::array<std::array<int, 4>, 6> tets = {{
        {0, 1, 3, 7},  // x, y, z
        {0, 1, 5, 7},  // x, z, y
        {0, 2, 3, 7},  // y, x, z
        {0, 2, 6, 7},  // y, z, x
        {0, 4, 5, 7},  // z, x, y
        {0, 4, 6, 7},  // z, y, x
    }};
    return tets;
}

Polygonizer::Polygonizer(const Sculpture& sculpture, const GridRegion& region, double relTolerance)
    : mSculpture(sculpture), mRegion(region), mTolerance(relTolerance * region.spacingMm) {
    if (region.n <= 0 || region.n % kChunkCells != 0)
        throw std::invalid_argument("polygonizer grid N must be a positive multiple of 16");
    for (int a = 0; a < 3; ++a)
        if (std::abs(region.originCell[a]) + region.n + 1 >= kCoordLimit)
            throw std::invalid_argument("polygonizer region lies outside the grid's range");
    if (!(relTolerance > 0)) throw std::invalid_argument("bisection tolerance must be > 0");
    mBlocksPerAxis = region.n / kBlockCells;
    mSumsAt = sculpture.store().writeCount();
    const int c = chunksPerAxis();
    mChunkVersions.assign(size_t(c) * c * c, 0);
    mPages.resize(mChunkVersions.size());
}

const Polygonizer::BlockMesh& Polygonizer::blockMesh(int bx, int by, int bz) const {
    static const BlockMesh kEmpty;
    const ChunkPage* p = pageOf(bx, by, bz);
    return p ? p->meshes[size_t(pageSlot(bx, by, bz))] : kEmpty;
}

void Polygonizer::makePages(const BlockList& blocks, size_t begin, size_t end,
                            const std::vector<char>& skip) const {
    for (size_t i = begin; i < end; ++i) {
        if (skip[i]) continue;
        auto& page = mPages[chunkIndexOf(blocks[i][0], blocks[i][1], blocks[i][2])];
        if (!page) page = std::make_unique<ChunkPage>();
    }
}

Aabb Polygonizer::blockBox(int bx, int by, int bz, int cells) const {
    const auto& o = mRegion.originCell;
    const int64_t x = o[0] + int64_t(bx) * kBlockCells, y = o[1] + int64_t(by) * kBlockCells,
                  z = o[2] + int64_t(bz) * kBlockCells;
    return Aabb{mRegion.vertexPos(x, y, z), mRegion.vertexPos(x + cells, y + cells, z + cells)};
}

bool Polygonizer::buildBlock(int bx, int by, int bz, BlockMesh& out,
                             std::unique_ptr<LocalField>& field, size_t& evals,
                             size_t& gathered) const {
    out.vertices.clear();
    out.triangles.clear();
    const Aabb box = blockBox(bx, by, bz, kBlockCells);
    constexpr int V = kBlockCells + 1;
    const int64_t gx0 = mRegion.originCell[0] + int64_t(bx) * kBlockCells;
    const int64_t gy0 = mRegion.originCell[1] + int64_t(by) * kBlockCells;
    const int64_t gz0 = mRegion.originCell[2] + int64_t(bz) * kBlockCells;
    ChunkPage* page = pageOf(bx, by, bz);
    const size_t slot = size_t(pageSlot(bx, by, bz));
    if (!page || !page->sums[slot])
        throw std::logic_error("Polygonizer::buildBlock: the block has no grid sums");
    std::unique_ptr<BlockSums>& sums = page->sums[slot];
    // The roots of edges no write reached since the last build can be kept (BlockSums).
    const BlockMesh* old = sums->meshFromSums ? &page->meshes[slot] : nullptr;
    const double iso = mSculpture.levels().iso();
    double values[V][V][V];
    FieldBounds range{std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity()};
    for (int i = 0; i < V; ++i)
        for (int j = 0; j < V; ++j)
            for (int k = 0; k < V; ++k) {
                values[i][j][k] = fixedToField(sums->values[size_t((i * V + j) * V + k)], iso);
                range.min = std::min(range.min, values[i][j][k]);
                range.max = std::max(range.max, values[i][j][k]);
            }
    if (!range.mayContainSurface()) {
        // No grid edge of the block crosses the surface, so its mesh is empty whatever f does
        // between the vertices. Its sums are dropped for the range of its values (kept and
        // widened as noteWrites does for bounds): most such blocks lie inside piled-up clay,
        // where loose bounds had them evaluated, and updating their sums at every write that
        // reaches them was most of a re-mesh there (docs/benchmarks.md). A write that may
        // bring a sign change has the block evaluated afresh, to the same sums.
        sums.reset();
        page->noSurface[slot] = range;
        return false;
    }
    // Whether a write since the old mesh reached the closed box [lo, hi] (the samples of an
    // edge's root lie in it).
    auto touched = [&](const Vec3& lo, const Vec3& hi) {
        for (const auto& [c, r2] : sums->touched) {
            const Vec3 d = c - glm::clamp(c, lo, hi);
            if (glm::dot(d, d) < r2) return true;
        }
        return false;
    };

    // Grid edges of the block by local start vertex and direction: computed yet or not.
    // (A flat table: no hashing or allocation on this hot path.)
    std::array<bool, V * V * V * 8> done{};
    // The crossing on the grid edge from local vertex a along dir (both ends in the block).
    auto crossing = [&](int ai, int aj, int ak, int dir) -> uint64_t {
        const uint64_t key = edgeKey(gx0 + ai, gy0 + aj, gz0 + ak, dir);
        // An edge belongs to the block holding its start vertex; edges starting on this
        // block's far faces are computed (once) by the next block, which has to be rebuilt
        // too whenever the field there changes (its closed box contains them).
        // (At the region's far faces there is no next block: the last one keeps them.)
        const int last = mBlocksPerAxis - 1;
        if ((ai == kBlockCells && bx < last) || (aj == kBlockCells && by < last) ||
            (ak == kBlockCells && bz < last))
            return key;
        bool& seen = done[size_t(((ai * V + aj) * V + ak) * 8 + dir)];
        if (seen) return key;
        seen = true;
        const int bi = ai + (dir & 1), bj = aj + ((dir >> 1) & 1), bk = ak + ((dir >> 2) & 1);
        const Vec3 edgeLo = mRegion.vertexPos(gx0 + ai, gy0 + aj, gz0 + ak);
        const Vec3 edgeHi = mRegion.vertexPos(gx0 + bi, gy0 + bj, gz0 + bk);
        Vec3 lo = edgeLo, hi = edgeHi;
        if (old && !touched(lo, hi)) {
            // The end values are the same too, so the edge crossed before and its vertex is
            // in the old mesh (not found only after a chunk cull emptied it: solved below).
            const auto it =
                std::lower_bound(old->vertices.begin(), old->vertices.end(), key,
                                 [](const EdgeVertex& v, uint64_t k) { return v.key < k; });
            if (it != old->vertices.end() && it->key == key) {
                out.vertices.push_back(*it);
                return key;
            }
        }
        if (!field) {
            field = std::make_unique<LocalField>(mSculpture, box);
            ++gathered;
        }
        double flo = values[ai][aj][ak], fhi = values[bi][bj][bk];
        // Always from the smaller end, so every block computing this edge gets the same bits.
        const bool loInside = flo > 0;
        Vec3 p;
        FieldSample s;
        // Illinois (regula falsi that halves the stale end's value when the same end is
        // replaced twice): the first linear guess usually already lies within the tolerance
        // of the surface, and its sample gives the vertex normal as well, so most crossings
        // cost one evaluation (docs/polygonizer.md has the measured error).
        int replaced = 0;  // -1: lo, +1: hi was replaced by the last step
        for (int step = 0;; ++step) {
            const double t = std::clamp(flo / (flo - fhi), 0.0, 1.0);
            p = lo + t * (hi - lo);
            s = field->sample(p);
            ++evals;
            // |f| / |grad f|: the first-order distance from p to the surface.
            if (std::abs(s.value) <= kFirstOrderMargin * mTolerance * glm::length(s.gradient) ||
                glm::length(hi - lo) <= mTolerance || step == kMaxRootSteps)
                break;
            if ((s.value > 0) == loInside) {
                lo = p;
                flo = s.value;
                if (replaced < 0) fhi *= 0.5;
                replaced = -1;
            } else {
                hi = p;
                fhi = s.value;
                if (replaced > 0) flo *= 0.5;
                replaced = 1;
            }
        }
        {
            // Clamped on the grid edge itself, so every build of this edge gets the same bits.
            const Vec3 ab = edgeHi - edgeLo;
            const double length = glm::length(ab);
            const double inset = std::min(0.5, kVertexInsetOverTolerance * mTolerance / length);
            const double u = glm::dot(p - edgeLo, ab) / (length * length);
            if (u < inset || u > 1 - inset) p = edgeLo + std::clamp(u, inset, 1 - inset) * ab;
        }
        const double g = glm::length(s.gradient);
        const Vec3 n = g > 0 ? -s.gradient / g : Vec3(0.0);
        out.vertices.push_back(EdgeVertex{key, p, n});
        return key;
    };

    const auto& tets = kuhnTetrahedra();
    const auto& cases = tetrahedronCases();
    for (int i = 0; i < kBlockCells; ++i)
        for (int j = 0; j < kBlockCells; ++j)
            for (int k = 0; k < kBlockCells; ++k) {
                double f[8];
                int inside = 0;
                for (int c = 0; c < 8; ++c) {
                    f[c] = values[i + (c & 1)][j + ((c >> 1) & 1)][k + ((c >> 2) & 1)];
                    inside += f[c] > 0;
                }
                if (inside == 0 || inside == 8) continue;
                for (size_t t = 0; t < tets.size(); ++t) {
                    int mask = 0;
                    for (int q = 0; q < 4; ++q)
                        mask |= int(f[tets[t][size_t(q)]] > 0) << q;
                    const TetCase& tc = cases[t][size_t(mask)];
                    if (tc.edges == 0) continue;
                    // Tetrahedron edges join corners a < b with b's bits a superset of a's.
                    uint64_t key[4];
                    for (int q = 0; q < tc.edges; ++q) {
                        const int lo = tc.edge[size_t(q)][0], hi = tc.edge[size_t(q)][1];
                        key[q] = crossing(i + (lo & 1), j + ((lo >> 1) & 1), k + ((lo >> 2) & 1),
                                          hi ^ lo);
                    }
                    auto emit = [&](uint64_t a, uint64_t b, uint64_t c) {
                        out.triangles.push_back(tc.flip ? std::array<uint64_t, 3>{a, c, b}
                                                        : std::array<uint64_t, 3>{a, b, c});
                    };
                    emit(key[0], key[1], key[2]);
                    if (tc.edges == 4) emit(key[0], key[2], key[3]);
                }
            }
    std::sort(out.vertices.begin(), out.vertices.end(),
              [](const EdgeVertex& a, const EdgeVertex& b) { return a.key < b.key; });
    sums->meshFromSums = true;
    sums->touched.clear();
    return true;
}

bool Polygonizer::blockRange(const Aabb& box, std::array<int, 3>& lo,
                             std::array<int, 3>& hi) const {
    const Vec3 origin = mRegion.box().min;
    const double blockSize = kBlockCells * mRegion.spacingMm;
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(0, int(std::floor((box.min[a] - origin[a]) / blockSize)) - 1);
        hi[a] =
            std::min(mBlocksPerAxis - 1, int(std::floor((box.max[a] - origin[a]) / blockSize)) + 1);
        empty |= lo[a] > hi[a];
    }
    return !empty;
}

void Polygonizer::blockAxes(int bx, int by, int bz, double* xs, double* ys, double* zs) const {
    const int64_t gx0 = mRegion.originCell[0] + int64_t(bx) * kBlockCells;
    const int64_t gy0 = mRegion.originCell[1] + int64_t(by) * kBlockCells;
    const int64_t gz0 = mRegion.originCell[2] + int64_t(bz) * kBlockCells;
    for (int i = 0; i <= kBlockCells; ++i) {
        const Vec3 p = mRegion.vertexPos(gx0 + i, gy0 + i, gz0 + i);
        xs[i] = p.x;
        ys[i] = p.y;
        zs[i] = p.z;
    }
}

void Polygonizer::dropSums() {
    for (auto& page : mPages) {
        if (!page) continue;
        for (auto& s : page->sums)
            s.reset();
        page->noSurface.fill(kUnknownBounds);
    }
}

size_t Polygonizer::noteWrites(std::span<const SkeletonWrite> writes) {
    const uint64_t now = mSculpture.store().writeCount();
    if (now != mSumsAt + writes.size()) {  // some write went unseen: start afresh
        dropSums();
        mSumsAt = now;
        return 0;
    }
    mSumsAt = now;
    const ToolLevels& levels = mSculpture.levels();
    const HermiteFalloff& falloff = levels.falloff();
    struct Term {
        Vec3 c;
        double before, after, invR, r2, reach2;
    };
    std::vector<Term> terms;
    std::vector<std::pair<uint32_t, uint32_t>> hits;  // (block, term) pairs with kept sums
    for (const SkeletonWrite& w : netWrites(writes)) {
        const double before = w.before ? double(*w.before) : 0.0;
        const double after = w.weight ? double(*w.weight) : 0.0;
        if (before == after) continue;
        const ToolLevel& tl = levels.level(w.level);
        // The centre, 1/R and R^2 exactly as LocalField computes them.
        const double h = tl.spacingMm, R = tl.supportMm;
        // reach2: R^2 widened for rounding (in the samples' distances and in the points an
        // edge root tries), for the test of which edge roots the write may change.
        const double reach = R * (1 + 1e-9) + 1e-9;
        const Vec3 c(w.coord.x * h, w.coord.y * h, w.coord.z * h);
        const Term t{c, before, after, 1.0 / R, R * R, reach * reach};
        std::array<int, 3> lo{}, hi{};
        if (!blockRange(Aabb{t.c - Vec3(R), t.c + Vec3(R)}, lo, hi)) continue;
        const double delta = after - before;
        for (int bx = lo[0]; bx <= hi[0]; ++bx)
            for (int by = lo[1]; by <= hi[1]; ++by)
                for (int bz = lo[2]; bz <= hi[2]; ++bz) {
                    // Without a page the block keeps neither sums nor bounds: nothing to update.
                    ChunkPage* page = pageOf(bx, by, bz);
                    if (!page) continue;
                    const size_t slot = size_t(pageSlot(bx, by, bz));
                    FieldBounds& kept = page->noSurface[slot];
                    const bool withSums = page->sums[slot] != nullptr;
                    if (!withSums && kept.min > kept.max) continue;
                    // Nothing to do for a block the write does not reach (a third of the range
                    // and more: the ball's corners and the range's slack): f there is the same,
                    // bit for bit (LocalField gathers by the same distance, without the margin).
                    const Aabb box = blockBox(bx, by, bz, kBlockCells);
                    const Vec3 nearest = glm::clamp(c, box.min, box.max);
                    const double d2 = glm::dot(c - nearest, c - nearest);
                    if (d2 >= t.reach2) continue;
                    if (withSums) {
                        hits.emplace_back(uint32_t(blockIndex(bx, by, bz)), uint32_t(terms.size()));
                        continue;
                    }
                    // The change's term over the block lies between 0 and delta F at the
                    // block's point nearest the centre (F falls off); widened by
                    // LocalField::bounds' rounding margin for the two terms a write splats
                    // (the old weight out, the new one in). (The far corner's F, as
                    // LocalField::bounds takes it, would be tighter by a little and cost a
                    // second falloff evaluation per block: this loop is serial.)
                    const double change = delta * falloff.value(std::sqrt(d2) * t.invR);
                    const double margin =
                        1e-9 * (std::abs(before) + std::abs(after)) + 2 / kFixedPerUnit;
                    kept.min += std::min(change, 0.0) - margin;
                    kept.max += std::max(change, 0.0) + margin;
                }
        terms.push_back(t);
    }
    // Per block: its terms, in any order (integer sums). Every block's sums are updated, even
    // where more writes reach it than half the skeletons it gathered: evaluating it afresh
    // would cost fewer splats, but also a gathering, and every edge root the writes did not
    // reach (dropping such sums, as done before, measured the same at zoom 5 and up to 12 %
    // slower at p99 at zoom 3 in swept mode; docs/benchmarks.md).
    std::sort(hits.begin(), hits.end());
    std::vector<std::pair<size_t, size_t>> groups;
    for (size_t i = 0; i < hits.size();) {
        size_t j = i;
        while (j < hits.size() && hits[j].first == hits[i].first)
            ++j;
        groups.emplace_back(i, j);
        i = j;
    }
    tbb::combinable<size_t> splats([] { return size_t(0); });
    parallelFor(mWorkers, groups.size(), 8, [&](size_t g0, size_t g1) {
        for (size_t g = g0; g < g1; ++g) {
            const auto [first, last] = groups[g];
            const auto [bx, by, bz] = blockAt(hits[first].first);
            BlockSums* sums = sumsOf(bx, by, bz);
            constexpr int V = kBlockCells + 1;
            double xs[V], ys[V], zs[V];
            blockAxes(bx, by, bz, xs, ys, zs);
            const Aabb box = blockBox(bx, by, bz, kBlockCells);
            size_t& n = splats.local();
            for (size_t h = first; h < last; ++h) {
                const Term& t = terms[hits[h].second];
                if (sums->meshFromSums) {
                    const Vec3 d = t.c - glm::clamp(t.c, box.min, box.max);
                    if (glm::dot(d, d) < t.reach2) {
                        if (sums->touched.size() == kMaxTouched) {
                            sums->meshFromSums = false;
                            sums->touched.clear();
                        } else {
                            sums->touched.emplace_back(t.c, t.reach2);
                        }
                    }
                }
                splatFixedChange(falloff, t.c, t.before, t.after, t.invR, t.r2, xs, ys, zs,
                                 sums->values.data());
                n += (t.before != 0) + (t.after != 0);
            }
        }
    });
    return splats.combine(std::plus<size_t>());
}

void Polygonizer::mergeBlocks(BlockList& into, BlockList more) {
    if (more.empty()) return;
    if (into.empty()) {
        into = std::move(more);
        return;
    }
    BlockList out;
    out.reserve(into.size() + more.size());
    std::set_union(into.begin(), into.end(), more.begin(), more.end(), std::back_inserter(out));
    into = std::move(out);
}

void Polygonizer::evaluateMissingSums(const BlockList& blocks, size_t begin, size_t end,
                                      std::vector<char>& culled, std::vector<char>& finished,
                                      std::vector<std::unique_ptr<LocalField>>& fields,
                                      bool threaded, const std::atomic<bool>* cancel,
                                      PolygonizeStats& stats) const {
    constexpr int B = kBlockCells, V = kBlockCells + 1;
    auto forEach = [&](auto&& body) { forEachIndex(mWorkers, threaded, begin, end, body); };
    tbb::combinable<size_t> evals([] { return size_t(0); });
    tbb::combinable<size_t> gathers([] { return size_t(0); });
    std::vector<char> freshFromBegin(end - begin, 0);
    auto fresh = [&](size_t i) -> char& { return freshFromBegin[i - begin]; };
    // The pages step 1 may write to, made here while nothing else runs.
    makePages(blocks, begin, end, culled);
    // 1. Which blocks need their sums: gathered, and their bounds tested.
    forEach([&](size_t i) {
        if (culled[i]) return;
        if (cancel && cancel->load(std::memory_order_relaxed)) {
            finished[i] = 0;
            return;
        }
        const auto& b = blocks[i];
        ChunkPage& page = *pageOf(b[0], b[1], b[2]);
        const size_t slot = size_t(pageSlot(b[0], b[1], b[2]));
        if (page.sums[slot]) return;
        FieldBounds& kept = page.noSurface[slot];
        if (kept.min <= kept.max && !kept.mayContainSurface()) {
            culled[i] = 1;
            return;
        }
        auto field = std::make_unique<LocalField>(mSculpture, blockBox(b[0], b[1], b[2], B));
        ++gathers.local();
        const FieldBounds bounds = field->bounds();
        if (!bounds.mayContainSurface()) {
            kept = bounds;
            culled[i] = 1;
            return;
        }
        kept = kUnknownBounds;
        page.sums[slot] = std::make_unique<BlockSums>();
        fields[i] = std::move(field);
        fresh(i) = 1;
    });
    stats.blocksGathered += gathers.combine(std::plus<size_t>());
    // Most of an edit's blocks keep their sums: then the steps below have nothing to do, and
    // are not dispatched to the workers at all.
    if (std::find(freshFromBegin.begin(), freshFromBegin.end(), 1) == freshFromBegin.end()) return;
    if (cancel && cancel->load(std::memory_order_relaxed)) {
        // Half-made sums are dropped; those blocks are left stale, as the cancel asks.
        for (size_t i = begin; i < end; ++i)
            if (fresh(i)) {
                const auto& b = blocks[i];
                pageOf(b[0], b[1], b[2])->sums[size_t(pageSlot(b[0], b[1], b[2]))].reset();
                fields[i].reset();
                finished[i] = 0;
            }
        return;
    }
    // 2. Each skeleton splatted onto the vertices it reaches (not every skeleton visited at
    // every vertex: piled-up clay has many small skeletons per block), in fixed point so that
    // noteWrites can keep the sums exact afterwards. A block skips its far face on an axis
    // where the next block has sums (kept, or made here): the vertices there are shared and
    // taken from it in step 3. Sums of integer terms do not depend on which block adds them
    // up: both blocks gather every skeleton that reaches a vertex on their common face (the
    // face is in both closed boxes) and compute its term from the same coordinates.
    auto ownExtent = [&](const std::array<int, 3>& b, int axis) {
        std::array<int, 3> n = b;
        ++n[size_t(axis)];
        return hasSums(n[0], n[1], n[2]) ? B : V;  // vertices evaluated along `axis`
    };
    forEach([&](size_t i) {
        if (!fresh(i)) return;
        const auto& b = blocks[i];
        const int ex = ownExtent(b, 0), ey = ownExtent(b, 1), ez = ownExtent(b, 2);
        double xs[V], ys[V], zs[V];
        blockAxes(b[0], b[1], b[2], xs, ys, zs);
        FixedSum part[V * V * V];
        fields[i]->gridSums(std::span(xs, size_t(ex)), std::span(ys, size_t(ey)),
                            std::span(zs, size_t(ez)), part);
        auto& values = sumsOf(b[0], b[1], b[2])->values;
        for (int x = 0; x < ex; ++x)
            for (int y = 0; y < ey; ++y)
                for (int z = 0; z < ez; ++z)
                    values[size_t((x * V + y) * V + z)] = part[(x * ey + y) * ez + z];
        evals.local() += size_t(ex * ey * ez);
    });
    const size_t values = evals.combine(std::plus<size_t>());
    stats.gridValues += values;
    stats.evaluations += values;
    // 3. The shared vertices a block skipped, from the block that has them: step from the block
    // to the next one along any axis where the vertex is on the far face and the next block has
    // sums, until no such step is left. That block has sums, and for every axis where the vertex
    // is still on its far face the block after it has none, so if it was evaluated in step 2
    // it did not skip the vertex. Step 2 has finished, so every such value is there.
    forEach([&](size_t i) {
        if (!fresh(i)) return;
        const auto& b = blocks[i];
        const int ex = ownExtent(b, 0), ey = ownExtent(b, 1), ez = ownExtent(b, 2);
        auto& values = sumsOf(b[0], b[1], b[2])->values;
        for (int x = 0; x < V; ++x)
            for (int y = 0; y < V; ++y)
                for (int z = 0; z < V; ++z) {
                    if (x < ex && y < ey && z < ez) continue;
                    std::array<int, 3> at = b, local{x, y, z};
                    for (bool stepped = true; stepped;) {
                        stepped = false;
                        for (size_t a = 0; a < 3; ++a) {
                            if (local[a] != B) continue;
                            std::array<int, 3> n = at;
                            ++n[a];
                            if (!hasSums(n[0], n[1], n[2])) continue;
                            at = n;
                            local[a] = 0;
                            stepped = true;
                        }
                    }
                    values[size_t((x * V + y) * V + z)] =
                        sumsOf(at[0], at[1], at[2])
                            ->values[size_t((local[0] * V + local[1]) * V + local[2])];
                }
    });
}

std::vector<char> Polygonizer::cullChunks(bool threaded) const {
    // One bounds test per chunk saves one per block in the (many) empty chunks.
    const int c = chunksPerAxis();
    std::vector<char> chunkCulled(size_t(c) * c * c, 0);
    auto testChunk = [&](size_t idx) {
        const int cx = int(idx / (size_t(c) * c)), cy = int(idx / c % c), cz = int(idx % c);
        const int per = kBlocksPerChunkAxis;
        const LocalField field(mSculpture, blockBox(cx * per, cy * per, cz * per, kChunkCells));
        chunkCulled[idx] = !field.bounds().mayContainSurface();
    };
    forEachIndex(mWorkers, threaded, 0, chunkCulled.size(), testChunk, 16);
    return chunkCulled;
}

PolygonizeStats Polygonizer::rebuild(const std::vector<std::array<int, 3>>& blocks, bool threaded,
                                     std::vector<char> culled, const std::atomic<bool>* cancel) {
    // Kept sums are current only if every write since they were made was noted.
    if (mSculpture.store().writeCount() != mSumsAt) {
        dropSums();
        mSumsAt = mSculpture.store().writeCount();
    }
    PolygonizeStats stats;
    stats.blocksConsidered = blocks.size();
    if (culled.empty()) culled.assign(blocks.size(), 0);
    std::vector<char> changed(blocks.size(), 0);
    // 1: rebuilt; 0: skipped after a cancel (still stale).
    std::vector<char> finished(blocks.size(), 1);
    std::vector<std::unique_ptr<LocalField>> fields(blocks.size());
    tbb::combinable<size_t> evals([] { return size_t(0); });
    tbb::combinable<size_t> gathered([] { return size_t(0); });
    auto work = [&](size_t i) {
        const auto& b = blocks[i];
        if (!finished[i] || (cancel && cancel->load(std::memory_order_relaxed))) {
            finished[i] = 0;
            return;
        }
        // Built into a buffer each thread keeps (and copied into the slot, into the capacity
        // it has, only when it changed): no allocation for every block of every edit.
        thread_local BlockMesh fresh;
        fresh.vertices.clear();
        fresh.triangles.clear();
        if (!culled[i] &&
            !buildBlock(b[0], b[1], b[2], fresh, fields[i], evals.local(), gathered.local()))
            culled[i] = 1;
        fields[i].reset();
        const BlockMesh& slot = blockMesh(b[0], b[1], b[2]);
        // Which neighbouring blocks see a difference: bit s (0..7) set when the blocks at
        // offset -s (bit 0 = x, 1 = y, 2 = z) use something that changed. Bit 0: this block.
        // Vertices it owns on its low faces are used by cells of the blocks below.
        uint8_t what = fresh.triangles != slot.triangles ? 1 : 0;
        const auto& a = fresh.vertices;
        const auto& o = slot.vertices;
        auto mark = [&](uint64_t key) {
            what |= 1;
            int low = 0;  // axes on which the vertex's start sits on the block's low face
            constexpr uint64_t m = (uint64_t(1) << 20) - 1;
            for (int axis = 0; axis < 3; ++axis) {
                int64_t g = int64_t((key >> (20 * axis)) & m);
                if (g >= (int64_t(1) << 19)) g -= int64_t(1) << 20;
                if (g - mRegion.originCell[axis] == int64_t(b[axis]) * kBlockCells)
                    low |= 1 << axis;
            }
            for (int sub = 1; sub < 8; ++sub)
                if ((sub & low) == sub) what |= uint8_t(1u << sub);
        };
        size_t ia = 0, io = 0;  // both sorted by key: a merge finds what differs
        while (ia < a.size() || io < o.size()) {
            if (io == o.size() || (ia < a.size() && a[ia].key < o[io].key)) {
                mark(a[ia++].key);
            } else if (ia == a.size() || o[io].key < a[ia].key) {
                mark(o[io++].key);
            } else {
                if (!(a[ia] == o[io])) mark(a[ia].key);
                ++ia;
                ++io;
            }
        }
        if (what) {
            // A block with a mesh, old or new, was evaluated once: its page exists.
            ChunkPage* page = pageOf(b[0], b[1], b[2]);
            if (!page) throw std::logic_error("Polygonizer: a changed block has no page");
            page->meshes[size_t(pageSlot(b[0], b[1], b[2]))] = fresh;
            changed[i] = char(what);
        }
    };
    // In slices, so that the skeletons gathered for a slice's blocks (kept from their sums to
    // their roots) are held for one slice at a time: held for a whole 1e6-skeleton region they
    // nearly doubled the peak memory (docs/benchmarks.md). The last slice first: blocks sorted
    // by x take their far x faces from the slice after them, which then has kept sums.
    for (size_t end = blocks.size(); end > 0;) {
        const size_t begin = end > kSliceBlocks ? end - kSliceBlocks : 0;
        evaluateMissingSums(blocks, begin, end, culled, finished, fields, threaded, cancel, stats);
        forEachIndex(mWorkers, threaded, begin, end, work);
        end = begin;
    }

    stats.evaluations += evals.combine(std::plus<size_t>());
    stats.blocksGathered += gathered.combine(std::plus<size_t>());
    const int c = chunksPerAxis(), per = kChunkCells / kBlockCells;
    std::vector<char> chunkChanged(mChunkVersions.size(), 0);
    for (size_t i = 0; i < blocks.size(); ++i) {
        if (!finished[i]) {
            stats.unfinished.push_back(blocks[i]);
            continue;
        }
        stats.blocksCulled += culled[i];
        if (!changed[i]) continue;
        // The block's chunk, and the chunks of the blocks below it that use what changed.
        const auto& b = blocks[i];
        for (int s = 0; s < 8; ++s) {
            if (!((uint8_t(changed[i]) >> s) & 1)) continue;
            const int x = b[0] - (s & 1), y = b[1] - ((s >> 1) & 1), z = b[2] - ((s >> 2) & 1);
            if (x < 0 || y < 0 || z < 0) continue;
            chunkChanged[(size_t(x / per) * c + y / per) * c + z / per] = 1;
        }
    }
    for (size_t i = 0; i < chunkChanged.size(); ++i) {
        if (!chunkChanged[i]) continue;
        // Versions are unique across every polygonizer of the process: a renderer that sees
        // a new polygonizer at a recycled address never mistakes its chunks for old ones.
        static std::atomic<uint64_t> lastVersion{0};
        mChunkVersions[i] = ++lastVersion;
        ++stats.chunksChanged;
        stats.changedChunks.push_back({int(i / (size_t(c) * c)), int(i / c % c), int(i % c)});
    }
    return stats;
}

PolygonizeStats Polygonizer::rebuildAll(bool threaded, const std::atomic<bool>* cancel) {
    // Only the blocks of chunks that may hold surface, and of chunks that kept something (a
    // mesh to clear, sums): every other block has an empty mesh now and had one before, so
    // listing it (12 bytes each, 200 MB for a 1024^3-cell grid) would change nothing.
    const std::vector<char> chunkCulled = cullChunks(threaded);
    std::vector<std::array<int, 3>> blocks;
    std::vector<char> culled;
    size_t skipped = 0;
    for (int x = 0; x < mBlocksPerAxis; ++x)
        for (int y = 0; y < mBlocksPerAxis; ++y)
            for (int z = 0; z < mBlocksPerAxis; ++z) {
                const size_t chunk = chunkIndexOf(x, y, z);
                if (chunkCulled[chunk] && !mPages[chunk]) {
                    ++skipped;
                    continue;
                }
                blocks.push_back({x, y, z});
                culled.push_back(chunkCulled[chunk]);
            }
    PolygonizeStats stats = rebuild(blocks, threaded, std::move(culled), cancel);
    // Counted as the whole region, as if each skipped block had been listed and culled.
    stats.blocksConsidered += skipped;
    stats.blocksCulled += skipped;
    return stats;
}

PolygonizeStats Polygonizer::update(const Aabb& changed, bool threaded) {
    return rebuild(blocksTouching(changed), threaded, {});
}

PolygonizeStats Polygonizer::update(std::span<const Vec3> points, double radius, bool threaded) {
    return rebuild(blocksNear(points, radius), threaded, {});
}

PolygonizeStats Polygonizer::rebuildBlocks(const BlockList& blocks, bool threaded,
                                           const std::atomic<bool>* cancel) {
    for (const auto& b : blocks)
        for (int a = 0; a < 3; ++a)
            if (b[a] < 0 || b[a] >= mBlocksPerAxis)
                throw std::out_of_range("polygonizer: block index outside the region");
    return rebuild(blocks, threaded, {}, cancel);
}

Polygonizer::BlockList Polygonizer::blocksTouching(const Aabb& changed) const {
    if (changed.empty()) return {};
    const Aabb box = mRegion.box();
    if (!changed.intersects(box)) return {};
    // Closed boxes: a block that only touches the changed region is rebuilt too.
    std::array<int, 3> lo{}, hi{};
    blockRange(changed, lo, hi);
    std::vector<std::array<int, 3>> blocks;
    for (int x = lo[0]; x <= hi[0]; ++x)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int z = lo[2]; z <= hi[2]; ++z)
                if (blockBox(x, y, z, kBlockCells).intersects(changed)) blocks.push_back({x, y, z});
    return blocks;
}

Polygonizer::BlockList Polygonizer::blocksNear(std::span<const Vec3> points, double radius) const {
    if (points.empty()) return {};
    const double r2 = radius * radius;
    std::vector<char> marked(size_t(mBlocksPerAxis) * mBlocksPerAxis * mBlocksPerAxis, 0);
    std::vector<std::array<int, 3>> blocks;
    for (const Vec3& p : points) {
        std::array<int, 3> lo{}, hi{};
        if (!blockRange(Aabb{p - Vec3(radius), p + Vec3(radius)}, lo, hi)) continue;
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    const size_t idx = blockIndex(x, y, z);
                    if (marked[idx]) continue;
                    // The closed block box against the open ball where f can have changed.
                    const Aabb b = blockBox(x, y, z, kBlockCells);
                    const Vec3 d = p - glm::clamp(p, b.min, b.max);
                    if (glm::dot(d, d) >= r2) continue;
                    marked[idx] = 1;
                    blocks.push_back({x, y, z});
                }
    }
    std::sort(blocks.begin(), blocks.end());
    return blocks;
}

const Polygonizer::EdgeVertex& Polygonizer::findVertex(uint64_t key) const {
    constexpr uint64_t m = (uint64_t(1) << 20) - 1;
    auto field = [&](int shift) {
        int64_t v = int64_t((key >> shift) & m);
        return v >= (int64_t(1) << 19) ? v - (int64_t(1) << 20) : v;  // sign-extend 20 bits
    };
    // The owner holds the start vertex; the last block of an axis also owns its far face.
    auto owner = [&](int64_t g, int axis) {
        const int64_t local = g - mRegion.originCell[axis];
        return local < 0 ? -1 : int(std::min<int64_t>(local / kBlockCells, mBlocksPerAxis - 1));
    };
    const int bx = owner(field(0), 0), by = owner(field(20), 1), bz = owner(field(40), 2);
    if (bx < 0 || by < 0 || bz < 0 || bx >= mBlocksPerAxis || by >= mBlocksPerAxis ||
        bz >= mBlocksPerAxis)
        throw std::logic_error("polygonizer: a triangle uses an edge outside the region");
    const auto& verts = blockMesh(bx, by, bz).vertices;
    auto it = std::lower_bound(verts.begin(), verts.end(), key,
                               [](const EdgeVertex& v, uint64_t k) { return v.key < k; });
    if (it == verts.end() || it->key != key)
        throw std::logic_error("polygonizer: a triangle uses an edge its owner did not compute");
    return *it;
}

void Polygonizer::appendBlock(const BlockMesh& b, Mesh& m,
                              std::unordered_map<uint64_t, uint32_t>& index) const {
    for (const auto& t : b.triangles)
        for (uint64_t k : t) {
            auto [it, added] = index.emplace(k, uint32_t(m.positions.size()));
            if (added) {
                const EdgeVertex& v = findVertex(k);
                m.positions.push_back(v.position);
                m.normals.push_back(v.normal);
            }
            m.indices.push_back(it->second);
        }
}

Mesh Polygonizer::mesh() const {
    Mesh m;
    std::unordered_map<uint64_t, uint32_t> index;
    // In block order (x, then y, then z), whatever the pages: the mesh's vertex order.
    for (int x = 0; x < mBlocksPerAxis; ++x)
        for (int y = 0; y < mBlocksPerAxis; ++y)
            for (int z = 0; z < mBlocksPerAxis; ++z)
                if (const ChunkPage* p = pageOf(x, y, z))
                    appendBlock(p->meshes[size_t(pageSlot(x, y, z))], m, index);
    return m;
}

std::string Polygonizer::verifyAgainstFullRebuild() const {
    Polygonizer full(mSculpture, mRegion, mTolerance / mRegion.spacingMm);
    full.rebuildAll();
    const Mesh a = mesh(), b = full.mesh();
    if (canonicalMeshHash(a) == canonicalMeshHash(b)) return "";
    const std::string diff = firstMeshDifference(a, b);
    return "incremental mesh differs from a full rebuild: " +
           (diff.empty() ? std::string("same triangles, different hash") : diff);
}

uint64_t Polygonizer::chunkVersion(int cx, int cy, int cz) const {
    const int c = chunksPerAxis();
    return mChunkVersions.at((size_t(cx) * c + cy) * c + cz);
}

Mesh Polygonizer::chunkMesh(int cx, int cy, int cz) const {
    const int per = kChunkCells / kBlockCells;
    size_t triangles = 0;
    for (int x = cx * per; x < (cx + 1) * per; ++x)
        for (int y = cy * per; y < (cy + 1) * per; ++y)
            for (int z = cz * per; z < (cz + 1) * per; ++z)
                triangles += blockMesh(x, y, z).triangles.size();
    Mesh m;
    if (triangles == 0) return m;
    m.positions.reserve(triangles);
    m.normals.reserve(triangles);
    m.indices.reserve(3 * triangles);
    // Every edge a chunk's triangle uses starts at a vertex of one of its cells, so its key
    // maps to a slot of a flat table over the chunk's (kChunkCells + 1)^3 vertices and the 8
    // directions: the same first-use numbering as appendBlock's hash map, without hashing or
    // an allocation per vertex (this runs for every changed chunk of every edit). The chunk's
    // own blocks own most of its vertices: their slots point at them first (kSource), so only
    // the edges owned by the blocks beyond its far faces are looked up (findVertex).
    constexpr int V = kChunkCells + 1;
    constexpr uint32_t kUnset = ~uint32_t(0), kSource = uint32_t(1) << 31;
    std::array<uint32_t, V * V * V * 8> slot;
    slot.fill(kUnset);
    const int64_t x0 = mRegion.originCell[0] + int64_t(cx) * kChunkCells;
    const int64_t y0 = mRegion.originCell[1] + int64_t(cy) * kChunkCells;
    const int64_t z0 = mRegion.originCell[2] + int64_t(cz) * kChunkCells;
    auto local = [&](uint64_t key, int axis, int64_t origin) {
        const int64_t l = edgeKeyCoord(key, axis) - origin;
        if (l < 0 || l >= V)
            throw std::logic_error("polygonizer: a chunk's triangle uses an edge outside it");
        return size_t(l);
    };
    auto slotOf = [&](uint64_t k) -> uint32_t& {
        return slot[((local(k, 0, x0) * V + local(k, 1, y0)) * V + local(k, 2, z0)) * 8 +
                    size_t(k >> 60)];
    };
    const BlockMesh* own[per * per * per];
    for (int b = 0; b < per * per * per; ++b) {
        own[b] =
            &blockMesh(cx * per + b / (per * per), cy * per + b / per % per, cz * per + b % per);
        for (size_t i = 0; i < own[b]->vertices.size(); ++i)
            slotOf(own[b]->vertices[i].key) = kSource | uint32_t(b) << 16 | uint32_t(i);
    }
    for (const BlockMesh* b : own)
        for (const auto& t : b->triangles)
            for (uint64_t k : t) {
                uint32_t& s = slotOf(k);
                if (s == kUnset || (s & kSource)) {
                    const EdgeVertex& v =
                        s == kUnset ? findVertex(k) : own[(s >> 16) & 0x7fff]->vertices[s & 0xffff];
                    s = uint32_t(m.positions.size());
                    m.positions.push_back(v.position);
                    m.normals.push_back(v.normal);
                }
                m.indices.push_back(s);
            }
    return m;
}

}  // namespace vsculpt::core
