// SPDX-License-Identifier: MIT
/// @file Sculpture.h
/// @brief The sculpture: configuration, tool levels, skeleton lattices and the initial shape.
///
/// All positions are in object space (mm). The object's pose in the world is kept here so
/// callers can apply world-space tool samples (see PlaceStroke.h).
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Geometry.h"
#include "vsculpt/core/SkeletonStore.h"
#include "vsculpt/core/ToolLevels.h"

#include <array>
#include <memory>
#include <vector>

namespace vsculpt::core {

/// A point skeleton with its own support radius, outside the lattices: the initial sphere
/// (and, later, sketched solids). Contributes weight * F(|P - center| / supportMm).
struct PointSkeleton {
    Vec3 centerMm{0.0};
    double supportMm = 0;
    double weight = 1;
};

struct SkeletonCounts {
    /// Point skeletons per level, index 0 = level 1. A thesis add+sub pair counts as two.
    std::array<size_t, kLevelCount> byLevel{};
    size_t additive = 0, subtractive = 0;
    size_t lattice = 0;  ///< sum of byLevel
    size_t point = 0;    ///< PointSkeletons (initial sphere)
    size_t total() const { return lattice + point; }
};

class Sculpture {
  public:
    /// Builds tool levels (calibrating once per distinct parameter set in this process) and the
    /// initial sphere. @pre validateConfig(cfg) passed (throws ConfigError otherwise).
    explicit Sculpture(const SculptConfig& cfg);

    /// A deep copy (skeletons and point skeletons; the tool levels are shared, immutable):
    /// what a mesher thread reads while this one is being edited (AsyncMesher.h).
    std::unique_ptr<Sculpture> clone() const;

    const SculptConfig& config() const { return mConfig; }
    const ToolLevels& levels() const { return *mLevels; }
    const std::shared_ptr<const ToolLevels>& sharedLevels() const { return mLevels; }

    SkeletonStore& store() { return mStore; }
    const SkeletonStore& store() const { return mStore; }

    const std::vector<PointSkeleton>& pointSkeletons() const { return mPoints; }
    void addPointSkeleton(const PointSkeleton& s);

    /// The object's pose; edits given in world space are mapped through its inverse.
    RigidTransform worldFromObject;

    SkeletonCounts counts() const;
    /// Bounds of the supports of the skeletons with positive weight: the surface lies inside,
    /// as negative weights only lower the field (f <= -c outside). Empty when there is none.
    Aabb supportBounds() const;

  private:
    Sculpture() = default;
    SculptConfig mConfig;
    std::shared_ptr<const ToolLevels> mLevels;
    SkeletonStore mStore;
    std::vector<PointSkeleton> mPoints;
};

/// The shared, cached tool-level table for a config (calibration runs once per parameter set).
std::shared_ptr<const ToolLevels> toolLevelsFor(const SculptConfig& cfg);

}  // namespace vsculpt::core
