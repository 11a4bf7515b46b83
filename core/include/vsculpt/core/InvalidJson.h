// SPDX-License-Identifier: MIT
/// @file InvalidJson.h
/// @brief The message for JSON text that nlohmann::json refused: the file, the line and
/// column where the parser stopped, and what it found, without the library's exception ids
/// ("[json.exception.parse_error.101]") or its own second position.
#pragma once

#include <exception>
#include <string>
#include <string_view>

namespace vsculpt::core {

/// "NAME:LINE:COLUMN: invalid JSON: WHAT" (both 1-based) for an exception that
/// nlohmann::json::parse threw on `text`: a syntax error where the parser stopped, a number
/// past a double's range (1e400) where that number is. Other exceptions: "NAME: invalid
/// JSON: WHAT". WHAT is printable (control bytes escaped) and at most about 240 bytes.
std::string invalidJsonMessage(const std::string& name, std::string_view text,
                               const std::exception& e);

}  // namespace vsculpt::core
