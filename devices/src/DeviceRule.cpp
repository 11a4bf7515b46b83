// SPDX-License-Identifier: MIT
#include "vsculpt/devices/DeviceRule.h"

#include <algorithm>

namespace vsculpt::devices {

namespace {
struct DriverName {
    DeviceDriver driver;
    const char* name;
};
constexpr DriverName kDrivers[] = {
    {DeviceDriver::SpaceMouse, "spacemouse"}, {DeviceDriver::Polhemus, "polhemus"},
    {DeviceDriver::WacomLegacy, "wacom"},     {DeviceDriver::HidDigitizer, "hid-digitizer"},
    {DeviceDriver::RiftImu, "rift"},          {DeviceDriver::OpenXr, "openxr"}};
}  // namespace

const char* toString(DeviceDriver d) {
    for (const auto& n : kDrivers)
        if (n.driver == d) return n.name;
    return "?";
}

const char* toString(DeviceAccess a) {
    return a == DeviceAccess::Libusb ? "libusb" : "hidraw";
}

std::optional<DeviceDriver> parseDeviceDriver(std::string_view name) {
    for (const auto& n : kDrivers)
        if (name == n.name) return n.driver;
    return std::nullopt;
}

std::optional<DeviceAccess> parseDeviceAccess(std::string_view name) {
    if (name == "libusb") return DeviceAccess::Libusb;
    if (name == "hidraw") return DeviceAccess::Hidraw;
    return std::nullopt;
}

const DeviceRule* findRule(const std::vector<DeviceRule>& rules, uint16_t vendor, uint16_t product,
                           DeviceAccess access) {
    for (const auto& r : rules)
        if (r.vendor == vendor && r.access == access &&
            std::find(r.products.begin(), r.products.end(), product) != r.products.end())
            return &r;
    return nullptr;
}

}  // namespace vsculpt::devices
