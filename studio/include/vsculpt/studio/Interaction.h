// SPDX-License-Identifier: MIT
/// @file Interaction.h
/// @brief The interaction state machine: device and keyboard events -> tool state and edits
/// through a Studio (thesis Table 2, without its annoyances).
///
/// Thesis mapping (3D mouse): the right button cycles the tool add -> carve -> select; the
/// left button steps the size one offered level per press, or with the select tool zooms one
/// level into the region under the tool. Beyond the thesis, direct jumps to any offered size
/// or zoom level and a way back to the overview, so nothing needs repeated presses. Add and
/// carve happen while the tool is engaged and moving: in the thesis the tool is always
/// engaged; a desktop binds engagement to a button.
#pragma once

#include "vsculpt/studio/Studio.h"

#include <vector>

namespace vsculpt::studio {

class Interaction {
  public:
    /// @param alwaysEngaged the thesis's behaviour: add/carve act whenever the tool moves
    explicit Interaction(Studio& studio, bool alwaysEngaged = false);

    /// Right button: add -> carve -> smooth -> select -> add (no smooth in thesis placement).
    void cycleTool();
    /// Mirror symmetry: off -> x -> y -> z -> off (Session::setMirror).
    void cycleMirror();
    /// Left button. Add/carve: the next smaller offered size, wrapping to the largest.
    /// Select: zoom one level into the region around `toolPos` (object space); at the
    /// deepest zoom it does nothing.
    void step(const core::Vec3& toolPos);
    /// Direct jumps. Return false (and change nothing) when the size is not offered at the
    /// current zoom or the zoom level is out of range.
    bool jumpToSize(int level);
    bool jumpToZoom(int zoom, const core::Vec3& center);
    /// Back to the whole sculpture (zoom 1).
    void overview();

    /// Engages or releases the tool (a button on desktops); releasing ends the stroke.
    void setEngaged(bool engaged);
    /// The tool's new position in world space: extends the stroke when engaged with add or
    /// carve (object space = inverse of the session's object pose).
    void moveTool(const core::Vec3& worldPos);

    /// The sizes the palette shows: exactly those offered at the current zoom.
    std::vector<int> offeredSizes() const;
    bool engaged() const { return mEngaged; }

  private:
    Studio& mStudio;
    const Session& session() const { return mStudio.session(); }
    bool mAlwaysEngaged;
    bool mEngaged;
};

}  // namespace vsculpt::studio
