// SPDX-License-Identifier: MIT
/// @file DeviceRule.h
/// @brief Which USB devices vsculpt opens, how, and what it does with them: one rule per
/// device, from configs/sculpt.json "devices.match" (docs/devices.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vsculpt::devices {

/// The decoder a device's reports go to.
/// OpenXr is not a USB device: the OpenXR controllers as recorded by `vsculpt --xr --record`
/// (one report a frame, app/XrInput.h), so a headset session replays like device reports.
enum class DeviceDriver { SpaceMouse, Polhemus, WacomLegacy, HidDigitizer, RiftImu, OpenXr };

/// How the bytes are read. Hidraw leaves the kernel's HID driver attached (the desktop keeps
/// the device); Libusb claims the interface, detaching the kernel driver while vsculpt runs.
enum class DeviceAccess { Libusb, Hidraw };

const char* toString(DeviceDriver d);
const char* toString(DeviceAccess a);
std::optional<DeviceDriver> parseDeviceDriver(std::string_view name);
std::optional<DeviceAccess> parseDeviceAccess(std::string_view name);

struct DeviceRule {
    std::string name;  ///< unique; names the device in events, recordings and messages
    uint16_t vendor = 0;
    std::vector<uint16_t> products;  ///< any of these
    DeviceDriver driver = DeviceDriver::SpaceMouse;
    DeviceAccess access = DeviceAccess::Hidraw;
    int interfaceNumber = 0;  ///< libusb: the interface to claim
    uint8_t inEndpoint = 0;   ///< libusb: IN endpoint address; 0 = the interface's first IN
    uint8_t outEndpoint = 0;  ///< libusb: OUT endpoint for commands; 0 = the first OUT, if any
};

/// The first rule with this access matching vendor:product, or nullptr.
const DeviceRule* findRule(const std::vector<DeviceRule>& rules, uint16_t vendor, uint16_t product,
                           DeviceAccess access);

}  // namespace vsculpt::devices
