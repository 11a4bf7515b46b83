// SPDX-License-Identifier: MIT
/// @file History.h
/// @brief Unlimited undo/redo, one step per stroke. Each step keeps only the lattice vertices
/// its stroke changed (before and after), so memory follows what was edited, not the size
/// of the sculpture.
#pragma once

#include "vsculpt/core/PlaceStroke.h"

#include <vector>

namespace vsculpt::core {

class Sculpture;

/// One stroke: what the user did (replayable) and what it changed (undoable).
struct StrokeRecord {
    ToolOp op = ToolOp::Add;
    MirrorAxis mirror = MirrorAxis::None;  ///< the stroke was also applied mirrored
    int level = 4;
    std::vector<Vec3> samples;  ///< object-space tool centres, mm (empty for a solid)
    std::vector<SkeletonChange> changes;
    /// A sketched solid (PlaceSolid.h) rather than a tool stroke: replayed from `changes`
    /// (their after-states), since the solid's mesh is not kept.
    bool solid = false;
};

class History {
  public:
    /// Records a finished stroke; clears the redo steps.
    void push(StrokeRecord record);
    bool canUndo() const { return !mDone.empty(); }
    bool canRedo() const { return !mUndone.empty(); }
    /// Reverts the last stroke on `sculpture`; returns the object-space region whose field
    /// changed (empty when there was nothing to undo).
    Aabb undo(Sculpture& sculpture);
    Aabb redo(Sculpture& sculpture);

    const std::vector<StrokeRecord>& done() const { return mDone; }
    const std::vector<StrokeRecord>& undone() const { return mUndone; }  ///< last = next redo
    /// Restores stacks read from a project snapshot.
    void restore(std::vector<StrokeRecord> done, std::vector<StrokeRecord> undone);
    size_t memoryBytes() const;

  private:
    std::vector<StrokeRecord> mDone, mUndone;
};

}  // namespace vsculpt::core
