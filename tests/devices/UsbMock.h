// SPDX-License-Identifier: MIT
// A USB device emulated with umockdev for the transport tests: sysfs entries that libusb
// enumerates, and a usbfs ioctl handler that answers SUBMITURB/REAPURB from a script of IN
// reports. Test executables using it run under `umockdev-wrapper` (LD_PRELOAD).
#pragma once

#include <umockdev.h>

#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace vsculpt::devices::test {

class UsbMock {
  public:
    /// `descriptors`: device + configuration descriptors as libusb reads them from sysfs.
    UsbMock(int bus, int address, std::vector<uint8_t> descriptors);
    ~UsbMock();
    UsbMock(const UsbMock&) = delete;
    UsbMock& operator=(const UsbMock&) = delete;

    /// Makes the device appear (sysfs + /dev node with the ioctl handler).
    void plug();
    /// Every URB in flight completes with ENODEV, then the device leaves sysfs.
    void unplug();

    /// IN data the device will return, one URB completion per entry, in order.
    void queueIn(std::vector<uint8_t> report);
    /// Bytes the host sent to OUT endpoints / control SET_REPORTs (setup + data), in order.
    std::vector<std::vector<uint8_t>> sent();
    /// True when every queued IN report has been handed to the host.
    bool drained();
    /// Whether the testbed is usable (umockdev-wrapper preloaded).
    static bool available();

    // Called from umockdev's handler thread.
    bool handle(UMockdevIoctlClient* client);

  private:
    std::string sysPath() const;
    int mBus, mAddress;
    std::vector<uint8_t> mDescriptors;
    UMockdevTestbed* mTestbed = nullptr;
    UMockdevIoctlBase* mHandler = nullptr;
    std::mutex mMutex;
    std::deque<std::vector<uint8_t>> mIn;
    std::deque<UMockdevIoctlData*> mFlyingIn;  // IN URBs waiting for data
    std::deque<UMockdevIoctlData*> mReapable;  // completed URBs (data filled in)
    std::vector<std::vector<uint8_t>> mSent;
    bool mUnplugged = false;
    bool mPlugged = false;
    bool mAttached = false;
};

/// Device + configuration descriptor of a one-interface HID device with one interrupt IN
/// endpoint (0x81) of `inPacket` bytes and, if outPacket > 0, an OUT endpoint (0x02).
std::vector<uint8_t> hidDescriptors(uint16_t vendor, uint16_t product, int inPacket, int outPacket,
                                    bool bulk = false);

}  // namespace vsculpt::devices::test
