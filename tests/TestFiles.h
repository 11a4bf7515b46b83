// SPDX-License-Identifier: MIT
/// @file TestFiles.h
/// @brief Whole files as bytes, for tests that damage, compare or inspect what was written.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace vsculpt::test {

/// The file's bytes ("" when it cannot be read: the caller's assertions then fail).
inline std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Replaces the file's bytes.
inline void writeFile(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace vsculpt::test
