// SPDX-License-Identifier: MIT
// The hidraw transport for real against a hidraw node emulated by umockdev (sysfs entries +
// a read script): the device is found by its HID_ID, reports come out one per read in order,
// removal gives Left, a new node gives Arrived again. Runs under umockdev-wrapper.
#include "vsculpt/devices/HidrawTransport.h"

#include <gtest/gtest.h>
#include <umockdev.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include <unistd.h>

namespace vsculpt::devices {
namespace {

bool umockdevLoaded() {
    const char* preload = std::getenv("LD_PRELOAD");
    return preload && std::strstr(preload, "umockdev");
}

size_t count(const std::vector<DeviceEvent>& events, DeviceEventKind kind) {
    size_t n = 0;
    for (const auto& e : events)
        n += e.kind == kind;
    return n;
}

bool waitFor(EventQueue& q, std::vector<DeviceEvent>& all, DeviceEventKind kind, size_t n) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
        q.drain(all);
        if (count(all, kind) >= n) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
}

// umockdev script data: bytes < 32 and '^' are escaped (script-format.txt).
std::string scriptData(const std::vector<uint8_t>& bytes) {
    std::string s;
    for (uint8_t b : bytes) {
        if (b == '^')
            s += "^`";
        else if (b < 32)
            s += {'^', char(b + 64)};
        else
            s += char(b);
    }
    return s;
}

// Node n sits on USB port 8+n: a replugged device appears at another port with another hidraw
// number, as it may with the kernel.
std::string usbInterface(int node) {
    const std::string port = "1-" + std::to_string(8 + node);
    return "/devices/usb1/" + port + "/" + port + ":1.0";
}

std::string sysPath(int node) {
    return "/sys" + usbInterface(node) + "/0003:256F:C635.000" + std::to_string(node + 1) +
           "/hidraw/hidraw" + std::to_string(node);
}

// The start of a multi-axis controller's report descriptor (Generic Desktop, Multi-axis
// Controller, Collection (Application), End Collection): the transport passes it on.
constexpr const char* kDescriptorHex = "05010908A101C0";
const std::vector<uint8_t> kDescriptor{0x05, 0x01, 0x09, 0x08, 0xA1, 0x01, 0xC0};

// A SpaceMouse Compact's hidraw node `hidraw<node>` (a replugged device gets a new number, as
// with the kernel) with a script of input reports.
void addSpaceMouse(UMockdevTestbed* tb, const std::vector<std::vector<uint8_t>>& reports,
                   int node) {
    GError* error = nullptr;
    const std::string n = std::to_string(node);
    const std::string hid = usbInterface(node) + "/0003:256F:C635.000" + std::to_string(node + 1);
    const std::string text =
        "P: " + sysPath(node).substr(4) + "\nN: hidraw" + n +
        "\nE: SUBSYSTEM=hidraw\nE: DEVNAME=/dev/hidraw" + n + "\n\nP: " + hid +
        "\nE: SUBSYSTEM=hid\nE: HID_ID=0003:0000256F:0000C635\n"
        "E: HID_NAME=3Dconnexion SpaceMouse Compact\nH: report_descriptor=" +
        std::string(kDescriptorHex) + "\n\nP: " + usbInterface(node) +
        "\nE: SUBSYSTEM=usb\nE: DEVTYPE=usb_interface\nA: bInterfaceNumber=00\\n\n";
    ASSERT_TRUE(umockdev_testbed_add_from_string(tb, text.c_str(), &error)) << error->message;
    const std::string script =
        (std::filesystem::temp_directory_path() /
         ("vsculpt-hidraw-" + std::to_string(::getpid()) + "-" + n + ".script"))
            .string();
    {
        std::ofstream out(script);
        // 40 ms apart: umockdev emulates the node as a stream, so reports the reader has not
        // taken yet would come out of one read() together (a kernel hidraw node never merges
        // reports); under full CPU load 1 ms apart did merge.
        for (const auto& r : reports)
            out << "r 40 " << scriptData(r) << "\n";
    }
    ASSERT_TRUE(
        umockdev_testbed_load_script(tb, ("/dev/hidraw" + n).c_str(), script.c_str(), &error))
        << error->message;
}

TEST(HidrawTransport, ParsesHidIdLines) {
    uint16_t bus = 0, vendor = 0, product = 0;
    EXPECT_TRUE(parseHidId("DRIVER=hid-generic\nHID_ID=0003:0000256F:0000C635\nHID_NAME=x\n", bus,
                           vendor, product));
    EXPECT_EQ(bus, 3);
    EXPECT_EQ(vendor, 0x256f);
    EXPECT_EQ(product, 0xc635);
    EXPECT_FALSE(parseHidId("HID_NAME=x\n", bus, vendor, product));
    EXPECT_FALSE(parseHidId("HID_ID=0003:0000256F\n", bus, vendor, product));
    EXPECT_FALSE(parseHidId("HID_ID=0003:0001256F:0000C635\n", bus, vendor, product));  // > 16 bits
    EXPECT_FALSE(parseHidId("HID_ID=zz03:0000256F:0000C635\n", bus, vendor, product));
}

TEST(HidrawTransport, ReadsReportsFollowsRemovalAndReturn) {
    if (!umockdevLoaded()) GTEST_SKIP() << "needs umockdev-wrapper (run through ctest)";
    UMockdevTestbed* tb = umockdev_testbed_new();
    // Reports with bytes that need escaping (0, '^', 32) to check the data path byte for byte.
    std::vector<std::vector<uint8_t>> reports = {{0x01, 0x00, 0x5e, 0x20, 0xff, 0x10, 0x80},
                                                 {0x02, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06},
                                                 {0x03, 0x01, 0x00}};
    addSpaceMouse(tb, reports, 0);

    DeviceRule rule;
    rule.name = "spacemouse";
    rule.vendor = 0x256f;
    rule.products = {0xc635};
    rule.access = DeviceAccess::Hidraw;
    TransportOptions o;
    o.rules = {rule};
    o.rescanIntervalS = 0.05;
    EventQueue q;
    {
        HidrawTransport transport(o, q);
        transport.start();
        std::vector<DeviceEvent> events;
        ASSERT_TRUE(waitFor(q, events, DeviceEventKind::Report, 3));
        ASSERT_EQ(events.front().kind, DeviceEventKind::Arrived);
        // The arrival carries the ids and the report descriptor read from sysfs, byte-exact.
        EXPECT_EQ(events.front().bytes, arrivalBytes(0x256f, 0xc635, kDescriptor));
        std::vector<std::vector<uint8_t>> got;
        for (const auto& e : events)
            if (e.kind == DeviceEventKind::Report) got.push_back(e.bytes);
        EXPECT_EQ(got, reports);
        ASSERT_EQ(transport.connected().size(), 1u);
        EXPECT_EQ(transport.connected()[0].where, "/dev/hidraw0");

        // Unplug: the hidraw node leaves sysfs.
        umockdev_testbed_remove_device(tb, sysPath(0).c_str());
        ASSERT_TRUE(waitFor(q, events, DeviceEventKind::Left, 1));
        EXPECT_TRUE(transport.connected().empty());

        addSpaceMouse(tb, {{0x03, 0x02, 0x00}}, 1);
        ASSERT_TRUE(waitFor(q, events, DeviceEventKind::Report, 4));
        EXPECT_EQ(count(events, DeviceEventKind::Arrived), 2u);
        EXPECT_EQ(events.back().bytes, (std::vector<uint8_t>{0x03, 0x02, 0x00}));
    }
    g_object_unref(tb);
}

}  // namespace
}  // namespace vsculpt::devices
