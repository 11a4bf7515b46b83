// SPDX-License-Identifier: MIT
#include "vsculpt/core/History.h"

#include "vsculpt/core/Sculpture.h"

namespace vsculpt::core {

void History::push(StrokeRecord record) {
    mDone.push_back(std::make_shared<const StrokeRecord>(std::move(record)));
    mUndone.clear();
}

Aabb History::undo(Sculpture& sculpture) {
    if (mDone.empty()) return {};
    std::shared_ptr<const StrokeRecord> r = std::move(mDone.back());
    mDone.pop_back();
    const Aabb box = revertChanges(sculpture, r->changes);
    mUndone.push_back(std::move(r));
    return box;
}

Aabb History::redo(Sculpture& sculpture) {
    if (mUndone.empty()) return {};
    std::shared_ptr<const StrokeRecord> r = std::move(mUndone.back());
    mUndone.pop_back();
    const Aabb box = reapplyChanges(sculpture, r->changes);
    mDone.push_back(std::move(r));
    return box;
}

void History::restore(std::vector<StrokeRecord> done, std::vector<StrokeRecord> undone) {
    mDone.clear();
    mUndone.clear();
    mDone.reserve(done.size());
    mUndone.reserve(undone.size());
    for (StrokeRecord& r : done)
        mDone.push_back(std::make_shared<const StrokeRecord>(std::move(r)));
    for (StrokeRecord& r : undone)
        mUndone.push_back(std::make_shared<const StrokeRecord>(std::move(r)));
}

size_t History::memoryBytes() const {
    size_t bytes = 0;
    for (const auto* stack : {&mDone, &mUndone})
        for (const std::shared_ptr<const StrokeRecord>& r : *stack)
            bytes += sizeof *r + sizeof r + r->samples.capacity() * sizeof(Vec3) +
                     r->changes.capacity() * sizeof(SkeletonChange);
    return bytes;
}

}  // namespace vsculpt::core
