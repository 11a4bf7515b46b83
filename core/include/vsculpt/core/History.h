// SPDX-License-Identifier: MIT
/// @file History.h
/// @brief Unlimited undo/redo, one step per stroke. Each step keeps only the lattice vertices
/// its stroke changed (before and after), so memory follows what was edited, not the size
/// of the sculpture.
#pragma once

#include "vsculpt/core/PlaceStroke.h"

#include <cstddef>
#include <iterator>
#include <memory>
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

/// One stack of a History (done or undone, oldest first), read-only: a view that stays
/// valid while the History lives and its stacks are not changed.
class HistorySteps {
  public:
    using Stack = std::vector<std::shared_ptr<const StrokeRecord>>;
    class iterator {
      public:
        using iterator_category = std::forward_iterator_tag;
        using value_type = StrokeRecord;
        using difference_type = std::ptrdiff_t;
        using pointer = const StrokeRecord*;
        using reference = const StrokeRecord&;
        iterator() = default;
        explicit iterator(Stack::const_iterator it) : mIt(it) {}
        reference operator*() const { return **mIt; }
        pointer operator->() const { return mIt->get(); }
        iterator& operator++() {
            ++mIt;
            return *this;
        }
        iterator operator++(int) { return iterator(mIt++); }
        friend bool operator==(const iterator&, const iterator&) = default;

      private:
        Stack::const_iterator mIt;
    };
    explicit HistorySteps(const Stack& stack) : mStack(&stack) {}
    size_t size() const { return mStack->size(); }
    bool empty() const { return mStack->empty(); }
    const StrokeRecord& operator[](size_t i) const { return *(*mStack)[i]; }
    const StrokeRecord& back() const { return *mStack->back(); }
    iterator begin() const { return iterator(mStack->begin()); }
    iterator end() const { return iterator(mStack->end()); }

  private:
    const Stack* mStack;
};

/// Records are immutable once pushed and shared between copies, so copying a History (a
/// background save's snapshot of it) costs a pointer per step, not the steps' changes.
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

    HistorySteps done() const { return HistorySteps(mDone); }
    HistorySteps undone() const { return HistorySteps(mUndone); }  ///< last = next redo
    /// Restores stacks read from a project snapshot.
    void restore(std::vector<StrokeRecord> done, std::vector<StrokeRecord> undone);
    /// Bytes of the records this history holds (copies share them; each counts them).
    size_t memoryBytes() const;

  private:
    HistorySteps::Stack mDone, mUndone;
};

}  // namespace vsculpt::core
