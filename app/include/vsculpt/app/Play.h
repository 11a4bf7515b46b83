// SPDX-License-Identifier: MIT
/// @file Play.h
/// @brief `vsculpt play SCRIPT`: a headless sculpting session driven by a playback script.
#pragma once

#include "vsculpt/app/Log.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace vsculpt::app {

struct PlayOptions {
    std::string script;
    std::vector<std::string> outputs;  ///< export paths; the format follows the extension
    std::string statsPath;             ///< JSON statistics ("" = none, "-" = stdout)
    bool check = false;                ///< incremental-vs-full mesh check after every edit
    int threads = 0;                   ///< 0 = all cores
    std::string configPath;            ///< "" = configs/sculpt.json
    std::string projectDir;            ///< "" = no project
    /// Grid spacing of exports and stats (0 = zoom 1's, kExportSpacingDetail = the spacing
    /// that keeps the finest detail, app::exportDetail).
    double exportSpacingMm = 0;
    static constexpr double kExportSpacingDetail = -1;
    static constexpr double kMaxExportSpacingMm = 1000;  ///< --export-spacing's upper bound
    bool progress = true;                                ///< progress bar on a terminal
    Verbosity verbosity = Verbosity::Normal;
    std::string shotPath;              ///< PNG of the final frame ("" = none)
    std::string stereo = "mono";       ///< mono, sbs or anaglyph
    std::string shotSize = "960x540";  ///< WIDTHxHEIGHT in pixels
    /// Frame of the --out files (core/ExportMesh.h): "y" or "z", and "mm", "cm" or "m"; "" is
    /// each format's default. .glb is always Y-up metres: a note says when these are not.
    /// --stats stays in object space (Z-up, mm) whatever these say.
    std::string up;
    std::string units;
};

/// Returns the exit code: 0 success, 1 runtime failure (check mismatch, export failure),
/// 2 bad input (script, config, arguments).
int runPlay(const PlayOptions& options, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
