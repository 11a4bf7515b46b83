// SPDX-License-Identifier: MIT
#include "vsculpt/core/MeshChunks.h"

#include "vsculpt/core/Polygonizer.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace vsculpt::core {

size_t MeshChunks::triangleCount() const {
    size_t n = 0;
    for (const auto& m : meshes)
        if (m) n += m->triangleCount();
    return n;
}

Mesh MeshChunks::merged() const {
    Mesh out;
    for (const auto& m : meshes) {
        if (!m) continue;
        const uint32_t base = uint32_t(out.positions.size());
        out.positions.insert(out.positions.end(), m->positions.begin(), m->positions.end());
        out.normals.insert(out.normals.end(), m->normals.begin(), m->normals.end());
        for (uint32_t i : m->indices)
            out.indices.push_back(base + i);
    }
    return out;
}

namespace {

/// A chunk reads its own blocks and, for the edge vertices its triangles use, the blocks
/// beyond its far faces (Polygonizer::chunkMesh): 3 per axis from its first block.
bool readsAStaleBlock(int cx, int cy, int cz, const std::vector<std::array<int, 3>>& stale) {
    constexpr int per = Polygonizer::kChunkCells / Polygonizer::kBlockCells;
    const std::array<int, 3> lo{cx * per, cy * per, cz * per};
    // Stale blocks sorted by x, then y, z: only those with x in range are looked at.
    auto it = std::lower_bound(stale.begin(), stale.end(), std::array<int, 3>{lo[0], 0, 0});
    for (; it != stale.end() && (*it)[0] <= lo[0] + per; ++it)
        if ((*it)[1] >= lo[1] && (*it)[1] <= lo[1] + per && (*it)[2] >= lo[2] &&
            (*it)[2] <= lo[2] + per)
            return true;
    return false;
}

}  // namespace

std::shared_ptr<const MeshChunks> publishChunks(const Polygonizer& poly, const MeshChunks* previous,
                                                const std::vector<std::array<int, 3>>* stale) {
    auto out = std::make_shared<MeshChunks>();
    const int c = poly.chunksPerAxis();
    out->region = poly.region();
    out->chunksPerAxis = c;
    const size_t count = size_t(c) * c * c;
    out->versions.assign(count, 0);
    out->meshes.assign(count, nullptr);
    out->chunkBounds.assign(count, Aabb{});
    const bool reuse = previous && previous->region == poly.region();
    const bool partial = stale && !stale->empty();
    if (partial && !reuse)
        throw std::logic_error("publishChunks: a partial set needs the previous set of its region");
    std::vector<std::array<int, 3>> fresh;  // chunks to extract
    for (int x = 0; x < c; ++x)
        for (int y = 0; y < c; ++y)
            for (int z = 0; z < c; ++z) {
                const size_t i = out->index(x, y, z);
                const uint64_t v = poly.chunkVersion(x, y, z);
                if (partial && previous->versions[i] != v && readsAStaleBlock(x, y, z, *stale)) {
                    // Not extractable yet: the previous mesh stays, and so does its version,
                    // so the next set extracts this chunk.
                    out->versions[i] = previous->versions[i];
                    out->meshes[i] = previous->meshes[i];
                    out->chunkBounds[i] = previous->chunkBounds[i];
                    continue;
                }
                out->versions[i] = v;
                if (v == 0) continue;
                if (reuse && previous->versions[i] == v) {
                    out->meshes[i] = previous->meshes[i];
                    out->chunkBounds[i] = previous->chunkBounds[i];
                } else {
                    fresh.push_back({x, y, z});
                }
            }
    out->partial = partial;
    // Each chunk's mesh is built from its own blocks (read-only): in parallel, on the
    // polygonizer's workers (the mesher's pool) or in the caller's oneTBB arena.
    parallelFor(poly.workers(), fresh.size(), 1, [&](size_t k0, size_t k1) {
        for (size_t k = k0; k < k1; ++k) {
            const auto [x, y, z] = fresh[k];
            Mesh m = poly.chunkMesh(x, y, z);
            if (m.triangleCount() == 0) continue;
            const size_t i = out->index(x, y, z);
            out->chunkBounds[i] = meshBounds(m);
            out->meshes[i] = std::make_shared<const Mesh>(std::move(m));
        }
    });
    for (size_t i = 0; i < count; ++i)
        if (out->meshes[i]) out->bounds.expand(out->chunkBounds[i]);
    return out;
}

}  // namespace vsculpt::core
