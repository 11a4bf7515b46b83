// SPDX-License-Identifier: MIT
#include "vsculpt/studio/SketchFileWriter.h"

#include "vsculpt/core/WriteFileAtomically.h"

#include <spdlog/spdlog.h>

namespace vsculpt::studio {

SketchFileWriter::SketchFileWriter(std::filesystem::path file, WriteFn write)
    : mFile(std::move(file)),
      mWrite(write ? std::move(write)
                   : WriteFn([](const std::filesystem::path& f, const std::string& text) {
                         core::writeFileAtomically(f, text, true);
                     })),
      mThread([this] { run(); }) {}

SketchFileWriter::~SketchFileWriter() {
    {
        const std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    mThread.join();
}

void SketchFileWriter::post(std::function<std::string()> compose) {
    {
        const std::lock_guard lock(mMutex);
        mPending = std::move(compose);
    }
    mWake.notify_one();
}

void SketchFileWriter::wait() {
    std::unique_lock lock(mMutex);
    mIdle.wait(lock, [&] { return !mPending && !mBusy; });
}

std::string SketchFileWriter::takeError() {
    const std::lock_guard lock(mMutex);
    return std::exchange(mError, std::string());
}

void SketchFileWriter::run() {
    std::unique_lock lock(mMutex);
    for (;;) {
        mWake.wait(lock, [&] { return mStop || mPending; });
        if (!mPending) return;  // stopping, everything written
        const std::function<std::string()> compose = std::move(mPending);
        mPending = nullptr;
        mBusy = true;
        lock.unlock();
        std::string error;
        try {
            mWrite(mFile, compose());
        } catch (const std::exception& e) {
            // The studio reports it on its own thread (takeError); logged here as well, for a
            // failure no later step asks about.
            error = e.what();
            spdlog::warn("the sketch was not saved: {}", error);
        }
        lock.lock();
        mBusy = false;
        if (!error.empty()) mError = error;
        mIdle.notify_all();
    }
}

}  // namespace vsculpt::studio
