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

/// A Rift DK1 tracker report (devices_report.md §4.1) with one IMU sample: report id 1, the
/// sample count, a millisecond timestamp (little-endian at 2), then at 8 the accelerometer and
/// the gyro as three 21-bit two's-complement counts each, packed MSB first into 8 bytes
/// (x in bits 63..43, y in 42..22, z in 21..1 of a big-endian word); 1e-4 m/s^2 and 1e-4 rad/s
/// per count.
inline Bytes riftDk1Report(uint16_t timestampMs, const int32_t accel[3],
                           const int32_t gyro[3] = nullptr) {
    Bytes r(62, 0);
    r[0] = 1;
    r[1] = 1;
    r[2] = uint8_t(timestampMs & 0xFF);
    r[3] = uint8_t(timestampMs >> 8);
    auto pack = [&](size_t at, const int32_t v[3]) {
        constexpr uint64_t kMask = 0x1FFFFF;
        const uint64_t word = (uint64_t(uint32_t(v[0])) & kMask) << 43 |
                              (uint64_t(uint32_t(v[1])) & kMask) << 22 |
                              (uint64_t(uint32_t(v[2])) & kMask) << 1;
        for (size_t i = 0; i < 8; ++i)
            r[at + i] = uint8_t(word >> (56 - 8 * i));
    };
    const int32_t zero[3] = {0, 0, 0};
    pack(8, accel);
    pack(16, gyro ? gyro : zero);
    return r;
}

inline devices::DeviceEvent report(int64_t timeNs, const std::string& device, Bytes bytes) {
    return {devices::DeviceEventKind::Report, timeNs, device, std::move(bytes)};
}

}  // namespace vsculpt::test
