// SPDX-License-Identifier: MIT
/// @file PlyHeaderProblem.h
/// @brief A PLY file's header checked before Assimp reads the file: Debian's Assimp 5.2
/// loops forever on a header cut short (`ply`, `format ascii 1.0`, then the end of the file)
/// and crashes on damaged header lines, where the sculptor wants an error that names the line.
#pragma once

#include <string>
#include <string_view>

namespace vsculpt::core {

/// Why the PLY file whose bytes begin with `bytes` (the whole file, or at least its header and
/// the size of the rest) cannot be what its header says, as "LINE: what" (1-based), or "" when
/// the header is well formed: the `ply` line, one `format` line (ascii, binary_little_endian or
/// binary_big_endian, version 1.0), `comment` and `obj_info` lines, `element NAME COUNT` and
/// `property TYPE NAME` / `property list TYPE TYPE NAME` lines with the PLY types, and
/// `end_header` within the first 64 KiB, all printable ASCII. A binary file must also be long
/// enough for its elements (each list counted as empty).
std::string plyHeaderProblem(std::string_view bytes);

}  // namespace vsculpt::core
