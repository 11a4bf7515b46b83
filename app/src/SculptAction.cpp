// SPDX-License-Identifier: MIT
#include "vsculpt/app/SculptAction.h"

#include "vsculpt/core/Config.h"

namespace vsculpt::app {

namespace {

/// The digit of "size_N" / "zoom_N" within [lo, hi], or 0.
int digitAfter(const std::string& action, const char* prefix, int lo, int hi) {
    const std::string p(prefix);
    if (action.size() != p.size() + 1 || action.compare(0, p.size(), p) != 0) return 0;
    const int d = action.back() - '0';
    return d >= lo && d <= hi ? d : 0;
}

}  // namespace

bool isSculptAction(const std::string& a) {
    return a == "tool_add" || a == "tool_carve" || a == "tool_smooth" || a == "tool_select" ||
           a == "cycle_tool" || a == "mirror_off" || a == "mirror_x" || a == "mirror_y" ||
           a == "mirror_z" || a == "cycle_mirror" || a == "overview" || a == "undo" ||
           a == "redo" || digitAfter(a, "size_", 1, core::kLevelCount) != 0 ||
           digitAfter(a, "zoom_", 1, core::kZoomLevels) != 0;
}

bool applySculptAction(const std::string& a, studio::Studio& studio,
                       studio::Interaction& interaction, const core::Vec3& zoomAt) {
    using studio::ToolKind;
    if (!isSculptAction(a)) return false;
    if (a.rfind("tool_", 0) == 0)
        studio.setTool(a == "tool_add"      ? ToolKind::Add
                       : a == "tool_carve"  ? ToolKind::Carve
                       : a == "tool_smooth" ? ToolKind::Smooth
                                            : ToolKind::Select);
    else if (a == "cycle_tool")
        interaction.cycleTool();
    else if (a == "cycle_mirror")
        interaction.cycleMirror();
    else if (a.rfind("mirror_", 0) == 0)
        studio.setMirror(a == "mirror_x"   ? core::MirrorAxis::X
                         : a == "mirror_y" ? core::MirrorAxis::Y
                         : a == "mirror_z" ? core::MirrorAxis::Z
                                           : core::MirrorAxis::None);
    else if (const int level = digitAfter(a, "size_", 1, core::kLevelCount))
        interaction.jumpToSize(level);
    else if (const int zoom = digitAfter(a, "zoom_", 1, core::kZoomLevels))
        interaction.jumpToZoom(zoom, zoomAt);
    else if (a == "overview")
        interaction.overview();
    else if (a == "undo")
        studio.undo();
    else
        studio.redo();
    return true;
}

}  // namespace vsculpt::app
