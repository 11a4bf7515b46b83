// SPDX-License-Identifier: MIT
// sketch.json is written on a thread of its own: a sketch step posts the file's next state and
// goes on. Before, each step composed and flushed the whole file itself: 78 ms a step on
// average over 600 pen strokes (docs/projects.md).
#include "vsculpt/studio/SketchFileWriter.h"

#include <gtest/gtest.h>

#include <future>
#include <stdexcept>
#include <string>
#include <vector>

using vsculpt::studio::SketchFileWriter;

namespace {

/// Records what was written, holding the first write until released.
struct HeldDisk {
    std::promise<void> release;
    std::shared_future<void> released = release.get_future().share();
    std::promise<void> firstStarted;
    std::mutex mutex;
    std::vector<std::string> written;
    SketchFileWriter::WriteFn fn() {
        return [this](const std::filesystem::path&, const std::string& text) {
            bool first;
            {
                const std::lock_guard lock(mutex);
                first = written.empty();
            }
            if (first) {
                firstStarted.set_value();
                released.wait();
            }
            const std::lock_guard lock(mutex);
            written.push_back(text);
        };
    }
};

}  // namespace

// Posting never waits for a write in progress (it would hang here: the first write is held
// until every post has returned), and of the states posted meanwhile only the latest is
// written: a sketch step's file follows the studio without a backlog of stale copies.
TEST(SketchFileWriter, PostsNeverWaitAndOnlyTheLatestPendingStateIsWritten) {
    HeldDisk disk;
    std::vector<std::string> composed;
    std::mutex composedMutex;
    {
        SketchFileWriter writer("sketch.json", disk.fn());
        auto state = [&](std::string text) {
            return [&composed, &composedMutex, text] {
                const std::lock_guard lock(composedMutex);
                composed.push_back(text);
                return text;
            };
        };
        writer.post(state("step 1"));
        disk.firstStarted.get_future().wait();  // step 1 is being written, and held
        for (int k = 2; k <= 5; ++k)
            writer.post(state("step " + std::to_string(k)));
        disk.release.set_value();
        writer.wait();
        EXPECT_EQ(disk.written, (std::vector<std::string>{"step 1", "step 5"}));
        EXPECT_EQ(composed, (std::vector<std::string>{"step 1", "step 5"}));  // 2-4 never built
        writer.post(state("step 6"));
    }  // the destructor writes what is pending
    EXPECT_EQ(disk.written.back(), "step 6");
}

// A failed write is handed out once by takeError (the studio tells the sculptor at the next
// step); the next state is written as usual.
TEST(SketchFileWriter, AFailedWriteIsReportedOnceAndTheNextStateIsWritten) {
    std::vector<std::string> written;
    bool fail = true;
    SketchFileWriter writer("dir/sketch.json",
                            [&](const std::filesystem::path& file, const std::string& text) {
                                if (fail) throw std::runtime_error(file.string() + ": disk full");
                                written.push_back(text);
                            });
    writer.post([] { return std::string("a"); });
    writer.wait();
    EXPECT_EQ(writer.takeError(), "dir/sketch.json: disk full");
    EXPECT_EQ(writer.takeError(), "");
    fail = false;
    writer.post([] { return std::string("b"); });
    writer.wait();
    EXPECT_EQ(writer.takeError(), "");
    EXPECT_EQ(written, std::vector<std::string>{"b"});
}
