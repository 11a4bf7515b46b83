// SPDX-License-Identifier: MIT
/// @file HidMultiAxis.h
/// @brief Generic decoder for 3D mice and other multi-axis controllers driven by their HID
/// report descriptor (Generic Desktop X, Y, Z, Rx, Ry, Rz and Button page), giving the same
/// SpaceMouseSample as the hand-written decoder in SpaceMouse.h, so each checks the other.
///
/// Axes are read as absolute values whatever the descriptor's Relative flag says: the
/// SpaceNavigator declares them Relative although they are the knob's displacement
/// (devices_report.md §2.3, the Linux hid-lg quirk that misses some production runs).
#pragma once

#include "vsculpt/devices/DecodeStatus.h"
#include "vsculpt/devices/HidDescriptor.h"
#include "vsculpt/devices/SpaceMouse.h"

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vsculpt::devices {

class HidMultiAxisDecoder {
  public:
    /// Uses the input reports inside a Multi-axis Controller (0x01:0x08) application
    /// collection, or, when there is none, inside Joystick/Gamepad ones (never a pen's or a
    /// mouse's X/Y). nullopt (and `error`) when no
    /// report carries an axis.
    static std::optional<HidMultiAxisDecoder> fromDescriptor(const HidDescriptor& descriptor,
                                                             std::string* error = nullptr);

    /// Decodes one input report (first byte = report id when the descriptor uses ids). Axis
    /// values are clamped to int16. Never reads past the span.
    std::optional<SpaceMouseSample> decode(std::span<const uint8_t> report, int64_t timeNs,
                                           DecodeStatus* status = nullptr) const;

    /// Millimetres of knob travel per count of the translation axes, from the physical range
    /// and unit; nullopt when the descriptor gives no length unit.
    std::optional<double> translationMmPerCount() const { return mMmPerCount; }

  private:
    struct Axis {
        HidField field;
        uint32_t index;
        int axis;  ///< 0..5 = X, Y, Z, Rx, Ry, Rz
    };
    struct Button {
        HidField field;
        uint32_t index;
        int bit;
    };
    struct Report {
        uint8_t id = 0;
        uint32_t bytes = 0;
        std::vector<Axis> axes;
        std::vector<Button> buttons;
        std::optional<std::pair<HidField, uint32_t>> battery;
    };
    std::vector<Report> mReports;
    bool mUsesIds = false;
    std::optional<double> mMmPerCount;
};

}  // namespace vsculpt::devices
