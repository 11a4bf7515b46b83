// SPDX-License-Identifier: MIT
/// @file JsonNesting.h
/// @brief How deep JSON text nests, found before it is parsed: nlohmann::json parses any
/// depth, but writing a value back (dump(), which error messages and the sketch file's loader
/// use) recurses once per level, so a file of 200 000 nested arrays overflowed the stack.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace vsculpt::core {

/// Deeper than any file vsculpt writes (a config nests 4 levels, a sketch file 8) by far.
inline constexpr int kMaxJsonNesting = 64;

/// Where `text` opens level maxDepth + 1 (the `[` or `{`), as "LINE:COLUMN: nested more than
/// N levels deep" (both 1-based) for a message that names the file before it; nullopt when the
/// text nests no deeper. Brackets inside strings (with their escapes) and inside `//` and
/// `/* */` comments do not count; anything else is left to the parser to judge.
std::optional<std::string> jsonNestingBeyond(std::string_view text, int maxDepth = kMaxJsonNesting);

}  // namespace vsculpt::core
