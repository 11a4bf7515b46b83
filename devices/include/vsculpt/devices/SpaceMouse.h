// SPDX-License-Identifier: MIT
/// @file SpaceMouse.h
/// @brief 3Dconnexion 3D mice: the pure decoder (HID input report bytes -> sample) and the
/// axis mapping (raw counts -> scaled, dead-zoned axes in the vsculpt frame). No USB here:
/// the transport (issue #6) hands reports to decodeSpaceMouseReport().
///
/// Report layouts (devices_report.md §2.2): report 1 = translation X, Y, Z as int16 LE
/// (7 bytes) on SpaceNavigator-class devices, or all six axes X, Y, Z, Rx, Ry, Rz (13 bytes)
/// on newer ones; report 2 = rotation Rx, Ry, Rz (7 bytes); report 3 = button bitmap (1 to 3
/// bytes); report 0x17 = battery level 0..100. Axes are treated as absolute whatever the
/// descriptor's Rel flag says (the SpaceNavigator declares them relative).
#pragma once

#include "vsculpt/devices/DecodeStatus.h"

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace vsculpt::devices {

struct SpaceMouseModel {
    uint16_t vendor = 0, product = 0;
    const char* name = "";
    bool swapInvertYZ = false;  ///< the device's Y/Z differ from the usual frame (spacenavd)
};

/// The known models, by USB vendor and product id; nullopt for anything else.
std::optional<SpaceMouseModel> findSpaceMouseModel(uint16_t vendor, uint16_t product);

struct SpaceMouseSample {
    int64_t timeNs = 0;  ///< monotonic clock of the host when read
    bool hasTranslation = false, hasRotation = false, hasButtons = false, hasBattery = false;
    std::array<int16_t, 3> translation{};  ///< raw counts, nominally -350..350
    std::array<int16_t, 3> rotation{};
    uint32_t buttons = 0;  ///< bit i = button i+1
    int battery = -1;      ///< percent
};

/// Decodes one input report (first byte = report id). Never reads past the span; a short
/// report gives Truncated, an id it does not know UnknownReport (both: nullopt).
std::optional<SpaceMouseSample> decodeSpaceMouseReport(std::span<const uint8_t> report,
                                                       int64_t timeNs,
                                                       DecodeStatus* status = nullptr);

struct AxisMapping {
    double fullScale = 350.0;  ///< raw count that maps to 1.0
    double deadZone = 0.02;    ///< |value| below this (after scaling) reads as 0
    bool swapInvertYZ = true;  ///< from the model table
};

/// Scaled axes: translation and rotation in [-1, 1] (clamped), dead-zoned, in the vsculpt
/// frame (x right, y away from the user, z up).
struct SpaceMouseAxes {
    std::array<double, 3> translation{}, rotation{};
};
SpaceMouseAxes mapAxes(const std::array<int16_t, 3>& translation,
                       const std::array<int16_t, 3>& rotation, const AxisMapping& mapping);

}  // namespace vsculpt::devices
