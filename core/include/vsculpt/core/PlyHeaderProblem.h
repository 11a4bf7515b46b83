// SPDX-License-Identifier: MIT
/// @file PlyHeaderProblem.h
/// @brief A PLY file's header checked before Assimp reads the file: Debian's Assimp 5.2
/// loops forever on a header cut short (`ply`, `format ascii 1.0`, then the end of the file)
/// and crashes on damaged header lines, where the sculptor wants an error that names the line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace vsculpt::core {

/// Why a PLY file cannot be what its header says, as "LINE: what" (1-based), or "" when the
/// header is well formed: the `ply` line, one `format` line (ascii, binary_little_endian or
/// binary_big_endian, version 1.0), `comment` and `obj_info` lines, `element NAME COUNT` and
/// `property TYPE NAME` / `property list TYPE TYPE NAME` lines with the PLY types, and
/// `end_header` within the first 64 KiB, all printable ASCII. A binary file must also be long
/// enough for its elements (each list counted as empty). `start` is the file's first bytes
/// (kMaxPlyHeaderBytes of them, or all of a shorter file), `fileBytes` its whole size: the
/// importer reads only the start, Assimp reads the file.
inline constexpr size_t kMaxPlyHeaderBytes = 64 * 1024;
std::string plyHeaderProblem(std::string_view start, uint64_t fileBytes);
/// The same for a file held whole in `bytes`.
inline std::string plyHeaderProblem(std::string_view bytes) {
    return plyHeaderProblem(bytes, bytes.size());
}

}  // namespace vsculpt::core
