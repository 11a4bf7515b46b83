// SPDX-License-Identifier: MIT
#include "vsculpt/devices/SpaceMouse.h"

#include <algorithm>
#include <cmath>

namespace vsculpt::devices {

namespace {

int16_t readLe16(std::span<const uint8_t> b, size_t offset) {
    return int16_t(uint16_t(b[offset]) | uint16_t(b[offset + 1]) << 8);
}

std::optional<SpaceMouseSample> fail(DecodeStatus* status, DecodeStatus why) {
    if (status) *status = why;
    return std::nullopt;
}

}  // namespace

std::optional<SpaceMouseModel> findSpaceMouseModel(uint16_t vendor, uint16_t product) {
    // devices_report.md §2.1 (spacenavd's and VRPN's tables).
    static const SpaceMouseModel kModels[] = {
        {0x046d, 0xc603, "SpaceMouse Plus XT", false},
        {0x046d, 0xc605, "CadMan", true},
        {0x046d, 0xc606, "SpaceMouse Classic", false},
        {0x046d, 0xc621, "SpaceBall 5000", true},
        {0x046d, 0xc623, "SpaceTraveler", true},
        {0x046d, 0xc625, "SpacePilot", true},
        {0x046d, 0xc626, "SpaceNavigator", true},
        {0x046d, 0xc627, "SpaceExplorer", true},
        {0x046d, 0xc628, "SpaceNavigator for Notebooks", true},
        {0x046d, 0xc629, "SpacePilot Pro", true},
        {0x046d, 0xc62b, "SpaceMouse Pro", true},
        {0x046d, 0xc640, "NuLOOQ", false},
        {0x256f, 0xc62e, "SpaceMouse Wireless (cabled)", true},
        {0x256f, 0xc62f, "SpaceMouse Wireless (receiver)", true},
        {0x256f, 0xc631, "SpaceMouse Pro Wireless (cabled)", true},
        {0x256f, 0xc632, "SpaceMouse Pro Wireless (receiver)", true},
        {0x256f, 0xc633, "SpaceMouse Enterprise", true},
        {0x256f, 0xc635, "SpaceMouse Compact", true},
        {0x256f, 0xc636, "SpaceMouse Module", true},
        {0x256f, 0xc638, "SpaceMouse Pro Wireless (Bluetooth)", true},
        {0x256f, 0xc63a, "SpaceMouse Wireless (Bluetooth)", true},
        {0x256f, 0xc641, "SpaceMouse USB", true},
    };
    for (const SpaceMouseModel& m : kModels)
        if (m.vendor == vendor && m.product == product) return m;
    return std::nullopt;
}

std::optional<SpaceMouseSample> decodeSpaceMouseReport(std::span<const uint8_t> r, int64_t timeNs,
                                                       DecodeStatus* status) {
    if (r.empty()) return fail(status, DecodeStatus::Empty);
    SpaceMouseSample s;
    s.timeNs = timeNs;
    switch (r[0]) {
        case 1:  // translation, or all six axes on single-report devices
            if (r.size() < 7) return fail(status, DecodeStatus::Truncated);
            s.hasTranslation = true;
            for (int a = 0; a < 3; ++a)
                s.translation[a] = readLe16(r, 1 + 2 * a);
            if (r.size() >= 13) {
                s.hasRotation = true;
                for (int a = 0; a < 3; ++a)
                    s.rotation[a] = readLe16(r, 7 + 2 * a);
            }
            break;
        case 2:
            if (r.size() < 7) return fail(status, DecodeStatus::Truncated);
            s.hasRotation = true;
            for (int a = 0; a < 3; ++a)
                s.rotation[a] = readLe16(r, 1 + 2 * a);
            break;
        case 3:  // button bitmap, 1 to 3 bytes depending on the model
            if (r.size() < 2) return fail(status, DecodeStatus::Truncated);
            s.hasButtons = true;
            for (size_t i = 1; i < std::min<size_t>(r.size(), 5); ++i)
                s.buttons |= uint32_t(r[i]) << (8 * (i - 1));
            break;
        case 0x17:  // battery level
            if (r.size() < 2) return fail(status, DecodeStatus::Truncated);
            s.hasBattery = true;
            s.battery = std::min<int>(r[1], 100);
            break;
        default:
            return fail(status, DecodeStatus::UnknownReport);
    }
    if (status) *status = DecodeStatus::Ok;
    return s;
}

SpaceMouseAxes mapAxes(const std::array<int16_t, 3>& t, const std::array<int16_t, 3>& r,
                       const AxisMapping& m) {
    auto scale = [&](int16_t raw) {
        const double v = std::clamp(double(raw) / m.fullScale, -1.0, 1.0);
        return std::abs(v) < m.deadZone ? 0.0 : v;
    };
    SpaceMouseAxes out;
    for (int a = 0; a < 3; ++a) {
        out.translation[a] = scale(t[a]);
        out.rotation[a] = scale(r[a]);
    }
    if (m.swapInvertYZ) {
        // The device reports y towards the user and z down (spacenavd: SWAPYZ | INVYZ).
        for (auto* v : {&out.translation, &out.rotation}) {
            const double y = (*v)[1], z = (*v)[2];
            (*v)[1] = -z;
            (*v)[2] = -y;
        }
    }
    return out;
}

}  // namespace vsculpt::devices
