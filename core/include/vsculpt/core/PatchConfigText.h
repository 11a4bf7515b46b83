// SPDX-License-Identifier: MIT
/// @file PatchConfigText.h
/// @brief Saves a config into the text of an existing config file, keeping what the user wrote
/// there: comments, order and layout of every value that stays.
#pragma once

#include "vsculpt/core/Config.h"

#include <string>
#include <string_view>

namespace vsculpt::core {

/// Returns `fileText` (a config file: JSON with comments) changed so that parseConfig reads
/// it back to `cfg`: each value that differs is replaced where it stands; a key the file lacks
/// is added at the end of its section only where `cfg` differs from the built-in default (the
/// value the file gave it by leaving it out). Text the values do not need is untouched, byte
/// for byte. Throws ConfigError naming `sourceName` and the line when `fileText` is not valid
/// JSON or not an object.
std::string patchConfigText(std::string_view fileText, const SculptConfig& cfg,
                            const std::string& sourceName);

}  // namespace vsculpt::core
