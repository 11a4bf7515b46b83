// SPDX-License-Identifier: MIT
/// @file Log.h
/// @brief Where the program's messages go: spdlog's default logger, pointed at the error
/// stream runCli was given (stderr in the program, a string stream in tests), with levels
/// chosen by --quiet / --verbose. Libraries (devices, core) log through spdlog's default
/// logger and never write to std::cerr themselves.
///
/// A message reads `vsculpt play: error: TEXT` (errors), `vsculpt play: warning: TEXT`,
/// `vsculpt play: TEXT` (information) or `vsculpt play: debug: TEXT` (--verbose): the
/// logger's name is the command that runs.
#pragma once

#include <spdlog/spdlog.h>

#include <iosfwd>
#include <memory>
#include <string>

namespace vsculpt::app {

enum class Verbosity {
    Quiet,    ///< errors and warnings only; no progress bars
    Normal,   ///< plus information (what was written, summaries, progress bars)
    Verbose,  ///< plus debug messages (configuration chosen, timings, device traffic)
    Trace,    ///< plus trace messages (every device report, every rebuild)
};

/// While alive, spdlog's default logger writes to `err` at `verbosity` (thread-safe: device
/// reader threads log too). The previous default logger is restored on destruction, so the
/// stream must outlive this object and nothing logs to it afterwards.
class LogScope {
  public:
    LogScope(std::ostream& err, Verbosity verbosity, const std::string& name = "vsculpt");
    ~LogScope();
    LogScope(const LogScope&) = delete;
    LogScope& operator=(const LogScope&) = delete;

    /// Renames the messages' prefix (e.g. "vsculpt play" once the subcommand is known).
    void rename(const std::string& name);
    Verbosity verbosity() const { return mVerbosity; }
    /// Progress bars are information: shown unless --quiet (and only on a terminal).
    bool progressAllowed() const { return mVerbosity != Verbosity::Quiet; }

  private:
    std::shared_ptr<spdlog::logger> mPrevious;
    spdlog::sink_ptr mSink;
    Verbosity mVerbosity;
};

/// Logs each line of a multi-line text as its own message at `level` (empty lines skipped).
void logLines(spdlog::level::level_enum level, const std::string& text);

/// Seconds as people read them: "850 ms", "12.4 s", "3 min 05 s".
std::string formatDuration(double seconds);

}  // namespace vsculpt::app
