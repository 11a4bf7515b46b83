// SPDX-License-Identifier: MIT
/// @file TrackerSample.h
/// @brief One 6-DOF pose of one station (sensor) of a magnetic tracker (Polhemus.h).
///
/// Frame: the tracker SOURCE's frame as the device reports it (Polhemus: +x away from the
/// source's cable side, +y right, +z down with the default hemisphere); the app maps it into the
/// sculpting frame. Position in millimetres whatever unit the device was set to.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

namespace vsculpt::devices {

struct TrackerSample {
    int64_t timeNs = 0;  ///< monotonic clock of the host when the bytes were read
    int station = 0;     ///< 1-based, as printed on the tracker's front panel
    bool hasPosition = false, hasOrientation = false;
    glm::dvec3 positionMm{0.0};
    /// Rotation from the station's sensor frame to the source frame (w, x, y, z as the device
    /// sends it; from Euler angles the order is azimuth about z, then elevation about the new
    /// y, then roll about the new x).
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
    bool hasDeviceTime = false;
    uint32_t deviceTimeMs = 0;  ///< tracker clock, ms since its last reset
    bool hasFrameCount = false;
    uint32_t frameCount = 0;
    uint32_t buttons = 0;    ///< stylus switch: bit 0
    int32_t distortion = 0;  ///< Liberty distortion level, when requested
    char errorCode = ' ';    ///< the record's status byte; ' ' = no error
};

}  // namespace vsculpt::devices
