// SPDX-License-Identifier: MIT
// The windows' on-screen UI content (WindowUi.h): the shared parts (help, project menu,
// dialogs, recent projects, preferences) and the sculpting window's palette and status.
#include "vsculpt/app/WindowUi.h"

#include "UiWidgets.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/core/HomeFolder.h"
#include "vsculpt/core/PatchConfigText.h"
#include "vsculpt/core/WriteFileAtomically.h"

#include <imgui.h>
#include <imgui_stdlib.h>
#include <spdlog/spdlog.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes (the UI's key map uses GLFW's)

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace vsculpt::app {

bool UiState::covers(double x, double y) const {
    for (const auto& [name, r] : rects)
        if (name.find(':') == std::string::npos && r.contains(x, y)) return true;
    return false;
}

namespace ui {

ImVec4 rgb(const std::array<uint8_t, 3>& c, float alpha) {
    return ImVec4(c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, alpha);
}

void applyStyle() {
    ImGuiStyle& style = ImGui::GetStyle();
    // Opaque panels: readable over any part of the sculpture, and the same colour in tests.
    style.Colors[ImGuiCol_WindowBg] = rgb(kUiPanelRgb, 1);
    style.Colors[ImGuiCol_PopupBg] = rgb(kUiPanelRgb, 1);
    style.Colors[ImGuiCol_Text] = rgb(kUiTextRgb, 1);
    style.WindowRounding = 0;
}

void rememberWindow(UiState& state, const std::string& name) {
    const ImVec2 p = ImGui::GetWindowPos(), s = ImGui::GetWindowSize();
    state.rects[name] = {p.x, p.y, p.x + s.x, p.y + s.y};
}

bool button(UiState& state, const std::string& label, bool current, const std::string& key) {
    if (current) {
        // The size, zoom or tool in use: yellow, as the old palette had it.
        ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.85f, 0.68f, 0.15f, 1));
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.08f, 0.08f, 0.08f, 1));
    }
    const bool clicked = ImGui::Button((label + "##" + (key.empty() ? label : key)).c_str());
    if (current) ImGui::PopStyleColor(2);
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    state.rects["button:" + (key.empty() ? label : key)] = {a.x, a.y, b.x, b.y};
    return clicked;
}

const ImGuiWindowFlags kPanel = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove |
                                ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                ImGuiWindowFlags_NoSavedSettings |
                                ImGuiWindowFlags_AlwaysAutoResize |
                                ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav;

void flow(const std::string& label, float maxWidth) {
    const ImGuiStyle& style = ImGui::GetStyle();
    const float w = ImGui::CalcTextSize(label.c_str(), nullptr, true).x + 2 * style.FramePadding.x;
    const float end = ImGui::GetItemRectMax().x - ImGui::GetWindowPos().x;
    if (end + style.ItemSpacing.x + w <= maxWidth - style.WindowPadding.x) ImGui::SameLine();
}

std::string keyOf(const std::map<std::string, std::string>* bindings, const std::string& action) {
    if (!bindings) return "";
    auto it = bindings->find(action);
    return it == bindings->end() ? "" : " (" + it->second + ")";
}

void projectButtons(UiState& state, const std::map<std::string, std::string>* bindings,
                    std::vector<UiAction>& actions) {
    if (!state.importing.empty()) {
        ImGui::TextUnformatted(state.importing.c_str());
        if (button(state, "cancel import", false, "cancel import"))
            actions.push_back({"cancel_import"});
    }
    if (button(state, "save" + keyOf(bindings, "save"), false, "save")) actions.push_back({"save"});
    ImGui::SameLine();
    if (button(state, "save as...", false, "save as..."))
        actions.push_back({"open_save_as_dialog"});
    ImGui::SameLine();
    if (button(state, "export...", false, "export...")) actions.push_back({"open_export_dialog"});
    ImGui::SameLine();
    if (button(state, "import mesh...", false, "import mesh..."))
        actions.push_back({"open_import_dialog"});
    if (button(state, "recent...", false, "recent...")) actions.push_back({"open_recent"});
    ImGui::SameLine();
    if (button(state, "new project" + keyOf(bindings, "new_project"), false, "new project"))
        actions.push_back({"new_project"});
    ImGui::SameLine();
    if (button(state, "preferences...", false, "preferences...")) {
        state.preferences = !state.preferences;
        state.preferencesNote.clear();
    }
    ImGui::SameLine();
    if (button(state, "help" + keyOf(bindings, "help"), state.help, "help"))
        actions.push_back({"help"});
}

void helpOverlay(UiState& state, const std::map<std::string, std::string>* bindings, bool sketch,
                 int width, int height) {
    if (!state.help || !bindings) return;
    ImGui::SetNextWindowPos(ImVec2(width * 0.5f, height * 0.5f), ImGuiCond_Always,
                            ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(width * 0.9f, height * 0.85f));
    bool open = true;
    if (ImGui::Begin("Keys and mouse", &open,
                     ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize)) {
        rememberWindow(state, "help");
        const auto lines = helpLines(*bindings, sketch);
        // Two pairs of columns side by side: the sketch window has about forty bindings.
        if (ImGui::BeginTable("bindings", 4, ImGuiTableFlags_SizingFixedFit)) {
            const size_t half = (lines.size() + 1) / 2;
            for (size_t i = 0; i < half; ++i) {
                ImGui::TableNextRow();
                for (size_t j : {i, i + half}) {
                    ImGui::TableNextColumn();
                    if (j < lines.size()) ImGui::TextUnformatted(lines[j].first.c_str());
                    ImGui::TableNextColumn();
                    if (j < lines.size())
                        ImGui::TextColored(ImVec4(1, 0.85f, 0.3f, 1), "%s   ",
                                           lines[j].second.c_str());
                }
            }
            ImGui::EndTable();
        }
    }
    ImGui::End();
    if (!open) state.help = false;
}

void dialog(UiState& state, std::vector<UiAction>& actions) {
    if (state.dialogOpening) {
        ImGui::OpenPopup("##project-dialog");
        state.dialogOpening = false;
        state.rects.erase("dialog");
    }
    const bool exportDialog = state.dialog == UiState::Dialog::Export;
    const bool importDialog = state.dialog == UiState::Dialog::Import;
    if (!ImGui::BeginPopupModal("##project-dialog", nullptr,
                                ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoTitleBar |
                                    ImGuiWindowFlags_NoSavedSettings))
        return;
    if (state.dialog == UiState::Dialog::None) {  // done (or cancelled) last frame
        ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
        return;
    }
    rememberWindow(state, "dialog");
    ImGui::TextUnformatted(
        exportDialog   ? "Export the sculpture to a file (.glb .obj .stl .ply .vdb .dxf)"
        : importDialog ? "Add a mesh file as clay (.obj .stl .ply .gltf .glb; docs/import.md)"
                       : "Save the project as a new folder (new or empty) and continue there");
    // The field has the keyboard with its text selected when the dialog opens and after an
    // error: typing replaces the proposal, arrows and End edit it.
    if (ImGui::IsWindowAppearing() || state.refocusField) ImGui::SetKeyboardFocusHere();
    state.refocusField = false;
    ImGui::SetNextItemWidth(520);
    const bool enter =
        ImGui::InputText("##path", &state.pathField,
                         ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    {
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        state.rects["field:path"] = {a.x, a.y, b.x, b.y};
    }
    if (exportDialog || importDialog) {
        // Export: the file's frame; import: the frame the file was written in. As wide as their
        // longest choice at any UI scale (found by QA: "format defa" at 1.4).
        const float comboWidth =
            ImGui::CalcTextSize("format default").x + 2 * ImGui::GetFrameHeight();
        ImGui::SetNextItemWidth(comboWidth);
        ImGui::Combo("up axis", exportDialog ? &state.exportUp : &state.importUp,
                     "format default\0+Y up\0+Z up\0");
        ImGui::SameLine();
        ImGui::SetNextItemWidth(comboWidth);
        ImGui::Combo("units", exportDialog ? &state.exportUnits : &state.importUnits,
                     "format default\0mm\0cm\0m\0");
    }
    if (importDialog) {
        ImGui::SetNextItemWidth(140);
        ImGui::InputDouble("fit to mm (0: as is)", &state.importFitMm, 0, 0, "%.1f");
        // The lattice the clay is made on: finer is smoother and truer, with more skeletons
        // to carry (docs/import.md, "Placement: the level").
        ImGui::SetNextItemWidth(260);
        ImGui::Combo("clay level", &state.importLevel,
                     "auto (from its thickness)\0"
                     "1 (finest)\0"
                     "2\0"
                     "3\0"
                     "4\0"
                     "5\0"
                     "6\0"
                     "7 (coarsest)\0");
    }
    if (!state.dialogError.empty()) {
        ImGui::PushTextWrapPos(560);
        ImGui::TextColored(ImVec4(1, 0.4f, 0.35f, 1), "%s", state.dialogError.c_str());
        ImGui::PopTextWrapPos();
    }
    const bool ok = button(state,
                           exportDialog   ? "export"
                           : importDialog ? "import"
                                          : "save as",
                           false, "dialog ok");
    ImGui::SameLine();
    const bool cancel =
        button(state, "cancel", false, "dialog cancel") || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE);
    if (ok || enter) {
        actions.push_back(dialogAction(state));
    } else if (cancel) {
        state.dialog = UiState::Dialog::None;
        state.dialogError.clear();
        ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
}

void recentPanel(UiState& state, std::vector<UiAction>& actions, int width) {
    if (!state.recent) return;
    ImGui::SetNextWindowPos(ImVec2(width - 8.f, 8), ImGuiCond_Always, ImVec2(1, 0));
    bool open = true;
    if (ImGui::Begin("Recent projects", &open,
                     ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize)) {
        rememberWindow(state, "recent");
        // As wide as its title and close box at least (found by QA: "Recent proje").
        ImGui::Dummy(
            ImVec2(ImGui::CalcTextSize("Recent projects").x + 2 * ImGui::GetFrameHeight(), 0));
        if (state.recentList.empty()) ImGui::TextUnformatted("no recent projects");
        for (size_t i = 0; i < state.recentList.size(); ++i)
            if (button(state, state.recentList[i].string(), false, "recent " + std::to_string(i)))
                actions.push_back({"open_project", state.recentList[i], {}});
    }
    ImGui::End();
    if (!open) state.recent = false;
}

void preferencesPanel(UiState& state, core::SculptConfig& cfg, std::vector<UiAction>& actions,
                      int width, int height) {
    if (!state.preferences) return;
    ImGui::SetNextWindowPos(ImVec2(width - 8.f, height * 0.5f), ImGuiCond_Always, ImVec2(1, 0.5f));
    bool open = true;
    if (ImGui::Begin("Preferences", &open,
                     ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize)) {
        rememberWindow(state, "preferences");
        bool changed = false;
        int stereo = cfg.render.stereo == "sbs" ? 1 : cfg.render.stereo == "anaglyph" ? 2 : 0;
        ImGui::SetNextItemWidth(200);
        if (ImGui::Combo("stereo", &stereo, "mono\0side by side\0anaglyph\0")) {
            cfg.render.stereo = stereo == 1 ? "sbs" : stereo == 2 ? "anaglyph" : "mono";
            changed = true;
        }
        // `decimals`: what the slider shows, and what is kept: a value dragged to 0.019 is saved
        // as 0.019, not as the float's 0.01899999938905239 (found by QA).
        auto slider = [&](const char* label, double& value, float lo, float hi, int decimals) {
            float v = float(value);
            const std::string fmt = "%." + std::to_string(decimals) + "f";
            ImGui::SetNextItemWidth(200);
            if (ImGui::SliderFloat(label, &v, lo, hi, fmt.c_str())) {
                const double step = std::pow(10.0, -decimals);
                value = std::round(double(v) / step) * step;
                changed = true;
            }
        };
        slider("IPD (mm)", cfg.render.ipdMm, 0, 80, 1);
        slider("UI depth (mm, 0: screen)", cfg.render.uiDepthMm, 0, 2000, 0);
        // The config's whole range (found by QA: the slider stopped at 3 of its 4).
        slider("UI scale", cfg.render.uiScale, 0.5f, 4, 2);
        if (const float drawn = fittedUiScale(cfg.render.uiScale, height);
            drawn < cfg.render.uiScale - 1e-6)
            ImGui::TextDisabled("drawn at %.2f: a window %d px high fits no more", drawn, height);
        slider("rotate (rad per pixel)", cfg.interaction.rotateRadPerPixel, 0.001f, 0.05f, 3);
        slider("scroll depth (x diameter)", cfg.interaction.depthStepOverDiameter, 0.05f, 1, 2);
        if (changed) actions.push_back({"preferences_changed"});
        ImGui::Separator();
        const std::filesystem::path target = core::userConfigPath();
        std::error_code ec;
        ImGui::PushTextWrapPos(420);
        if (target.empty())
            ImGui::TextUnformatted("no user config folder ($XDG_CONFIG_HOME and $HOME unset)");
        else
            ImGui::Text(
                "Save writes %s%s", target.c_str(),
                std::filesystem::exists(target, ec)
                    ? " (updating that file: only changed values are rewritten, its comments stay)"
                    : "");
        if (!state.preferencesNote.empty()) ImGui::TextUnformatted(state.preferencesNote.c_str());
        ImGui::PopTextWrapPos();
        if (!target.empty() && button(state, "save preferences", false, "save preferences"))
            actions.push_back({"save_preferences"});
    }
    ImGui::End();
    if (!open) state.preferences = false;
}

void sharedPanels(UiState& state, const std::map<std::string, std::string>* bindings, bool sketch,
                  core::SculptConfig& cfg, std::vector<UiAction>& actions, int width, int height) {
    helpOverlay(state, bindings, sketch, width, height);
    recentPanel(state, actions, width);
    preferencesPanel(state, cfg, actions, width, height);
    dialog(state, actions);
}

void beginUi(UiState& state) {
    applyStyle();
    // Rectangles are this frame's: panels closed since the last one are gone.
    state.rects.clear();
}

}  // namespace ui

std::vector<std::pair<std::string, std::string>> helpLines(
    const std::map<std::string, std::string>& bindings, bool sketch) {
    std::vector<std::pair<std::string, std::string>> lines;
    for (const auto& [action, key] : bindings)
        lines.emplace_back(action, key);
    if (sketch) {
        lines.emplace_back("draw (canvas) / draw on the model", "left button");
        lines.emplace_back("pan the canvas / turn the sculpture", "right drag");
        lines.emplace_back("zoom the canvas", "scroll wheel");
    } else {
        lines.emplace_back("sculpt (add / carve while held)", "left button");
        lines.emplace_back("turn the sculpture", "right drag");
        lines.emplace_back("move the sculpture", "middle drag");
        lines.emplace_back("tool depth in / out", "scroll wheel");
    }
    return lines;
}

namespace {

// In ToolKind's order.
constexpr const char* kToolNames[4] = {"add", "carve", "smooth", "select"};
const ImVec4 kToolColour[4] = {ImVec4(0.45f, 1.0f, 0.5f, 1), ImVec4(1.0f, 0.4f, 0.35f, 1),
                               ImVec4(1.0f, 0.8f, 0.4f, 1), ImVec4(0.45f, 0.65f, 1.0f, 1)};

/// The palette's rows (tool, undo and redo; mirror; the zoom's sizes; zoom), in the current
/// window: the window's palette and the headset's panel show the same buttons.
void paletteRows(UiState& state, const SculptUiView& v, std::vector<UiAction>& actions) {
    using ui::button;
    const int tool = int(v.tool);
    // The labels' column, in the font's size: the buttons line up at any UI scale.
    const float column = 4.6f * ImGui::GetFontSize();
    ImGui::AlignTextToFramePadding();  // level with the buttons
    ImGui::Text("tool");
    for (int t = 0; t < 4; ++t) {
        ImGui::SameLine(t == 0 ? column : 0);
        if (button(state, kToolNames[t], t == tool, ""))
            actions.push_back({std::string("tool_") + kToolNames[t]});
    }
    ImGui::SameLine();
    ImGui::TextUnformatted("   ");
    ImGui::SameLine();
    if (button(state, "undo" + ui::keyOf(v.bindings, "undo"), false, "undo"))
        actions.push_back({"undo"});
    ImGui::SameLine();
    if (button(state, "redo" + ui::keyOf(v.bindings, "redo"), false, "redo"))
        actions.push_back({"redo"});
    ImGui::AlignTextToFramePadding();
    ImGui::Text("mirror");
    for (core::MirrorAxis m :
         {core::MirrorAxis::None, core::MirrorAxis::X, core::MirrorAxis::Y, core::MirrorAxis::Z}) {
        ImGui::SameLine(m == core::MirrorAxis::None ? column : 0);
        const std::string name = core::toString(m);
        if (button(state, name, m == v.mirror, "mirror " + name))
            actions.push_back({"mirror_" + name});
    }
    ImGui::AlignTextToFramePadding();
    ImGui::Text("size");
    for (size_t i = 0; i < v.offeredSizes.size(); ++i) {
        const auto& [level, mm] = v.offeredSizes[i];
        ImGui::SameLine(i == 0 ? column : 0);
        char label[48];
        std::snprintf(label, sizeof label, "%d: %.1f mm", level, mm);
        if (button(state, label, level == v.size, "size " + std::to_string(level)))
            actions.push_back({"size_" + std::to_string(level)});
    }
    ImGui::AlignTextToFramePadding();
    ImGui::Text("zoom");
    for (int z = 1; z <= 5; ++z) {
        ImGui::SameLine(z == 1 ? column : 0);
        if (button(state, std::to_string(z) + (z == 1 ? " overview" : ""), z == v.zoom,
                   "zoom " + std::to_string(z)))
            actions.push_back({"zoom_" + std::to_string(z)});
    }
}

}  // namespace

SculptUiView sculptUiViewOf(const studio::Session& session,
                            const studio::Interaction& interaction) {
    SculptUiView view;
    const core::ToolLevels& levels = session.sculpture().levels();
    view.tool = session.tool();
    view.mirror = session.mirror();
    view.size = session.size();
    view.sizeMm = levels.level(session.size()).diameterMm;
    for (int s : interaction.offeredSizes())
        view.offeredSizes.emplace_back(s, levels.level(s).diameterMm);
    view.zoom = session.zoom();
    view.skeletons = session.sculpture().counts().total();
    view.project =
        session.projectDir() ? session.projectDir()->filename().string() : "no project (scratch)";
    return view;
}

std::vector<UiAction> sculptUi(UiState& state, const SculptUiView& v, core::SculptConfig& cfg,
                               int width, int height) {
    using ui::button;
    ui::beginUi(state);
    std::vector<UiAction> actions;
    const int tool = int(v.tool);
    // The status panel, top left.
    const float left = 8 + v.marginPx;
    ImGui::SetNextWindowPos(ImVec2(left, 8), ImGuiCond_Always);
    if (ImGui::Begin("##status", nullptr, ui::kPanel)) {
        ui::rememberWindow(state, "status");
        const float values = 7 * ImGui::GetFontSize();  // the column at any UI scale
        ImGui::Text("tool");
        ImGui::SameLine(values);
        ImGui::TextColored(kToolColour[tool], "%s", kToolNames[tool]);
        ImGui::Text("mirror");
        ImGui::SameLine(values);
        ImGui::Text("%s", v.mirror == core::MirrorAxis::None
                              ? "off"
                              : (std::string(core::toString(v.mirror)) + " = 0 plane").c_str());
        ImGui::Text("size");
        ImGui::SameLine(values);
        ImGui::Text("%d  (%.1f mm)", v.size, v.sizeMm);
        ImGui::Text("zoom");
        ImGui::SameLine(values);
        ImGui::Text("%d of 5", v.zoom);
        ImGui::Text("skeletons");
        ImGui::SameLine(values);
        ImGui::Text("%zu", v.skeletons);
        ImGui::Text("frame");
        ImGui::SameLine(values);
        ImGui::Text("%.1f ms", v.frameMs);
        ImGui::Text("project");
        ImGui::SameLine(values);
        ImGui::TextUnformatted(v.project.c_str());
        // The buttons before the message, so a message of a few lines (save as, new project)
        // never moves them under the pointer (found by QA: a click meant for "recent..."
        // saved again).
        ui::projectButtons(state, v.bindings, actions);
        if (!v.message.empty()) {
            ImGui::PushTextWrapPos(420);
            ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", v.message.c_str());
            ImGui::PopTextWrapPos();
        }
    }
    ImGui::End();

    // The palette, along the bottom edge.
    ImGui::SetNextWindowPos(ImVec2(left, height - 8.f), ImGuiCond_Always, ImVec2(0, 1));
    if (ImGui::Begin("##palette", nullptr, ui::kPanel)) {
        ui::rememberWindow(state, "palette");
        paletteRows(state, v, actions);
    }
    ImGui::End();
    // The shared panels sit at the right edge: the same margin there.
    ui::sharedPanels(state, v.bindings, false, cfg, actions, width - int(v.marginPx), height);
    return actions;
}

std::vector<UiAction> headsetUi(UiState& state, const SculptUiView& v, const std::string& hands,
                                int width, int height) {
    using ui::button;
    ui::beginUi(state);
    std::vector<UiAction> actions;
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(float(width), float(height)), ImGuiCond_Always);
    // Buttons a controller's ray can hit from arm's length: about twice the window's padding.
    const float font = ImGui::GetFontSize();
    ImGui::PushStyleVar(ImGuiStyleVar_FramePadding, ImVec2(0.7f * font, 0.45f * font));
    ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(0.45f * font, 0.45f * font));
    if (ImGui::Begin("##headset", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                         ImGuiWindowFlags_NoNav)) {
        ui::rememberWindow(state, "headset");
        const int tool = int(v.tool);
        ImGui::TextColored(kToolColour[tool], "%s", kToolNames[tool]);
        ImGui::SameLine();
        ImGui::Text(" size %d (%.1f mm)   zoom %d   mirror %s", v.size, v.sizeMm, v.zoom,
                    core::toString(v.mirror));
        ImGui::Text("%zu skeleton%s   %.1f ms   %s", v.skeletons, v.skeletons == 1 ? "" : "s",
                    v.frameMs, hands.c_str());
        paletteRows(state, v, actions);
        ImGui::Spacing();
        if (button(state, "save", false, "save")) actions.push_back({"save"});
        ImGui::SameLine();
        if (button(state, "export .glb", false, "export")) actions.push_back({"export"});
        ImGui::SameLine();
        ImGui::AlignTextToFramePadding();
        ImGui::TextUnformatted(v.project.c_str());
        if (!v.message.empty()) {
            ImGui::PushTextWrapPos(float(width) - font);
            ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", v.message.c_str());
            ImGui::PopTextWrapPos();
        }
        // Where the pen points: a controller has no cursor of its own.
        if (ImGui::IsMousePosValid())
            ImGui::GetForegroundDrawList()->AddCircleFilled(ImGui::GetIO().MousePos, 0.35f * font,
                                                            IM_COL32(255, 255, 255, 230));
    }
    ImGui::End();
    ImGui::PopStyleVar(2);
    return actions;
}

std::filesystem::path savePreferences(const core::SculptConfig& cfg) {
    const std::filesystem::path path = core::userConfigPath();
    if (path.empty())
        throw std::runtime_error("no user config folder: $XDG_CONFIG_HOME and $HOME are unset");
    std::filesystem::create_directories(path.parent_path());
    std::string text = core::configToJson(cfg) + "\n";
    // A file the user keeps keeps its comments and layout: only the values that differ change.
    if (std::ifstream in{path}) {
        std::ostringstream was;
        was << in.rdbuf();
        try {
            std::string patched = core::patchConfigText(was.str(), cfg, path.string());
            if (core::configToJson(core::parseConfig(patched, path.string())) ==
                core::configToJson(cfg))
                text = std::move(patched);
        } catch (const core::ConfigError& e) {
            spdlog::warn("{}: replaced whole ({})", path.string(), e.what());
        }
    }
    core::writeFileAtomically(path, text, true);
    return path;
}

namespace {

// A path as a user types it in a dialog: "~/out.obj" is in the home folder (not a folder named
// "~" in the current one, found by QA), and a relative one is made absolute, so the message
// says where the file went.
std::filesystem::path typedPath(const std::filesystem::path& typed) {
    std::filesystem::path p = typed;
    if (const std::string t = typed.string(); t == "~" || t.rfind("~/", 0) == 0) {
        const std::filesystem::path home = core::homeFolder();
        if (home.empty()) throw std::invalid_argument(t + ": no home folder ($HOME is not set)");
        p = home / (t.size() > 2 ? t.substr(2) : "");
    }
    return std::filesystem::absolute(p).lexically_normal();
}

}  // namespace

float fittedUiScale(double configured, int heightPx) {
    return float(std::max(0.5, std::min(configured, double(std::max(1, heightPx)) / 560.0)));
}

bool opensPanel(const std::string& n) {
    return n == "open_save_as_dialog" || n == "open_export_dialog" || n == "open_import_dialog" ||
           n == "open_recent";
}

bool closeOpenPanel(UiState& state) {
    for (bool* open : {&state.help, &state.recent, &state.preferences})
        if (*open) {
            *open = false;
            return true;
        }
    return false;
}

bool applySharedUiAction(const UiAction& a, Rig& rig, UiState& state, const core::SculptConfig& cfg,
                         std::string& message, bool& switched) {
    const std::string& n = a.name;
    if (n == "open_save_as_dialog" || n == "open_export_dialog" || n == "open_import_dialog") {
        state.dialog = n == "open_export_dialog"   ? UiState::Dialog::Export
                       : n == "open_import_dialog" ? UiState::Dialog::Import
                                                   : UiState::Dialog::SaveAs;
        state.dialogOpening = true;
        state.dialogError.clear();
        state.pathField = state.dialog == UiState::Dialog::Export ? rig.defaultExportPath().string()
                          : state.dialog == UiState::Dialog::Import
                              ? state.lastImportPath
                              : newProjectDir("projects").string();
        return true;
    }
    if (n == "open_recent") {
        state.recent = !state.recent;
        state.recentList = recentProjects();
        return true;
    }
    if (n == "cancel_import") {
        if (rig.studio().cancelImport()) message = "import cancelled: nothing added";
        return true;
    }
    const bool fromDialog = n == "save_as" || n == "export" || n == "import";
    if (n != "save" && n != "new_project" && n != "open_project" && n != "save_preferences" &&
        !fromDialog)
        return false;
    try {
        if (fromDialog && a.path.empty()) throw std::invalid_argument("type a path first");
        const std::filesystem::path path = fromDialog ? typedPath(a.path) : a.path;
        if (n == "save") {
            message = rig.save();
        } else if (n == "save_as") {
            message = rig.saveAs(path);
            switched = true;
        } else if (n == "export") {
            message = rig.exportTo(path, a.exportOptions);
        } else if (n == "import") {
            // Read and placed beside the frame (a scan can take seconds); the frame's poll
            // (Rig::pollBackgroundWork) says when it is in.
            rig.studio().importMeshInBackground(path, a.importOptions, a.importLevel);
            spdlog::info("importing {}", path.string());
            message.clear();  // the panel's import line (UiState::importing) says it
            state.lastImportPath = path.string();
        } else if (n == "new_project") {
            message = rig.newProject();
            switched = true;
        } else if (n == "open_project") {
            message = rig.openProject(path);
            switched = true;
            state.recent = false;
        } else {
            const std::filesystem::path p = savePreferences(cfg);
            message = "preferences saved to " + p.string();
            state.preferencesNote = message;
        }
        if (fromDialog) {
            state.dialog = UiState::Dialog::None;
            state.dialogError.clear();
        }
    } catch (const std::logic_error& e) {
        if (!dynamic_cast<const std::invalid_argument*>(&e) &&
            !dynamic_cast<const std::out_of_range*>(&e))
            throw;  // a broken invariant: not a refused request
        message = e.what();
        if (fromDialog) state.dialogError = message;
        state.refocusField = fromDialog;
    } catch (const std::exception& e) {
        message = e.what();
        if (fromDialog) state.dialogError = message;
        state.refocusField = fromDialog;
        if (n == "save_preferences") state.preferencesNote = message;
    }
    return true;
}

UiAction dialogAction(const UiState& state) {
    const bool exporting = state.dialog == UiState::Dialog::Export;
    const bool importing = state.dialog == UiState::Dialog::Import;
    UiAction a{exporting ? "export" : importing ? "import" : "save_as", state.pathField};
    const int upChoice = importing ? state.importUp : state.exportUp;
    const int unitChoice = importing ? state.importUnits : state.exportUnits;
    std::optional<core::UpAxis> up;
    std::optional<core::LengthUnit> units;
    if (upChoice > 0) up = upChoice == 1 ? core::UpAxis::Y : core::UpAxis::Z;
    if (unitChoice > 0)
        units = unitChoice == 1   ? core::LengthUnit::Millimetre
                : unitChoice == 2 ? core::LengthUnit::Centimetre
                                  : core::LengthUnit::Metre;
    if (exporting) {
        a.exportOptions.up = up;
        a.exportOptions.units = units;
    }
    if (importing) {
        a.importOptions.up = up;
        if (units) a.importOptions.mmPerUnit = core::mmPerUnit(*units);
        if (state.importFitMm > 0) a.importOptions.fitMm = state.importFitMm;
        a.importLevel = state.importLevel;
    }
    return a;
}

}  // namespace vsculpt::app
