// SPDX-License-Identifier: MIT
/// @file RenderStill.h
/// @brief `vsculpt render INPUT --out image.png`: a ray-traced still (Embree, ambient
/// occlusion, soft shadows) of a script's or a project's sculpture, or with `--turntable N`
/// an image sequence of the sculpture turning once about the vertical axis.
#pragma once

#include "vsculpt/app/Log.h"

#include <iosfwd>
#include <string>

namespace vsculpt::app {

struct RenderOptions {
    std::string input;    ///< a playback script, or a project folder
    std::string outPath;  ///< PNG
    std::string size = "1280x960";
    int samples = 32;      ///< ambient-occlusion rays per pixel (shadow rays: half)
    double spacingMm = 0;  ///< mesh grid spacing; 0 = the zoom-3 spacing (fine detail)
    static constexpr double kMaxSpacingMm = 1000;  ///< --spacing's upper bound
    std::string configPath;                        ///< for scripts
    double yawDeg = 0, pitchDeg = 0;               ///< camera: turn the sculpture before framing it
    /// 0: one still. N > 0: N frames, frame i turned by yawDeg + 360 i / N degrees about the
    /// vertical axis through the sculpture's centre, all with one framing; written to
    /// turntablePath(outPath, i, N).
    int turntable = 0;
    bool progress = true;  ///< progress bar on a terminal
    Verbosity verbosity = Verbosity::Normal;
};

/// The file of turntable frame `index` of `count`: a run of '#' in `outPath` becomes the
/// zero-padded frame number (at least as many digits as '#'s), else "-NNN" goes before the
/// extension (three digits, more when `count` needs them). Frames are numbered from 0.
std::string turntablePath(const std::string& outPath, int index, int count);

/// Exit code: 0 success, 1 runtime failure, 2 bad input.
int runRenderStill(const RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
