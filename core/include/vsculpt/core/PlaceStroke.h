// SPDX-License-Identifier: MIT
/// @file PlaceStroke.h
/// @brief Turns a tool path into skeletons on the tool level's lattice (thesis §3.1.2), under
/// the sculpture's placement mode (docs/placement.md).
///
/// A stroke is the sequence of tool-centre samples between pressing and releasing the tool.
/// Every lattice vertex inside the tool sphere swept between consecutive samples is visited
/// once per stroke, so fast strokes leave no gaps. Decisions that depend on the field use the
/// field as it was before the stroke began, so the result does not depend on sample spacing.
#pragma once

#include "vsculpt/core/Geometry.h"

#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace vsculpt::core {

class Sculpture;
class FieldProbe;

enum class ToolOp { Add, Carve };
const char* toString(ToolOp op);

/// One vertex's state before and after an edit (nullopt = empty): enough to undo or redo it.
struct SkeletonChange {
    int level = 0;
    LatticeCoord coord;
    std::optional<float> before, after;
};

struct EditResult {
    /// Object-space box outside which f did not change (changed vertices padded by R_k).
    Aabb changedRegion;
    int changedVertices = 0;
    /// Tighter: f changed only within supportMm of these lattice vertices (object space).
    std::vector<Vec3> changedPoints;
    double supportMm = 0;
};

/// An in-progress stroke on one sculpture. Edits the sculpture as samples arrive.
class StrokeBuilder {
  public:
    /// @param level tool level 1..7 (checked: std::invalid_argument)
    StrokeBuilder(Sculpture& sculpture, ToolOp op, int level);
    ~StrokeBuilder();

    /// Adds a tool-centre sample in object space (mm) and applies the swept segment from the
    /// previous sample. Throws std::invalid_argument for a non-finite or out-of-range point.
    EditResult addSample(const Vec3& objectPos);
    /// Same for a world-space sample: objectPos = inverse(worldFromObject) * worldPos.
    EditResult addSampleWorld(const Vec3& worldPos, const RigidTransform& worldFromObject);

    /// Every vertex change so far, in the order applied.
    const std::vector<SkeletonChange>& changes() const { return mChanges; }
    std::vector<SkeletonChange> takeChanges() { return std::move(mChanges); }

  private:
    double preStrokeRawSum(const LatticeCoord& v, const Vec3& pos);

    Sculpture& mSculpture;
    ToolOp mOp;
    int mLevel;
    std::optional<Vec3> mLast;
    struct Visit {
        std::optional<float> preStroke;  // the vertex's state before this stroke
        double lateral;                  // closest approach of the stroke so far, mm
    };
    // A vertex is decided again only when the path comes closer to it (free mode weights
    // depend on that distance); decisions always start from the pre-stroke state.
    std::unordered_map<LatticeCoord, Visit, LatticeCoordHash> mVisited;
    std::unordered_map<LatticeCoord, float, LatticeCoordHash> mDeltas;  // weight change per vertex
    std::vector<LatticeCoord> mStencil;  // lattice offsets within the level's support radius
    std::vector<SkeletonChange> mChanges;
    std::unique_ptr<FieldProbe> mProbe;
};

/// Applies a whole stroke (object-space path). Returns the union of the changed regions and
/// appends the vertex changes to `changes` when given.
EditResult applyStroke(Sculpture& sculpture, ToolOp op, int level, std::span<const Vec3> path,
                       std::vector<SkeletonChange>* changes = nullptr);

/// Restores the `before` state of each change, last first (undo). Returns the changed region.
Aabb revertChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes);
/// Re-applies the `after` state of each change, first first (redo).
Aabb reapplyChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes);

}  // namespace vsculpt::core
