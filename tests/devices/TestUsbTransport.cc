// SPDX-License-Identifier: MIT
// The libusb transport for real, against USB devices emulated by umockdev: reports come out
// in order and byte-exact, unplug gives Left, plugging back resumes, commands reach the
// device. Runs under umockdev-wrapper (tests/devices/CMakeLists.txt).
#include "UsbMock.h"

#include "vsculpt/devices/SpaceMouse.h"
#include "vsculpt/devices/UsbTransport.h"

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <thread>

namespace vsculpt::devices {
namespace {

using test::UsbMock;

// Collects events until `done` says so or 20 s pass (a hang is a failure, not a timing
// assertion: on a healthy run everything arrives in milliseconds).
bool collectUntil(EventQueue& q, std::vector<DeviceEvent>& all,
                  const std::function<bool(const std::vector<DeviceEvent>&)>& done) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
        q.drain(all);
        if (done(all)) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
}

size_t count(const std::vector<DeviceEvent>& events, DeviceEventKind kind) {
    size_t n = 0;
    for (const auto& e : events)
        n += e.kind == kind;
    return n;
}

std::vector<uint8_t> translationReport(int16_t x, int16_t y, int16_t z) {
    return {0x01,
            uint8_t(x),
            uint8_t(uint16_t(x) >> 8),
            uint8_t(y),
            uint8_t(uint16_t(y) >> 8),
            uint8_t(z),
            uint8_t(uint16_t(z) >> 8)};
}

TransportOptions spaceMouseOptions() {
    TransportOptions o;
    DeviceRule r;
    r.name = "spacemouse";
    r.vendor = 0x046d;
    r.products = {0xc626};
    r.driver = DeviceDriver::SpaceMouse;
    r.access = DeviceAccess::Libusb;
    o.rules = {r};
    o.transfersInFlight = 3;
    o.rescanIntervalS = 0.05;
    return o;
}

class UsbTransportTest : public ::testing::Test {
  protected:
    void SetUp() override {
        if (!UsbMock::available()) GTEST_SKIP() << "needs umockdev-wrapper (run through ctest)";
    }
};

TEST_F(UsbTransportTest, SpaceMouseReportsArriveInOrderAndByteExact) {
    UsbMock mouse(1, 5, test::hidDescriptors(0x046d, 0xc626, 7, 0));
    std::vector<std::vector<uint8_t>> sentReports;
    for (int i = 0; i < 50; ++i) {
        sentReports.push_back(translationReport(int16_t(i * 7 - 175), int16_t(-i), int16_t(i * 3)));
        mouse.queueIn(sentReports.back());
    }
    mouse.plug();

    EventQueue q;
    UsbTransport transport(spaceMouseOptions(), q);
    transport.start();
    std::vector<DeviceEvent> events;
    ASSERT_TRUE(collectUntil(q, events,
                             [](const auto& e) { return count(e, DeviceEventKind::Report) >= 50; }))
        << "reports seen: " << count(events, DeviceEventKind::Report);

    ASSERT_EQ(events.front().kind, DeviceEventKind::Arrived);
    EXPECT_EQ(events.front().device, "spacemouse");
    std::vector<std::vector<uint8_t>> got;
    int64_t lastTime = 0;
    for (const auto& e : events) {
        if (e.kind != DeviceEventKind::Report) continue;
        got.push_back(e.bytes);
        EXPECT_GE(e.timeNs, lastTime);
        lastTime = e.timeNs;
    }
    EXPECT_EQ(got, sentReports);
    // And they decode to what was built.
    const auto sample = decodeSpaceMouseReport(got[10], 0);
    ASSERT_TRUE(sample.has_value());
    EXPECT_EQ(sample->translation[0], 10 * 7 - 175);
    EXPECT_EQ(sample->translation[1], -10);
    EXPECT_EQ(sample->translation[2], 30);

    const auto open = transport.connected();
    ASSERT_EQ(open.size(), 1u);
    EXPECT_EQ(open[0].counters.reports, 50u);
    EXPECT_EQ(open[0].counters.bytes, 350u);
}

TEST_F(UsbTransportTest, UnplugGivesLeftAndReplugResumes) {
    UsbMock mouse(1, 6, test::hidDescriptors(0x046d, 0xc626, 7, 0));
    for (int i = 0; i < 5; ++i)
        mouse.queueIn(translationReport(1, 2, int16_t(i)));
    mouse.plug();

    EventQueue q;
    UsbTransport transport(spaceMouseOptions(), q);
    transport.start();
    std::vector<DeviceEvent> events;
    ASSERT_TRUE(collectUntil(q, events,
                             [](const auto& e) { return count(e, DeviceEventKind::Report) >= 5; }));

    mouse.unplug();
    ASSERT_TRUE(collectUntil(q, events,
                             [](const auto& e) { return count(e, DeviceEventKind::Left) >= 1; }));
    EXPECT_EQ(events.back().kind, DeviceEventKind::Left);
    EXPECT_TRUE(transport.connected().empty());

    for (int i = 0; i < 4; ++i)
        mouse.queueIn(translationReport(9, 9, int16_t(100 + i)));
    mouse.plug();
    ASSERT_TRUE(collectUntil(q, events,
                             [](const auto& e) { return count(e, DeviceEventKind::Report) >= 9; }))
        << "arrivals: " << count(events, DeviceEventKind::Arrived);
    EXPECT_EQ(count(events, DeviceEventKind::Arrived), 2u);
    EXPECT_EQ(events.back().bytes, translationReport(9, 9, 103));
}

TEST_F(UsbTransportTest, CommandsAndFeatureReportsReachTheDevice) {
    // A bulk device with an OUT endpoint, like a tracker.
    UsbMock tracker(1, 7, test::hidDescriptors(0x0f44, 0xff20, 64, 64, /*bulk=*/true));
    tracker.plug();
    EventQueue q;
    TransportOptions o = spaceMouseOptions();
    o.rules[0].name = "tracker";
    o.rules[0].vendor = 0x0f44;
    o.rules[0].products = {0xff20};
    o.rules[0].driver = DeviceDriver::Polhemus;
    UsbTransport transport(o, q);
    EXPECT_EQ(transport.sendOutput("tracker", std::vector<uint8_t>{'P'}), SendStatus::NotConnected);
    transport.start();
    std::vector<DeviceEvent> events;
    ASSERT_TRUE(collectUntil(
        q, events, [](const auto& e) { return count(e, DeviceEventKind::Arrived) >= 1; }));

    const std::vector<uint8_t> command = {'C', '\r'};
    EXPECT_EQ(transport.sendOutput("tracker", command), SendStatus::Ok);
    const std::vector<uint8_t> feature = {0x02, 0xaa, 0xbb};
    EXPECT_EQ(transport.sendFeature("tracker", feature), SendStatus::Ok);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (tracker.sent().size() < 2 && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const auto sent = tracker.sent();
    ASSERT_EQ(sent.size(), 2u);
    EXPECT_EQ(sent[0], command);
    // SET_REPORT(feature, id 2) to interface 0, then the report.
    const std::vector<uint8_t> setup = {0x21, 0x09, 0x02, 0x03, 0x00, 0x00,
                                        0x03, 0x00, 0x02, 0xaa, 0xbb};
    EXPECT_EQ(sent[1], setup);
}

}  // namespace
}  // namespace vsculpt::devices
