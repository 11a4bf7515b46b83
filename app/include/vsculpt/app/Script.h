// SPDX-License-Identifier: MIT
/// @file Script.h
/// @brief The playback script format (docs/playback.md): plain text, one command per line,
/// `#` comments, millimetres. Parsing checks syntax; rules that depend on the session's
/// state (a size not offered at the current zoom) are checked when the command runs, and
/// reported with the same file:line prefix.
#pragma once

#include "vsculpt/core/Geometry.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vsculpt::app {

/// "file:line: message". The line is 1-based; 0 when the error concerns the whole file.
class ScriptError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

enum class ToolKind { Add, Carve, Select };

struct ScriptCommand {
    enum class Kind { Tool, Size, Zoom, Object, Space, Stroke, Undo, Redo, Save };
    Kind kind = Kind::Undo;
    int line = 0;  ///< where the command starts
    ToolKind tool = ToolKind::Add;
    int value = 0;          ///< size K / zoom Z
    bool hasPoint = false;  ///< zoom with a centre
    core::Vec3 point{0.0};
    core::RigidTransform pose;       ///< object
    bool world = false;              ///< space
    std::vector<core::Vec3> points;  ///< stroke
};

struct Script {
    std::string source;
    std::vector<ScriptCommand> commands;
};

Script parseScript(std::string_view text, const std::string& sourceName);
Script loadScript(const std::filesystem::path& path);

}  // namespace vsculpt::app
