// SPDX-License-Identifier: MIT
#include "vsculpt/core/SkeletonStore.h"

#include "SkeletonStoreImpl.h"

#include <stdexcept>

namespace vsculpt::core {

namespace {
int checkedIndex(int level) {
    if (level < 1 || level > kLevelCount)
        throw std::out_of_range("skeleton level " + std::to_string(level) + " outside 1..7");
    return level - 1;
}
}  // namespace

SkeletonStore::SkeletonStore() : mImpl(std::make_unique<Impl>()) {}
SkeletonStore::~SkeletonStore() = default;
SkeletonStore::SkeletonStore(SkeletonStore&&) noexcept = default;
SkeletonStore& SkeletonStore::operator=(SkeletonStore&&) noexcept = default;

SkeletonStore SkeletonStore::clone() const {
    SkeletonStore copy;
    copy.mImpl = std::make_unique<Impl>(*mImpl);  // Tree's copy constructor copies deeply
    return copy;
}

std::optional<float> SkeletonStore::get(int level, const LatticeCoord& c) const {
    const SkeletonTree& t = mImpl->trees[checkedIndex(level)];
    float v = 0;
    if (t.probeValue(toVdb(c), v)) return v;
    return std::nullopt;
}

void SkeletonStore::set(int level, const LatticeCoord& c, float weight) {
    const int i = checkedIndex(level);
    SkeletonTree& t = mImpl->trees[i];
    const openvdb::Coord xyz = toVdb(c);
    if (!t.isValueOn(xyz)) {
        ++mImpl->counts[i];
        mImpl->bounds[i].expand(xyz);
    }
    t.setValueOn(xyz, weight);
}

void SkeletonStore::erase(int level, const LatticeCoord& c) {
    const int i = checkedIndex(level);
    SkeletonTree& t = mImpl->trees[i];
    const openvdb::Coord xyz = toVdb(c);
    if (!t.isValueOn(xyz)) return;
    --mImpl->counts[i];
    t.setValueOff(xyz, 0.0f);
}

size_t SkeletonStore::vertexCount(int level) const { return mImpl->counts[checkedIndex(level)]; }

size_t SkeletonStore::vertexCount() const {
    size_t n = 0;
    for (size_t c : mImpl->counts) n += c;
    return n;
}

size_t SkeletonStore::memoryBytes() const {
    size_t bytes = sizeof(Impl);
    for (const auto& t : mImpl->trees) bytes += t.memUsage();
    return bytes;
}

void SkeletonStore::forEach(const std::function<void(const SkeletonEntry&)>& fn) const {
    for (int i = 0; i < kLevelCount; ++i) {
        for (auto it = mImpl->trees[i].cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            fn(SkeletonEntry{i + 1, LatticeCoord{c.x(), c.y(), c.z()}, *it});
        }
    }
}

}  // namespace vsculpt::core
