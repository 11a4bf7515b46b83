// SPDX-License-Identifier: MIT
// Device reports built from the documented layouts (devices_report.md §1.3 Liberty binary
// records, §2.2 3Dconnexion reports) for the app-level device tests.
#pragma once

#include "vsculpt/devices/DeviceEvent.h"

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

namespace vsculpt::test {

using Bytes = std::vector<uint8_t>;

/// Liberty record with the default output list (position cm, quaternion, timestamp, frame
/// count, space): 8-byte header + 37 bytes.
inline Bytes libertyRecord(int station, double xCm, double yCm, double zCm, uint32_t frame,
                           const float quat[4] = nullptr) {
    Bytes b{'L', 'Y', uint8_t(station), 'C', ' ', 0, 37, 0};
    auto f32 = [&](float v) {
        const uint32_t u = std::bit_cast<uint32_t>(v);
        for (int k = 0; k < 4; ++k)
            b.push_back(uint8_t(u >> (8 * k)));
    };
    auto u32 = [&](uint32_t u) {
        for (int k = 0; k < 4; ++k)
            b.push_back(uint8_t(u >> (8 * k)));
    };
    f32(float(xCm));
    f32(float(yCm));
    f32(float(zCm));
    const float identity[4] = {1, 0, 0, 0};
    for (int k = 0; k < 4; ++k)
        f32(quat ? quat[k] : identity[k]);
    u32(frame * 4);
    u32(frame);
    b.push_back(' ');
    return b;
}

inline Bytes mouseAxes(uint8_t id, int16_t a, int16_t b, int16_t c) {
    return {id,
            uint8_t(a),
            uint8_t(uint16_t(a) >> 8),
            uint8_t(b),
            uint8_t(uint16_t(b) >> 8),
            uint8_t(c),
            uint8_t(uint16_t(c) >> 8)};
}

inline Bytes mouseButtons(uint8_t bits) {
    return {0x03, bits, 0x00};
}

inline devices::DeviceEvent report(int64_t timeNs, const std::string& device, Bytes bytes) {
    return {devices::DeviceEventKind::Report, timeNs, device, std::move(bytes)};
}

}  // namespace vsculpt::test
