// SPDX-License-Identifier: MIT
/// @file SkeletonStoreImpl.h
/// @brief Private: the compact brick storage behind SkeletonStore, shared with field evaluation.
///
/// Why not an OpenVDB tree: strokes are thin tubes, 2 to 3 lattice vertices across, so a
/// 4^3 block a stroke passes holds about 5 skeletons. A dense OpenVDB leaf stores all 64
/// values (plus node overhead) and measured 90-160 bytes per skeleton on sculpted shapes
/// (docs/benchmarks.md); storing only the occupied vertices of each block measured ~20.
#pragma once

#include "vsculpt/core/SkeletonStore.h"

#include <array>
#include <bit>
#include <climits>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace vsculpt::core {

/// 4x4x4 lattice vertices; bit (x*16 + y*4 + z) of `mask` marks an occupied vertex. The
/// weights of the occupied vertices are stored in bit order at pool[offset ...].
struct Brick {
    int32_t ox = 0, oy = 0, oz = 0;  ///< lattice coordinate of the brick's (0,0,0) vertex
    uint64_t mask = 0;
    uint32_t offset = 0;    ///< first weight in the level's pool
    uint32_t capacity = 0;  ///< weights reserved at offset (power of two, >= popcount(mask))
};

inline constexpr int kBrickDim = 4;
/// Lattice coordinates must stay within +-2^22 so brick keys pack into 64 bits.
inline constexpr int32_t kMaxLatticeCoord = (1 << 22) - 1;

inline int brickBit(int x, int y, int z) {
    return (x & 3) * 16 + (y & 3) * 4 + (z & 3);
}

inline uint64_t brickKey(int32_t bx, int32_t by, int32_t bz) {
    constexpr uint64_t m = (1u << 21) - 1;
    return (uint64_t(bx) & m) | ((uint64_t(by) & m) << 21) | ((uint64_t(bz) & m) << 42);
}

struct LevelBricks {
    std::unordered_map<uint64_t, uint32_t> index;  ///< brick key -> position in `bricks`
    std::vector<Brick> bricks;                     ///< never reordered: positions are stable
    std::vector<float> pool;
    size_t wasted = 0;  ///< pool entries no brick owns any more (reclaimed by compaction)
    size_t count = 0;   ///< occupied vertices
    /// Occupied index bounds (grown on insert, never shrunk); empty when min > max.
    std::array<int32_t, 3> min{INT32_MAX, INT32_MAX, INT32_MAX};
    std::array<int32_t, 3> max{INT32_MIN, INT32_MIN, INT32_MIN};

    /// Position of the brick holding lattice brick (bx, by, bz), or -1.
    int64_t find(int32_t bx, int32_t by, int32_t bz) const {
        auto it = index.find(brickKey(bx, by, bz));
        return it == index.end() ? -1 : int64_t(it->second);
    }
};

struct SkeletonStore::Impl {
    std::array<LevelBricks, kLevelCount> levels;
    /// Bumped whenever a brick is created, so readers can cache "no brick here" safely.
    uint64_t generation = 0;
};

}  // namespace vsculpt::core
