// SPDX-License-Identifier: MIT
/// @file SculptAction.h
/// @brief The sculpting actions every input names the same way (key bindings, the window's
/// palette, the headset's panel): "tool_add" / "tool_carve" / "tool_smooth" / "tool_select",
/// "cycle_tool", "mirror_off" / "mirror_x" / "mirror_y" / "mirror_z", "cycle_mirror",
/// "size_N", "zoom_N", "overview", "undo", "redo". One place applies them, so a button in the
/// headset does exactly what the same button in the window does.
#pragma once

#include "vsculpt/core/Geometry.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/Studio.h"

#include <string>

namespace vsculpt::app {

/// Applies `action` to the studio through the interaction. `zoomAt` (object space, mm) is
/// where "zoom_N" centres the region. Returns false when `action` is none of the names
/// above (nothing is done). A refused command (nothing to undo, a size the zoom does not
/// offer) throws what the studio throws; a broken invariant std::logic_error.
bool applySculptAction(const std::string& action, studio::Studio& studio,
                       studio::Interaction& interaction, const core::Vec3& zoomAt);

/// Whether applySculptAction knows `action` (recordings check the names they read).
bool isSculptAction(const std::string& action);

}  // namespace vsculpt::app
