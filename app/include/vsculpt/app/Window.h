// SPDX-License-Identifier: MIT
/// @file Window.h
/// @brief The sculpting window: `vsculpt` with no subcommand. Mouse and keyboard stand in for
/// the pen and the 3D mouse (docs/window.md lists the bindings).
#pragma once

#include "vsculpt/app/Log.h"

#include "vsculpt/app/WindowUi.h"
#include "vsculpt/render/Shot.h"
#include "vsculpt/render/StereoCamera.h"
#include "vsculpt/render/Viewer.h"

#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace vsculpt::app {

struct WindowOptions {
    std::string configPath;                   ///< "" = configs/sculpt.json
    Verbosity verbosity = Verbosity::Normal;  ///< --quiet / --verbose (Log.h)
    std::string stereo;                       ///< "" = the config's render.stereo
    int width = 1280, height = 800;
    int frames = 0;          ///< stop after this many frames (0: until closed) — tests, demos
    std::string playScript;  ///< run this script first (one command per frame)
    std::string shotPath;    ///< PNG of the last frame
    bool hidden = false;     ///< no visible window (with frames/shot: automated runs)
    bool devices = true;     ///< open trackers, 3D mice and headsets (docs/devices.md)
    /// The project the window works in; "" = the last project, or a new autosave project
    /// under $XDG_DATA_HOME/vsculpt/autosave (docs/projects.md).
    std::string projectDir;
    bool noProject = false;  ///< nothing saved (a scratch session)
    bool ui = true;          ///< the on-screen UI (off: measuring what it costs)
    /// An OpenXR headset instead of the window (`--xr`, docs/xr.md); unset: the config's
    /// render.output decides; false: the desktop window whatever the config says.
    std::optional<bool> xr;
    /// With the headset: record the controllers to this .vsrec, a report a frame (docs/xr.md);
    /// `vsculpt play` replays it to the same sculpture. The window ignores it.
    std::string recordPath;

    /// Tests: called at the start of every frame (0-based) with the UI as last drawn; events
    /// pushed to `inject` go through the window's real input handling this frame.
    std::function<void(size_t frame, const UiState& ui, std::vector<render::InputEvent>& inject)>
        onFrame;
    /// Tests: the last frame and the session's state after it.
    render::Image* lastFrame = nullptr;
    struct Report {
        studio::ToolKind tool = studio::ToolKind::Add;
        core::MirrorAxis mirror = core::MirrorAxis::None;
        int size = 0, zoom = 0;
        core::Vec3 zoomCentreMm{0.0};     ///< the centre of the zoom region (object space)
        size_t skeletons = 0, steps = 0;  ///< skeletons: the clay placed (lattice skeletons)
        std::string message;
        UiState ui;                     ///< the UI's state and rectangles after the last frame
        render::StereoDisplay display;  ///< the last frame's (Viewer::lastDisplay)
        double uiShiftNdc[2] = {0, 0};  ///< the UI's shift in each eye (Viewer::lastUiShiftNdc)
        double meanUiMs = 0;            ///< CPU time of the UI frame (build + render), mean
    };
    Report* report = nullptr;
};

/// Exit code 0; 1 when no window can be opened (the message says why and points to
/// `vsculpt play`); 2 for bad input (config, script, a project that cannot be opened).
/// With `xr` (or render.output "xr") it is runXr's (XrWindow.h), which comes back here when
/// there is no headset.
int runWindow(const WindowOptions& options, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
