// SPDX-License-Identifier: MIT
/// @file ProgressBar.h
/// @brief A one-line progress bar for long runs (`play`, `render`): `[#####     ] 42 %
/// line 120, 3.1 s left`, redrawn in place at most ten times a second. Drawn only on a
/// terminal and not with --quiet (the caller decides: `enabled`); it erases itself when done
/// or before a message is logged (clear()), so messages never land in the middle of it.
#pragma once

#include <chrono>
#include <iosfwd>
#include <string>

namespace vsculpt::app {

class ProgressBar {
  public:
    /// `total` units of work (0: nothing is drawn); `what` names them ("line", "row").
    ProgressBar(std::ostream& out, bool enabled, size_t total, std::string what);
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    /// `done` of the total are finished; `at` is shown after `what` (e.g. the script line).
    void update(size_t done, long at);
    /// Erases the bar (it comes back at the next update).
    void clear();

  private:
    std::ostream& mOut;
    bool mEnabled, mDrawn = false;
    size_t mTotal;
    std::string mWhat;
    std::chrono::steady_clock::time_point mStart, mLast{};
};

/// Whether standard error is a terminal (progress bars are drawn only there).
bool stderrIsTerminal();

}  // namespace vsculpt::app
