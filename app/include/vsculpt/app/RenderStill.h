// SPDX-License-Identifier: MIT
/// @file RenderStill.h
/// @brief `vsculpt render INPUT --out image.png`: a ray-traced still (Embree, ambient
/// occlusion, soft shadows) of a script's or a project's sculpture.
#pragma once

#include <iosfwd>
#include <string>

namespace vsculpt::app {

struct RenderOptions {
    std::string input;    ///< a playback script, or a project folder
    std::string outPath;  ///< PNG
    std::string size = "1280x960";
    int samples = 32;                 ///< ambient-occlusion rays per pixel (shadow rays: half)
    double spacingMm = 0;             ///< mesh grid spacing; 0 = the zoom-3 spacing (fine detail)
    std::string configPath;           ///< for scripts
    double yawDeg = 0, pitchDeg = 0;  ///< camera: turn the sculpture before framing it
};

/// Exit code: 0 success, 1 runtime failure, 2 bad input.
int runRenderStill(const RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
