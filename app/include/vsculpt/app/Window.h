// SPDX-License-Identifier: MIT
/// @file Window.h
/// @brief The sculpting window: `vsculpt` with no subcommand. Mouse and keyboard stand in for
/// the pen and the 3D mouse (docs/window.md lists the bindings).
#pragma once

#include "vsculpt/app/Log.h"

#include <iosfwd>
#include <string>

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
};

/// Exit code 0; 1 when no window can be opened (the message says why and points to
/// `vsculpt play`); 2 for bad input (config, script, a project that cannot be opened).
int runWindow(const WindowOptions& options, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
