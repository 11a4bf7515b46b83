// SPDX-License-Identifier: MIT
/// @file HidrawTransport.h
/// @brief The Linux hidraw transport: HID devices read through /dev/hidrawN while the
/// kernel's HID driver stays attached, so a tablet or 3D mouse keeps working on the desktop
/// while vsculpt runs (the default for HID devices; docs/devices.md).
///
/// Threads: one reader thread per open device (poll + read, one report per read), and one
/// watcher thread that scans /sys/class/hidraw every `rescanIntervalS` for arrivals and
/// removals and raises stall warnings. Nothing here decodes.
#pragma once

#include "vsculpt/devices/Transport.h"

#include <filesystem>
#include <memory>

namespace vsculpt::devices {

class HidrawTransport final : public Transport {
  public:
    /// Only rules with access == Hidraw are used. `queue` must outlive the transport.
    /// `sysRoot`/`devRoot` exist for tests; the defaults are the real ones.
    HidrawTransport(TransportOptions options, EventQueue& queue,
                    std::filesystem::path sysClass = "/sys/class/hidraw",
                    std::filesystem::path devDir = "/dev");
    ~HidrawTransport() override;

    void start() override;
    std::vector<ConnectedDevice> connected() const override;
    /// write() of an output report (bytes[0] = report id, 0 when the device has none).
    SendStatus sendOutput(const std::string& device, std::span<const uint8_t> bytes) override;
    /// HIDIOCSFEATURE.
    SendStatus sendFeature(const std::string& device, std::span<const uint8_t> bytes) override;

    struct Impl;

  private:
    std::unique_ptr<Impl> mImpl;
};

/// One hidraw node as `vsculpt devices` lists it.
struct HidrawNodeInfo {
    std::string node;  ///< "hidraw3"
    uint16_t bus = 0, vendor = 0, product = 0;
    std::string name;  ///< HID_NAME from the uevent
    bool readable = false;
    std::filesystem::path hidDevice;  ///< the HID device's sysfs folder (report_descriptor)
};

/// Every hidraw node under `sysClass` (empty when there is none or no such directory).
std::vector<HidrawNodeInfo> listHidrawNodes(
    const std::filesystem::path& sysClass = "/sys/class/hidraw",
    const std::filesystem::path& devDir = "/dev");

/// Parses the HID_ID line of a hidraw uevent ("HID_ID=0003:0000256F:0000C635"); false when
/// the text has none or it is malformed.
bool parseHidId(const std::string& ueventText, uint16_t& bus, uint16_t& vendor, uint16_t& product);

}  // namespace vsculpt::devices
