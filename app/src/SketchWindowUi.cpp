// SPDX-License-Identifier: MIT
// The sketch window's panel (WindowUi.h): page, mode, stroke kind, the last stroke's role,
// solids, selection and undo, with the shared project parts. Its actions are the sketch
// bindings' names, so the window applies them exactly as it applies keys.
#include "UiWidgets.h"
#include "vsculpt/app/WindowUi.h"

#include <imgui.h>

#include <algorithm>

namespace vsculpt::app {

std::vector<UiAction> sketchUi(UiState& state, const SketchUiView& v, core::SculptConfig& cfg,
                               int width, int height) {
    using ui::button;
    ui::beginUi(state);
    std::vector<UiAction> actions;
    // Over the bottom right of the 3D view: the canvas, where the pen works, stays clear.
    const float maxWidth = std::max(200.f, width * 0.5f - 16);
    bool first = true;  // the first button of a row: no flow test against the text before it
    auto act = [&](const std::string& label, const std::string& action, bool current = false) {
        const std::string text = label + ui::keyOf(v.bindings, action);
        if (!first) ui::flow(text, maxWidth);
        first = false;
        if (button(state, text, current, label)) actions.push_back({action});
    };
    // A row: its title, then its buttons on the same line while they fit.
    auto row = [&](const char* title) {
        ImGui::TextUnformatted(title);
        first = false;
    };
    ImGui::SetNextWindowPos(ImVec2(width - 8.f, height - 8.f), ImGuiCond_Always, ImVec2(1, 1));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(maxWidth, float(height)));
    if (ImGui::Begin("##sketch", nullptr, ui::kPanel)) {
        ui::rememberWindow(state, "status");
        ImGui::PushTextWrapPos(maxWidth - 16);
        ImGui::Text("page '%s' (%zu of %zu, %s view) | %s%s | lasso %s", v.page.c_str(),
                    v.pageIndex + 1, v.pageCount, v.plane.c_str(), v.cleanup ? "clean-up" : "draft",
                    v.cleanup ? (v.curves ? " curves" : " lines") : "", v.lasso ? "on" : "off");
        ImGui::Text("%zu stroke(s), %zu curve(s), %zu step(s) | %.1f ms | project %s", v.strokes,
                    v.curvesDone, v.steps, v.frameMs, v.project.c_str());
        if (!v.message.empty())
            ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", v.message.c_str());
        ImGui::PopTextWrapPos();
        // On short windows the rows start folded, so the 3D view stays visible.
        if (!state.sketchTools) state.sketchTools = height >= 600;
        if (button(state, *state.sketchTools ? "hide tools" : "tools...", false, "tools"))
            state.sketchTools = !*state.sketchTools;
        first = false;
        if (*state.sketchTools) {
            row("page");
            act("previous", "page_previous");
            act("next", "page_next");
            act("new page", "page_new");
            act("front", "view_front", v.plane == "front");
            act("side", "view_side", v.plane == "side");
            act("top", "view_top", v.plane == "top");
            row("mode");
            // Both mode buttons send the toggle: only the one not in use does anything.
            ui::flow("draft", maxWidth);
            if (button(state, "draft", !v.cleanup, "draft") && v.cleanup)
                actions.push_back({"mode"});
            ui::flow("clean-up", maxWidth);
            if (button(state, "clean-up" + ui::keyOf(v.bindings, "mode"), v.cleanup, "clean-up") &&
                !v.cleanup)
                actions.push_back({"mode"});
            first = false;
            act("lines", "kind_line", v.cleanup && !v.curves);
            act("curves", "kind_curve", v.cleanup && v.curves);
            act("lasso", "lasso", v.lasso);
            row("role (last stroke)");
            act("outline", "role_outline");
            act("surface x", "role_surface_x");
            act("y", "role_surface_y");
            act("z", "role_surface_z");
            act("section", "role_sweep_section");
            act("path", "role_sweep_path");
            act("cut line", "role_cut");
            act("extrude line", "role_extrude");
            row("solid");
            act("inflate", "solid_inflate");
            act("three sections", "solid_three_section");
            act("sweep", "solid_sweep");
            act("cut", "solid_cut");
            act("extrude", "solid_extrude");
            row("edit");
            act("undo", "undo");
            act("redo", "redo");
            act("delete", "delete");
            act("frame", "frame");
            act("history", "history");
        }
        ImGui::Separator();
        ui::projectButtons(state, v.bindings, actions);
    }
    ImGui::End();
    ui::sharedPanels(state, v.bindings, true, cfg, actions, width, height);
    return actions;
}

}  // namespace vsculpt::app
