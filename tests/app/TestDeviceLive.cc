// SPDX-License-Identifier: MIT
// The whole device path live, without hardware: a Polhemus Liberty HS emulated by umockdev
// streams pen records through the real libusb transport into `vsculpt record`, which sculpts
// and writes a recording; `vsculpt play` of that recording must give the same sculpture (mesh
// hash) as the live run. Runs under umockdev-wrapper.
#include "../devices/UsbMock.h"
#include "DeviceReports.h"

#include "vsculpt/app/DeviceCommands.h"
#include "vsculpt/app/Play.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/devices/Polhemus.h"
#include "vsculpt/studio/Session.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

using namespace vsculpt;
namespace fs = std::filesystem;

namespace {

std::string meshHashIn(const std::string& text) {
    std::smatch m;
    const std::regex re("mesh hash ([0-9a-f]{16})");
    return std::regex_search(text, m, re) ? m[1].str() : std::string();
}

TEST(DeviceLive, RecordThenReplayGivesTheLiveSculpture) {
    if (!devices::test::UsbMock::available())
        GTEST_SKIP() << "needs umockdev-wrapper (run through ctest)";
    const fs::path dir = fs::temp_directory_path() / ("vsculpt-live-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path configPath = dir / "config.json";
    {
        std::ofstream c(configPath);
        c << R"({
  "initial_sphere": {"radius_mm": 30},
  "polygonizer": {"grid_n": 32},
  "devices": {"rescan_interval_s": 0.05,
              "match": [{"name": "tracker", "driver": "polhemus", "access": "libusb",
                         "vendor": "0x0f44", "products": ["0xff20"]}]}
})";
    }
    // A Liberty HS (bulk IN and OUT). Like the real one, it streams only once the start-up
    // commands have arrived.
    devices::test::UsbMock tracker(
        1, 9, devices::test::hidDescriptors(0x0f44, 0xff20, 64, 64, /*bulk=*/true));
    tracker.plug();
    const auto model = devices::findPolhemusModel(0x0f44, 0xff20);
    ASSERT_TRUE(model);
    const auto expected = devices::polhemusStartupCommands(devices::defaultPolhemusConfig(*model));

    app::RecordOptions rec;
    rec.outPath = (dir / "session.vsrec").string();
    rec.configPath = configPath.string();
    rec.untilUnplugged = true;
    rec.seconds = 60;  // a safety net: the run ends at the unplug
    std::ostringstream recOut, recErr;
    int recCode = -1;
    std::thread recorder([&] { recCode = app::runRecord(rec, recOut, recErr); });

    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (tracker.sent().size() < expected.size() && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    // 60 pen records across the top of the sphere, in 64-byte USB reads that cut records
    // anywhere.
    test::Bytes stream;
    for (int i = 0; i < 60; ++i) {
        const auto r =
            test::libertyRecord(1, -3.0 + 0.1 * i, 0.2 * std::sin(i * 0.3), 3.1, uint32_t(i));
        stream.insert(stream.end(), r.begin(), r.end());
    }
    for (size_t i = 0; i < stream.size(); i += 64)
        tracker.queueIn(
            test::Bytes(stream.begin() + i, stream.begin() + std::min(stream.size(), i + 64)));
    while (!tracker.drained() && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_TRUE(tracker.drained());
    tracker.unplug();
    recorder.join();
    ASSERT_EQ(recCode, 0) << recErr.str();
    EXPECT_NE(recErr.str().find("tracker connected"), std::string::npos) << recErr.str();
    EXPECT_NE(recErr.str().find("tracker disconnected"), std::string::npos) << recErr.str();
    EXPECT_NE(recErr.str().find("tracker: 43 reports, 60 samples"), std::string::npos)
        << recErr.str();

    // The start-up commands reached the tracker, in order.
    const auto sent = tracker.sent();
    ASSERT_EQ(sent.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i)
        EXPECT_EQ(sent[i], expected[i]) << "command " << i;

    const std::string live = meshHashIn(recErr.str());
    ASSERT_FALSE(live.empty()) << recErr.str();

    app::PlayOptions play;
    play.script = rec.outPath;
    play.progress = false;
    play.check = true;
    std::ostringstream playOut, playErr;
    ASSERT_EQ(app::runPlay(play, playOut, playErr), 0) << playErr.str();
    EXPECT_EQ(meshHashIn(playErr.str()), live) << playErr.str();

    // And the pen did sculpt: the live sculpture is not the initial sphere.
    core::SculptConfig cfg = core::loadConfig(configPath);
    studio::Session fresh(cfg);
    char initial[17];
    std::snprintf(initial, sizeof initial, "%016llx",
                  static_cast<unsigned long long>(core::canonicalMeshHash(fresh.wholeMesh())));
    EXPECT_NE(live, initial);
    fs::remove_all(dir);
}

}  // namespace
