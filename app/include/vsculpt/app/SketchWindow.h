// SPDX-License-Identifier: MIT
/// @file SketchWindow.h
/// @brief `vsculpt sketch`: the tablet sketch mode's window (docs/sketch-mode.md). The canvas
/// on the left (pen tablet or mouse), the sculpture on the right, updated as sketches become
/// solids; drawing over the sculpture puts surface lines on it.
#pragma once

#include "vsculpt/app/Log.h"

#include "vsculpt/app/WindowUi.h"
#include "vsculpt/render/Shot.h"
#include "vsculpt/render/Viewer.h"

#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace vsculpt::app {

struct SketchWindowOptions {
    std::string configPath;                   ///< "" = configs/sculpt.json
    Verbosity verbosity = Verbosity::Normal;  ///< --quiet / --verbose (Log.h)
    std::string projectDir;  ///< "" = the last project or a new autosave project (Rig.h)
    bool noProject = false;  ///< nothing saved (a scratch session)
    int width = 1280, height = 720;
    int frames = 0;          ///< stop after this many frames (0: until closed)
    std::string playScript;  ///< run this script first, one command per frame
    std::string shotPath;    ///< PNG of the last frame
    bool hidden = false;     ///< no visible window (automated runs)
    bool devices = true;     ///< open pen tablets (and the other devices)
    /// A second window with the sculpture in side-by-side stereo for the headset (full screen
    /// on render.fullscreen_monitor when set), head-tracked when a headset reports.
    bool headset = false;
    /// Tests: receives a copy of the last frame when not null.
    render::Image* lastFrame = nullptr;
    render::Image* lastHeadsetFrame = nullptr;  ///< the same for the headset window
    /// Tests: input events delivered at the given frame (0-based), as if from the mouse,
    /// keyboard or window system, through the window's real input handling.
    std::vector<std::pair<size_t, render::InputEvent>> injectedEvents;
    bool ui = true;               ///< the on-screen UI (off: measuring what it costs)
    UiState* uiReport = nullptr;  ///< tests: the UI's state and rectangles after the last frame
    std::string* messageReport = nullptr;  ///< tests: the panel's message line after it
};

/// Exit code 0; 1 when no window can be opened (the message says why and points to
/// `vsculpt play`); 2 for bad input (config, script, project).
int runSketchWindow(const SketchWindowOptions& options, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
