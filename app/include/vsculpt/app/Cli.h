// SPDX-License-Identifier: MIT
/// @file Cli.h
/// @brief The `vsculpt` command line. main() only forwards to runCli().
#pragma once

#include <iosfwd>

namespace vsculpt::app {

/// Parses arguments, runs the requested job and returns the process exit code:
/// 0 success, 1 runtime failure, 2 bad input (arguments, config). Messages go to `out`/`err`.
int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

/// `code`, unless what was written to standard output (std::cout, stdio) did not all reach it
/// (a full disk, a closed descriptor): then 1, after saying why on standard error, as Unix
/// tools do, so `vsculpt info > /dev/full` fails instead of losing its output silently.
int standardOutputChecked(int code);

}  // namespace vsculpt::app
