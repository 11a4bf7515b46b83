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
#include <vector>

namespace vsculpt::app {

/// "WIDTHxHEIGHT", each 1..16384 pixels. Throws std::invalid_argument naming `option`.
std::pair<int, int> parseImageSize(const std::string& text, const std::string& option);

/// Images are written as PNG only: a path that does not end in .png is refused (rather than a
/// PNG written under a .jpg name). Throws std::invalid_argument naming `option`.
void requirePngPath(const std::filesystem::path& path, const std::string& option);

/// A device recording is written as .vsrec (what `vsculpt play` and the docs call one), not
/// under another format's name. Throws std::invalid_argument naming `option`.
void requireRecordingPath(const std::filesystem::path& path, const std::string& option);

/// Two outputs on one file, or an output on the script, the config or a project's own files
/// (every file directly in `projectDir`: snapshot, journal, their backups, sketch.json, lock):
/// the run would overwrite what it reads or writes. Paths are compared resolved (`..`, links).
/// `written` holds (option, path) pairs; empty `script`, `config`, `projectDir` are skipped.
/// The message naming the option, or "" when none clash.
std::string outputClash(const std::vector<std::pair<std::string, std::string>>& written,
                        const std::string& script, const std::string& config,
                        const std::string& projectDir);

/// A window run's last frame: read back, handed to `lastFrame` (tests) when given and written to
/// `shotPath` (--shot) when not empty. False, with the error logged, when the PNG cannot be
/// written (the run's exit code is then 1).
bool keepLastFrame(render::Viewer& viewer, const std::string& shotPath, render::Image* lastFrame);

}  // namespace vsculpt::app
