// SPDX-License-Identifier: MIT
/// @file SkeletonStoreImpl.h
/// @brief Private: the OpenVDB trees behind SkeletonStore, shared with field evaluation.
#pragma once

#include "vsculpt/core/SkeletonStore.h"

#include <openvdb/openvdb.h>

#include <array>

namespace vsculpt::core {

/// 4^3 leaves (one 64-bit activity mask each), 8^3 and 16^3 internal nodes. Small nodes keep
/// thin strokes of fine tools cheap; see docs/benchmarks.md for the bytes-per-skeleton figures.
using SkeletonTree = openvdb::tree::Tree4<float, 4, 3, 2>::Type;
using SkeletonLeaf = SkeletonTree::LeafNodeType;
static_assert(SkeletonLeaf::DIM == 4 && SkeletonLeaf::NUM_VALUES == 64);

struct SkeletonStore::Impl {
    std::array<SkeletonTree, kLevelCount> trees;
    std::array<size_t, kLevelCount> counts{};
    /// Index bounds of occupied vertices per level (grown on insert, never shrunk): lets field
    /// evaluation skip a level whose skeletons are all far from the query.
    std::array<openvdb::CoordBBox, kLevelCount> bounds;
};

inline openvdb::Coord toVdb(const LatticeCoord& c) { return openvdb::Coord(c.x, c.y, c.z); }

}  // namespace vsculpt::core
