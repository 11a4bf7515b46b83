// SPDX-License-Identifier: MIT
/// @file XrWindow.h
/// @brief Sculpting in an OpenXR headset: `vsculpt --xr` or render.output "xr" (docs/xr.md).
/// The frame loop is paced by xrWaitFrame; each frame syncs the controllers (XrInput.h),
/// draws both eyes into the runtime's swapchains and submits them as one projection layer,
/// with the status and the palette as a quad layer beside the sculpture, clicked with the pen
/// (XrPanelUi.h). The desktop window mirrors the left eye (unless --hidden). The dialogs that
/// need typing are not in the headset.
#pragma once

#include "vsculpt/app/Window.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/studio/Script.h"

#include <iosfwd>

namespace vsculpt::app {

/// Exit codes: 0 when the session ends (--frames reached, the window closed, the runtime
/// ended it); 1 when the headset is lost mid-session or an OpenXR call fails; 2 for bad
/// input (config, script, project). No runtime or no headset: a warning saying why, then the
/// desktop window (runWindow) and its exit code. `cfg` and `script` are what runWindow
/// loaded from the options (config file, --play), so neither is read twice.
int runXr(const WindowOptions& options, const core::SculptConfig& cfg, studio::Script script,
          std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
