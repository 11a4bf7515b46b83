// SPDX-License-Identifier: MIT
/// @file PenSample.h
/// @brief One pen-tablet state, the common output of the legacy Wacom decoder (WacomLegacy.h)
/// and the generic HID digitizer decoder (HidDigitizer.h).
///
/// Frame: the tablet's own, as the device counts: x to the right, y DOWN (towards the user on a
/// desk tablet), origin at the top-left corner of the active area, millimetres. Tilt is the
/// pen's lean towards +x and +y in radians (0 = upright), as HID X Tilt / Y Tilt define it.
#pragma once

#include <glm/vec2.hpp>

#include <cstdint>

namespace vsculpt::devices {

enum class PenTool { None, Pen, Eraser, Airbrush, Mouse, Lens };

const char* toString(PenTool t);

struct PenSample {
    int64_t timeNs = 0;        ///< monotonic clock of the host when read
    bool inProximity = false;  ///< the tool is sensed (hovering or touching)
    bool touching = false;     ///< tip (or eraser) on the surface
    PenTool tool = PenTool::None;
    bool hasPosition = false;  ///< false on proximity-only reports
    glm::dvec2 positionMm{0.0};
    /// Position as a fraction of the logical range (0..1 each), for mapping the whole tablet
    /// onto a screen or a canvas without knowing its size.
    glm::dvec2 positionNormalized{0.0};
    double pressure = 0.0;  ///< 0..1 of the device's range
    bool hasTilt = false;
    glm::dvec2 tiltRad{0.0};
    uint32_t buttons = 0;     ///< bit 0 = first barrel button, bit 1 = second barrel button
    uint32_t toolSerial = 0;  ///< 0 when the device does not tell
};

}  // namespace vsculpt::devices
