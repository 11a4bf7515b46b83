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

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Geometry.h"

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace vsculpt::core {

class Sculpture;
class FieldProbe;

/// Add: union with the swept tool. Carve: subtract it. Smooth: relax the surface under the
/// tool toward its local average (free placement mode only; docs/placement.md).
enum class ToolOp { Add, Carve, Smooth };
const char* toString(ToolOp op);

/// Mirror symmetry: every stroke is also applied mirrored across the object-space plane
/// through the origin normal to this axis (x = 0, y = 0 or z = 0). The lattices are symmetric
/// about these planes, so the mirrored half lands on mirrored vertices and the field stays
/// mirror-equal.
enum class MirrorAxis { None, X, Y, Z };
const char* toString(MirrorAxis axis);
/// `p` mirrored across the axis's plane (unchanged for None).
Vec3 mirrored(const Vec3& p, MirrorAxis axis);

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
    /// @param mirror also apply every swept segment mirrored across that plane, as part of
    ///        the same stroke (one undo step; decisions from the same pre-stroke field).
    /// Smooth in thesis placement mode is refused (std::invalid_argument): its skeletons are
    /// unit weights, there is nothing to relax.
    StrokeBuilder(Sculpture& sculpture, ToolOp op, int level, MirrorAxis mirror = MirrorAxis::None);
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
    EditResult addSmoothSample(const Vec3& a, const Vec3& p);

    Sculpture& mSculpture;
    ToolOp mOp;
    int mLevel;
    MirrorAxis mMirror;
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
    // Smooth: per level (1..7), each visited vertex's closest approach and the pre-stroke
    // state of every vertex the stroke changed.
    std::array<std::unordered_map<LatticeCoord, double, LatticeCoordHash>, kLevelCount>
        mSmoothVisited;
    std::array<std::unordered_map<LatticeCoord, std::optional<float>, LatticeCoordHash>,
               kLevelCount>
        mSmoothPre;
};

/// Applies a whole stroke (object-space path). Returns the union of the changed regions and
/// appends the vertex changes to `changes` when given.
EditResult applyStroke(Sculpture& sculpture, ToolOp op, int level, std::span<const Vec3> path,
                       std::vector<SkeletonChange>* changes = nullptr,
                       MirrorAxis mirror = MirrorAxis::None);

/// Restores the `before` state of each change, last first (undo). Returns the changed region.
Aabb revertChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes);
/// Re-applies the `after` state of each change, first first (redo).
Aabb reapplyChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes);

}  // namespace vsculpt::core
