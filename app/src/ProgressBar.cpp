// SPDX-License-Identifier: MIT
#include "vsculpt/app/ProgressBar.h"

#include "vsculpt/app/Log.h"

#include <unistd.h>

#include <ostream>

namespace vsculpt::app {

ProgressBar::ProgressBar(std::ostream& out, bool enabled, size_t total, std::string what)
    : mOut(out),
      mEnabled(enabled && total > 0),
      mTotal(total),
      mWhat(std::move(what)),
      mStart(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
    clear();
}

void ProgressBar::update(size_t done, long at) {
    if (!mEnabled) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < mTotal && now - mLast < std::chrono::milliseconds(100)) return;
    mLast = now;
    const double fraction = double(std::min(done, mTotal)) / double(mTotal);
    const int width = 30, filled = int(fraction * width);
    std::string line =
        "\r[" + std::string(size_t(filled), '#') + std::string(size_t(width - filled), ' ') + "] " +
        std::to_string(int(fraction * 100)) + " % " + mWhat + " " + std::to_string(at);
    // The remaining time, once there is enough behind us to estimate it.
    const double elapsed = std::chrono::duration<double>(now - mStart).count();
    if (fraction > 0.02 && elapsed > 1.0 && done < mTotal)
        line += ", " + formatDuration(elapsed * (1 - fraction) / fraction) + " left";
    line += "   ";
    mOut << line << std::flush;
    mDrawn = true;
}

void ProgressBar::clear() {
    if (!mDrawn) return;
    mOut << "\r" << std::string(72, ' ') << "\r" << std::flush;
    mDrawn = false;
}

bool stderrIsTerminal() {
    return ::isatty(2) == 1;
}

}  // namespace vsculpt::app
