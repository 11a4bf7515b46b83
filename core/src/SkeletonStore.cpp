// SPDX-License-Identifier: MIT
#include "vsculpt/core/SkeletonStore.h"

#include "SkeletonStoreImpl.h"

#include <algorithm>
#include <stdexcept>

namespace vsculpt::core {

namespace {

int checkedIndex(int level) {
    if (level < 1 || level > kLevelCount)
        throw std::out_of_range("skeleton level " + std::to_string(level) + " outside 1..7");
    return level - 1;
}

void checkRange(const LatticeCoord& c) {
    if (std::abs(c.x) > kMaxLatticeCoord || std::abs(c.y) > kMaxLatticeCoord ||
        std::abs(c.z) > kMaxLatticeCoord)
        throw std::out_of_range("lattice coordinate outside +-2^22");
}

int32_t brickOf(int32_t v) {
    return v >> 2;
}  // arithmetic shift: floor division by 4

uint32_t roundCapacity(uint32_t n) {
    return std::max<uint32_t>(4, std::bit_ceil(n));
}

/// Rewrites the pool with every brick's weights packed, dropping the holes growth left.
void compactLevel(LevelBricks& L) {
    std::vector<float> pool;
    pool.reserve(L.pool.size() - L.wasted);
    for (Brick& b : L.bricks) {
        const uint32_t n = uint32_t(std::popcount(b.mask));
        const uint32_t cap = n == 0 ? 0 : roundCapacity(n);
        const uint32_t offset = uint32_t(pool.size());
        pool.insert(pool.end(), L.pool.begin() + b.offset, L.pool.begin() + b.offset + n);
        pool.resize(offset + cap, 0.0f);
        b.offset = offset;
        b.capacity = cap;
    }
    L.pool = std::move(pool);
    L.wasted = 0;
}

}  // namespace

SkeletonStore::SkeletonStore() : mImpl(std::make_unique<Impl>()) {}
SkeletonStore::~SkeletonStore() = default;
SkeletonStore::SkeletonStore(SkeletonStore&&) noexcept = default;
SkeletonStore& SkeletonStore::operator=(SkeletonStore&&) noexcept = default;

uint64_t SkeletonStore::writeCount() const {
    return mImpl->writes;
}

SkeletonStore SkeletonStore::clone() const {
    SkeletonStore copy;
    *copy.mImpl = *mImpl;
    return copy;
}

void SkeletonStore::apply(std::span<const SkeletonWrite> writes) {
    for (const SkeletonWrite& w : writes) {
        if (w.weight)
            set(w.level, w.coord, *w.weight);
        else
            erase(w.level, w.coord);
    }
}

std::optional<float> SkeletonStore::get(int level, const LatticeCoord& c) const {
    const LevelBricks& L = mImpl->levels[checkedIndex(level)];
    const int64_t slot = L.find(brickOf(c.x), brickOf(c.y), brickOf(c.z));
    if (slot < 0) return std::nullopt;
    const Brick& b = L.bricks[size_t(slot)];
    const int bit = brickBit(c.x, c.y, c.z);
    if (!(b.mask >> bit & 1)) return std::nullopt;
    const int rank = std::popcount(b.mask & ((uint64_t(1) << bit) - 1));
    return L.pool[b.offset + rank];
}

void SkeletonStore::set(int level, const LatticeCoord& c, float weight) {
    checkRange(c);
    LevelBricks& L = mImpl->levels[checkedIndex(level)];
    ++mImpl->writes;
    if (mWriteLog) mWriteLog->push_back(SkeletonWrite{level, c, weight, get(level, c)});
    const int32_t bx = brickOf(c.x), by = brickOf(c.y), bz = brickOf(c.z);
    const auto [slot, created] =
        L.index.tryEmplace(brickKey(bx, by, bz), uint32_t(L.bricks.size()));
    if (created) {
        L.bricks.push_back(Brick{bx * kBrickDim, by * kBrickDim, bz * kBrickDim, 0, 0, 0});
        ++mImpl->generation;
    }
    Brick& b = L.bricks[slot];
    const int bit = brickBit(c.x, c.y, c.z);
    const int rank = std::popcount(b.mask & ((uint64_t(1) << bit) - 1));
    if (b.mask >> bit & 1) {
        L.pool[b.offset + rank] = weight;
        return;
    }
    const uint32_t n = uint32_t(std::popcount(b.mask));
    if (n + 1 > b.capacity) {  // move the brick's weights to a larger segment at the end
        const uint32_t cap = roundCapacity(n + 1);
        const uint32_t offset = uint32_t(L.pool.size());
        L.pool.resize(L.pool.size() + cap, 0.0f);
        std::copy_n(L.pool.begin() + b.offset, n, L.pool.begin() + offset);
        L.wasted += b.capacity;
        b.offset = offset;
        b.capacity = cap;
    }
    float* v = L.pool.data() + b.offset;
    std::copy_backward(v + rank, v + n, v + n + 1);
    v[rank] = weight;
    b.mask |= uint64_t(1) << bit;
    ++L.count;
    L.min = {std::min(L.min[0], c.x), std::min(L.min[1], c.y), std::min(L.min[2], c.z)};
    L.max = {std::max(L.max[0], c.x), std::max(L.max[1], c.y), std::max(L.max[2], c.z)};
    if (L.wasted > 4096 && L.wasted * 3 > L.pool.size()) compactLevel(L);
}

void SkeletonStore::erase(int level, const LatticeCoord& c) {
    LevelBricks& L = mImpl->levels[checkedIndex(level)];
    ++mImpl->writes;
    if (mWriteLog) mWriteLog->push_back(SkeletonWrite{level, c, std::nullopt, get(level, c)});
    const int64_t slot = L.find(brickOf(c.x), brickOf(c.y), brickOf(c.z));
    if (slot < 0) return;
    Brick& b = L.bricks[size_t(slot)];
    const int bit = brickBit(c.x, c.y, c.z);
    if (!(b.mask >> bit & 1)) return;
    const int rank = std::popcount(b.mask & ((uint64_t(1) << bit) - 1));
    const int n = std::popcount(b.mask);
    float* v = L.pool.data() + b.offset;
    std::copy(v + rank + 1, v + n, v + rank);
    b.mask &= ~(uint64_t(1) << bit);
    --L.count;
}

void SkeletonStore::compact() {
    for (LevelBricks& L : mImpl->levels)
        compactLevel(L);
}

size_t SkeletonStore::vertexCount(int level) const {
    return mImpl->levels[checkedIndex(level)].count;
}

size_t SkeletonStore::vertexCount() const {
    size_t n = 0;
    for (const LevelBricks& L : mImpl->levels)
        n += L.count;
    return n;
}

namespace {
size_t levelBytes(const LevelBricks& L) {
    return L.bricks.capacity() * sizeof(Brick) + L.pool.capacity() * sizeof(float) +
           L.index.bytes();
}
}  // namespace

size_t SkeletonStore::memoryBytes() const {
    size_t bytes = sizeof(Impl);
    for (const LevelBricks& L : mImpl->levels)
        bytes += levelBytes(L);
    return bytes;
}

SkeletonStore::LevelStats SkeletonStore::stats(int level) const {
    const LevelBricks& L = mImpl->levels[checkedIndex(level)];
    return LevelStats{L.count, L.bricks.size(), levelBytes(L)};
}

void SkeletonStore::forEach(const std::function<void(const SkeletonEntry&)>& fn) const {
    for (int i = 0; i < kLevelCount; ++i) {
        const LevelBricks& L = mImpl->levels[i];
        for (const Brick& b : L.bricks) {
            uint64_t bits = b.mask;
            for (int r = 0; bits; ++r) {
                const int n = std::countr_zero(bits);
                bits &= bits - 1;
                fn(SkeletonEntry{
                    i + 1, LatticeCoord{b.ox + (n >> 4), b.oy + ((n >> 2) & 3), b.oz + (n & 3)},
                    L.pool[b.offset + r]});
            }
        }
    }
}

}  // namespace vsculpt::core
