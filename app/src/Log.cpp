// SPDX-License-Identifier: MIT
#include "vsculpt/app/Log.h"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/ostream_sink.h>

#include <cmath>
#include <cstdio>
#include <string_view>

namespace vsculpt::app {

namespace {

// "%*": the level as the message's first word, except for information, which needs none
// (the GNU convention `program: error: text`).
class LevelWord final : public spdlog::custom_flag_formatter {
  public:
    void format(const spdlog::details::log_msg& msg, const std::tm&,
                spdlog::memory_buf_t& dest) override {
        std::string_view word;
        switch (msg.level) {
            case spdlog::level::trace:
                word = "trace: ";
                break;
            case spdlog::level::debug:
                word = "debug: ";
                break;
            case spdlog::level::warn:
                word = "warning: ";
                break;
            case spdlog::level::err:
                word = "error: ";
                break;
            case spdlog::level::critical:
                word = "fatal: ";
                break;
            default:
                break;
        }
        dest.append(word.data(), word.data() + word.size());
    }
    std::unique_ptr<custom_flag_formatter> clone() const override {
        return std::make_unique<LevelWord>();
    }
};

spdlog::level::level_enum levelFor(Verbosity v) {
    switch (v) {
        case Verbosity::Quiet:
            return spdlog::level::warn;
        case Verbosity::Normal:
            return spdlog::level::info;
        case Verbosity::Verbose:
            return spdlog::level::debug;
        case Verbosity::Trace:
            return spdlog::level::trace;
    }
    return spdlog::level::info;
}

std::shared_ptr<spdlog::logger> makeLogger(const std::string& name, spdlog::sink_ptr sink,
                                           Verbosity v) {
    auto logger = std::make_shared<spdlog::logger>(name, std::move(sink));
    auto formatter = std::make_unique<spdlog::pattern_formatter>();
    formatter->add_flag<LevelWord>('*').set_pattern("%n: %*%v");
    logger->set_formatter(std::move(formatter));
    logger->set_level(levelFor(v));
    // Messages are rare and a crash must not swallow the last ones.
    logger->flush_on(spdlog::level::trace);
    return logger;
}

}  // namespace

LogScope::LogScope(std::ostream& err, Verbosity verbosity, const std::string& name)
    : mPrevious(spdlog::default_logger()),
      mSink(std::make_shared<spdlog::sinks::ostream_sink_mt>(err, /*force_flush=*/true)),
      mVerbosity(verbosity) {
    spdlog::set_default_logger(makeLogger(name, mSink, verbosity));
}

LogScope::~LogScope() {
    spdlog::set_default_logger(mPrevious);
}

void LogScope::rename(const std::string& name) {
    spdlog::set_default_logger(makeLogger(name, mSink, mVerbosity));
}

void logLines(spdlog::level::level_enum level, const std::string& text) {
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        if (end > start)
            spdlog::log(level, "{}", std::string_view(text).substr(start, end - start));
        start = end + 1;
    }
}

std::string formatDuration(double seconds) {
    char b[64];
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    if (seconds < 1.0) {
        std::snprintf(b, sizeof b, "%.0f ms", seconds * 1e3);
    } else if (seconds < 60.0) {
        std::snprintf(b, sizeof b, "%.1f s", seconds);
    } else {
        const long total = std::lround(seconds);
        if (total < 3600)
            std::snprintf(b, sizeof b, "%ld min %02ld s", total / 60, total % 60);
        else
            std::snprintf(b, sizeof b, "%ld h %02ld min", total / 3600, (total % 3600) / 60);
    }
    return b;
}

}  // namespace vsculpt::app
