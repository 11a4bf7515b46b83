// SPDX-License-Identifier: MIT
/// @file Cli.h
/// @brief The `vsculpt` command line. main() only forwards to runCli().
#pragma once

#include <iosfwd>

namespace vsculpt::app {

/// Parses arguments, runs the requested job and returns the process exit code:
/// 0 success, 1 runtime failure, 2 bad input (arguments, config). Messages go to `out`/`err`.
int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

/// For main(): SIGINT, SIGTERM and SIGHUP (where not ignored) first remove the temporary files
/// of writes in progress (core::removeTemporaryFilesInProgress), then end the process as they
/// would have: Ctrl-C during an export leaves neither the export nor a hidden temporary file.
void removeTemporaryFilesOnInterrupt();

}  // namespace vsculpt::app
