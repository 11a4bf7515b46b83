// SPDX-License-Identifier: MIT
/// @file ImuSample.h
/// @brief One inertial measurement of a headset IMU, as decoded from the device, in the
/// device's IMU frame. For the Rift with the sensor-config flag "sensor coordinates" (0x40)
/// clear, which is what buildRiftSensorConfig() sends by default, the IMU frame is the HMD
/// frame: x right, y up, z out of the back of the head (the wearer looks down -z), the same
/// axes as the renderer's head frame.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>

namespace vsculpt::devices {

struct ImuSample {
    /// Device clock in nanoseconds: the device's wrapping counter extended to 64 bits and
    /// strictly increasing from sample to sample (its resolution is the device's: 1 ms on the
    /// DK1, 1 us on the DK2/CV1). Use it for integration intervals: it does not suffer USB
    /// latency jitter.
    int64_t deviceTimeNs = 0;
    /// Host monotonic clock, estimated as the report's arrival time minus the sample's age in
    /// device time. Use it to line the sample up with other devices (e.g. the head tracker).
    int64_t hostTimeNs = 0;
    glm::dvec3 accelMps2{0.0};      ///< specific force, m/s^2: reads about +9.81 along "up" at rest
    glm::dvec3 gyroRadps{0.0};      ///< angular velocity of the IMU in its own frame, rad/s
    glm::dvec3 magneticGauss{0.0};  ///< per report (repeated for each sample), gauss
    double temperatureC = 0.0;      ///< per report, degrees Celsius
};

}  // namespace vsculpt::devices
