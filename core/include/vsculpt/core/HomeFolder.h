// SPDX-License-Identifier: MIT
/// @file HomeFolder.h
/// @brief The user's home folder, for the per-user config and data folders.
#pragma once

#include <filesystem>

namespace vsculpt::core {

/// $HOME when set and absolute, else the home folder of this process's user in the password
/// database (a session started with `env -i`, a service, sudo -H), else empty. Never a folder
/// shared with other users: with HOME unset, projects went to /tmp/vsculpt, where another
/// user's session could continue them (found by QA).
std::filesystem::path homeFolder();

}  // namespace vsculpt::core
