// SPDX-License-Identifier: MIT
/// @file SkeletonStore.h
/// @brief The locally refined skeleton lattices: one sparse OpenVDB tree per tool level,
/// holding a weight at each lattice vertex a tool has placed a skeleton on.
///
/// A vertex is either empty (inactive) or holds a skeleton with a signed weight w: its field
/// contribution is w * F_k(|P - v|). Thesis mode uses w = +1 (additive), -1 (subtractive) and
/// 0 (an additive and a subtractive skeleton stacked, which cancel); free mode uses any w.
/// Storage is sparse: per level, a hash of the 4^3 vertex blocks a tool touched, each holding
/// only its occupied vertices' weights (docs/benchmarks.md: bytes per skeleton, and why this
/// is not an OpenVDB tree). Lattice coordinates must stay within +-2^22 (checked).
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Geometry.h"

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace vsculpt::core {

/// Lattice coordinates must stay within +-this so the storage's brick keys pack into 64 bits.
inline constexpr int32_t kMaxLatticeCoord = (1 << 22) - 1;

struct SkeletonEntry {
    int level = 0;  ///< 1..7
    LatticeCoord coord;
    float weight = 0;
};

/// One write to a store: a skeleton placed or overwritten (weight), or a vertex emptied
/// (no weight). Replaying a store's writes in order on a clone gives the same store.
/// `before` is the vertex's state the write replaced, so a reader can apply the write's
/// difference to sums it keeps (Polygonizer::noteWrites).
struct SkeletonWrite {
    int level = 0;
    LatticeCoord coord;
    std::optional<float> weight;
    std::optional<float> before;
};

class SkeletonStore {
  public:
    SkeletonStore();
    ~SkeletonStore();
    SkeletonStore(SkeletonStore&&) noexcept;
    SkeletonStore& operator=(SkeletonStore&&) noexcept;
    SkeletonStore(const SkeletonStore&) = delete;  // deep copies are explicit: clone()
    SkeletonStore& operator=(const SkeletonStore&) = delete;

    /// A deep copy.
    SkeletonStore clone() const;

    /// The weight at a vertex, or nullopt when the vertex holds no skeleton.
    std::optional<float> get(int level, const LatticeCoord& c) const;
    /// Places (or overwrites) the skeleton at a vertex.
    void set(int level, const LatticeCoord& c, float weight);
    /// Empties a vertex (no-op when already empty).
    void erase(int level, const LatticeCoord& c);

    /// From now on every set() and erase() is also appended to `*log` (nullptr: stop). The
    /// store does not own the log; a mesher drains it after each edit (AsyncMesher.h). A
    /// clone does not inherit it.
    void logWritesTo(std::vector<SkeletonWrite>* log) { mWriteLog = log; }
    /// Replays writes in order (set or erase).
    void apply(std::span<const SkeletonWrite> writes);
    /// How many set() and erase() calls this store has seen (a clone starts from its
    /// original's count): a reader that was told of every write since count c is current
    /// exactly when writeCount() is c plus the writes it was told of.
    uint64_t writeCount() const;

    /// Packs storage, returning the space growth left behind (also done automatically).
    void compact();

    /// Number of occupied vertices on one level / on all levels.
    size_t vertexCount(int level) const;
    size_t vertexCount() const;
    /// Heap bytes used by the trees (OpenVDB's own accounting).
    size_t memoryBytes() const;

    struct LevelStats {
        size_t vertices = 0, blocks = 0, bytes = 0;  ///< blocks: allocated 4^3 leaves
    };
    LevelStats stats(int level) const;

    /// Visits every occupied vertex, level by level, in the trees' order.
    void forEach(const std::function<void(const SkeletonEntry&)>& fn) const;

    struct Impl;  ///< defined in src/SkeletonStoreImpl.h; field evaluation reads it directly
    const Impl& impl() const { return *mImpl; }

  private:
    std::unique_ptr<Impl> mImpl;
    std::vector<SkeletonWrite>* mWriteLog = nullptr;
};

}  // namespace vsculpt::core
