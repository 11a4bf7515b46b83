// SPDX-License-Identifier: MIT
/// @file CliChecks.h
/// @brief Checks of command-line values shared by the subcommands, so the same mistake gets
/// the same message and the same exit code (2, bad input) everywhere.
#pragma once

#include "vsculpt/render/Shot.h"
#include "vsculpt/render/Viewer.h"

#include <filesystem>
#include <string>
#include <utility>

namespace vsculpt::app {

/// "WIDTHxHEIGHT", each 1..16384 pixels. Throws std::invalid_argument naming `option`.
std::pair<int, int> parseImageSize(const std::string& text, const std::string& option);

/// Images are written as PNG only: a path that does not end in .png is refused (rather than a
/// PNG written under a .jpg name). Throws std::invalid_argument naming `option`.
void requirePngPath(const std::filesystem::path& path, const std::string& option);

/// A window run's last frame: read back, handed to `lastFrame` (tests) when given and written to
/// `shotPath` (--shot) when not empty. False, with the error logged, when the PNG cannot be
/// written (the run's exit code is then 1).
bool keepLastFrame(render::Viewer& viewer, const std::string& shotPath, render::Image* lastFrame);

}  // namespace vsculpt::app
