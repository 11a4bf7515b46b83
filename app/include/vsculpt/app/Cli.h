// SPDX-License-Identifier: MIT
/// @file Cli.h
/// @brief The `vsculpt` command line. main() only forwards to runCli().
#pragma once

#include <iosfwd>

namespace vsculpt::app {

/// Parses arguments, runs the requested job and returns the process exit code:
/// 0 success, 1 runtime failure, 2 bad input (arguments, config). Messages go to `out`/`err`.
int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace vsculpt::app
