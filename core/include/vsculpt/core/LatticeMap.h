#pragma once
/// @file
/// @brief A sparse map from lattice vertices to values, stored in dense 8^3 bricks.
///
/// Placement looks up every target within a few lattice spacings of each re-fitted target;
/// in a node-based hash map each lookup walked a chain of separately allocated nodes (42 % of
/// a stroke's placement time on a lattice one level below the tool's: docs/benchmarks.md).
/// Here a lookup is an index into the vertex's brick; the brick itself comes from a small
/// direct-mapped cache of the bricks looked up recently (present or absent), keyed by the low
/// bits of the brick coordinates, so a neighbourhood of up to 4^3 bricks is hashed once. Values
/// are never moved: references stay valid until the map is destroyed. Not thread-safe (the
/// cache is written even in find()).
#include "vsculpt/core/Geometry.h"

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <unordered_map>
#include <utility>

namespace vsculpt::core {

template <class T>
class LatticeMap {
  public:
    /// The value at v, or nullptr.
    T* find(const LatticeCoord& v) const {
        const Brick* b = brick(v);
        if (!b) return nullptr;
        const int32_t i = b->slots[slot(v)];
        return i < 0 ? nullptr : const_cast<T*>(&mValues[size_t(i)]);
    }
    bool contains(const LatticeCoord& v) const { return find(v) != nullptr; }
    /// The value at v, default-constructed if absent; second: whether it was inserted.
    std::pair<T*, bool> tryEmplace(const LatticeCoord& v) {
        Brick* b = brick(v);
        if (!b) {
            const LatticeCoord key = brickOf(v);
            auto& owned = mBricks[key];
            owned = std::make_unique<Brick>();
            owned->slots.fill(-1);
            b = owned.get();
            mCache[cacheSlot(key)] = CacheEntry{key, b, true};  // it was cached as absent
        }
        int32_t& i = b->slots[slot(v)];
        if (i >= 0) return {&mValues[size_t(i)], false};
        i = int32_t(mValues.size());
        mValues.emplace_back();
        return {&mValues.back(), true};
    }
    size_t size() const { return mValues.size(); }

  private:
    static constexpr int kShift = 3;  // 8^3 vertices a brick
    static constexpr int32_t kMask = (1 << kShift) - 1;
    struct Brick {
        std::array<int32_t, 1 << (3 * kShift)> slots;  // index into mValues, -1: empty
    };
    static LatticeCoord brickOf(const LatticeCoord& v) {
        return {v.x >> kShift, v.y >> kShift, v.z >> kShift};  // floor for negatives too
    }
    static size_t slot(const LatticeCoord& v) {
        return size_t((((v.x & kMask) << kShift | (v.y & kMask)) << kShift) | (v.z & kMask));
    }
    struct CacheEntry {
        LatticeCoord key;
        Brick* brick = nullptr;  // nullptr: no brick there
        bool valid = false;
    };
    static constexpr int kCacheBits = 2;  // per axis: 4^3 entries
    static size_t cacheSlot(const LatticeCoord& key) {
        constexpr int32_t m = (1 << kCacheBits) - 1;
        return size_t((((key.x & m) << kCacheBits | (key.y & m)) << kCacheBits) | (key.z & m));
    }
    Brick* brick(const LatticeCoord& v) const {
        const LatticeCoord key = brickOf(v);
        CacheEntry& e = mCache[cacheSlot(key)];
        if (e.valid && e.key == key) return e.brick;
        const auto it = mBricks.find(key);
        e = CacheEntry{key, it == mBricks.end() ? nullptr : it->second.get(), true};
        return e.brick;
    }

    std::unordered_map<LatticeCoord, std::unique_ptr<Brick>, LatticeCoordHash> mBricks;
    std::deque<T> mValues;
    mutable std::array<CacheEntry, size_t(1) << (3 * kCacheBits)> mCache{};
};

}  // namespace vsculpt::core
