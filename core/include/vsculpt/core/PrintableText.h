// SPDX-License-Identifier: MIT
/// @file PrintableText.h
/// @brief Text from files and devices made safe to show: a message that quotes what it could
/// not read must not write raw bytes (an ELF header, escape sequences) to the terminal.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace vsculpt::core {

/// `text` with control characters, DEL and bytes that are not part of valid UTF-8 written
/// as \xNN (tab kept as \t), and cut to `maxBytes` with "..." when longer.
std::string printableText(std::string_view text, size_t maxBytes = 80);

/// The offset of the first byte that says `text` is not a text file (a NUL, or a control
/// character other than tab, CR, LF, FF), or nullopt for text.
std::optional<size_t> firstBinaryByte(std::string_view text);

}  // namespace vsculpt::core
