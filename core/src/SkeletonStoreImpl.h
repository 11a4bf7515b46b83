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
#include <utility>
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

inline int brickBit(int x, int y, int z) {
    return (x & 3) * 16 + (y & 3) * 4 + (z & 3);
}

inline uint64_t brickKey(int32_t bx, int32_t by, int32_t bz) {
    constexpr uint64_t m = (1u << 21) - 1;
    return (uint64_t(bx) & m) | ((uint64_t(by) & m) << 21) | ((uint64_t(bz) & m) << 42);
}

/// Open-addressing hash from brick key to brick position: one cache line per lookup, which
/// matters because field evaluation looks bricks up for every query point.
class BrickIndex {
  public:
    static constexpr uint64_t kEmpty = ~uint64_t(0);  // brick keys use 63 bits: never this

    int64_t find(uint64_t key) const {
        if (mSlots.empty()) return -1;
        for (size_t i = home(key);; i = (i + 1) & mMask) {
            const Slot& s = mSlots[i];
            if (s.key == key) return s.value;
            if (s.key == kEmpty) return -1;
        }
    }
    /// Inserts key -> value unless present; returns the stored value and whether it inserted.
    std::pair<uint32_t, bool> tryEmplace(uint64_t key, uint32_t value) {
        if ((mSize + 1) * 2 > mSlots.size()) grow();
        for (size_t i = home(key);; i = (i + 1) & mMask) {
            Slot& s = mSlots[i];
            if (s.key == key) return {s.value, false};
            if (s.key == kEmpty) {
                s = Slot{key, value};
                ++mSize;
                return {value, true};
            }
        }
    }
    size_t size() const { return mSize; }
    size_t bytes() const { return mSlots.capacity() * sizeof(Slot); }

  private:
    struct Slot {
        uint64_t key = kEmpty;
        uint32_t value = 0;
    };
    size_t home(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> mShift); }
    void grow() {
        std::vector<Slot> old = std::move(mSlots);
        const size_t cap = old.empty() ? 64 : old.size() * 2;
        mSlots.assign(cap, Slot{});
        mMask = cap - 1;
        mShift = 64 - std::countr_zero(cap);
        mSize = 0;
        for (const Slot& s : old)
            if (s.key != kEmpty) tryEmplace(s.key, s.value);
    }
    std::vector<Slot> mSlots;
    size_t mMask = 0, mSize = 0;
    int mShift = 64;
};

struct LevelBricks {
    BrickIndex index;           ///< brick key -> position in `bricks`
    std::vector<Brick> bricks;  ///< never reordered: positions are stable
    std::vector<float> pool;
    size_t wasted = 0;  ///< pool entries no brick owns any more (reclaimed by compaction)
    size_t count = 0;   ///< occupied vertices
    /// Occupied index bounds (grown on insert, never shrunk); empty when min > max.
    std::array<int32_t, 3> min{INT32_MAX, INT32_MAX, INT32_MAX};
    std::array<int32_t, 3> max{INT32_MIN, INT32_MIN, INT32_MIN};

    /// Position of the brick holding lattice brick (bx, by, bz), or -1.
    int64_t find(int32_t bx, int32_t by, int32_t bz) const {
        return index.find(brickKey(bx, by, bz));
    }
};

struct SkeletonStore::Impl {
    std::array<LevelBricks, kLevelCount> levels;
    /// Bumped whenever a brick is created, so readers can cache "no brick here" safely.
    uint64_t generation = 0;
    uint64_t writes = 0;  // set() and erase() calls (SkeletonStore::writeCount)
};

}  // namespace vsculpt::core
