// SPDX-License-Identifier: MIT
/// @file SketchFileWriter.h
/// @brief Writes a project's sketch.json on a thread of its own, so that a sketch step never
/// waits for the file: its text grows with every stroke drawn (7 MB after 600 strokes of 120
/// samples) and took the step 78 ms on average to compose and flush (docs/projects.md).
#pragma once

#include <condition_variable>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace vsculpt::studio {

class SketchFileWriter {
  public:
    /// How the text is put in the file: core::writeFileAtomically, durable, unless given
    /// (tests hold it, or fail it). Throws to report a failure.
    using WriteFn = std::function<void(const std::filesystem::path&, const std::string&)>;
    explicit SketchFileWriter(std::filesystem::path file, WriteFn write = {});
    /// Writes what was posted last, then stops.
    ~SketchFileWriter();
    SketchFileWriter(const SketchFileWriter&) = delete;
    SketchFileWriter& operator=(const SketchFileWriter&) = delete;

    /// Hands over the file's next contents, composed on the writer's thread (`compose` must
    /// own what it reads: a copy of the studio's state). Only the latest pending one is
    /// written: a state a newer one replaced before its turn is skipped. Written atomically
    /// and durably (core::writeFileAtomically).
    void post(std::function<std::string()> compose);
    /// Waits until what was posted is written.
    void wait();
    /// Why the last write failed ("" when it did not), handed out once.
    std::string takeError();

  private:
    void run();

    const std::filesystem::path mFile;
    const WriteFn mWrite;
    std::mutex mMutex;
    std::condition_variable mWake, mIdle;
    std::function<std::string()> mPending;
    bool mBusy = false, mStop = false;
    std::string mError;
    std::thread mThread;
};

}  // namespace vsculpt::studio
