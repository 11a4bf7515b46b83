// SPDX-License-Identifier: MIT
// Building blocks of the windows' ImGui panels (WindowUi.h), shared by the sculpting and the
// sketch window's UI. Internal to app/; valid between UiLayer::beginFrame and endFrame.
#pragma once

#include "vsculpt/app/WindowUi.h"

#include <imgui.h>

#include <map>
#include <string>
#include <vector>

namespace vsculpt::app::ui {

/// Panels pinned in place, sized to their content, never taking keyboard focus.
extern const ImGuiWindowFlags kPanel;

/// Sets the panel and text colours (kUiPanelRgb, kUiTextRgb) and forgets last frame's rects.
void beginUi(UiState& state);
/// Records the current window's rectangle as state.rects[name].
void rememberWindow(UiState& state, const std::string& name);
/// A button, yellow when `current`; its rectangle goes to state.rects["button:" + key] (key
/// defaults to the label). True when clicked.
bool button(UiState& state, const std::string& label, bool current, const std::string& key);
/// Before a button labelled `label`: on the same line when it still fits in the window's
/// content width (`maxWidth` pixels from the window's left edge), else on a new line.
void flow(const std::string& label, float maxWidth);
/// " (KEY)" for an action's binding, or "".
std::string keyOf(const std::map<std::string, std::string>* bindings, const std::string& action);
/// Save, save as..., export..., recent..., new project, preferences..., help.
void projectButtons(UiState& state, const std::map<std::string, std::string>* bindings,
                    std::vector<UiAction>& actions);
/// The help overlay, recent projects, preferences and the save-as/export dialog.
void sharedPanels(UiState& state, const std::map<std::string, std::string>* bindings, bool sketch,
                  core::SculptConfig& cfg, std::vector<UiAction>& actions, int width, int height);

}  // namespace vsculpt::app::ui
