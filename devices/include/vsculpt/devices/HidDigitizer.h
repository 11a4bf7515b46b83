// SPDX-License-Identifier: MIT
/// @file HidDigitizer.h
/// @brief Generic pen-tablet decoder for devices that describe their pen with standard HID
/// usages (Digitizer page 0x0D: In Range, Tip Switch, Barrel Switch, Invert, Eraser, Tip
/// Pressure, X/Y Tilt; Generic Desktop X/Y). Covers Windows-Ink tablets (XP-Pen, Huion, UGEE),
/// pen displays and Wacom's "HID generic" models, whose vendor page 0xFF0D mirrors the
/// standard usages (0xFF0D:0x0130 = Generic Desktop X, 0xFF0D:0x0042 = Tip Switch, ...).
///
/// Positions are scaled to millimetres by the physical range, unit and unit exponent of X and
/// Y. Tilt uses its unit when the descriptor gives degrees or radians, else reads the logical
/// value as degrees (what cheap tablets send without a unit).
#pragma once

#include "vsculpt/devices/DecodeStatus.h"
#include "vsculpt/devices/HidDescriptor.h"
#include "vsculpt/devices/PenSample.h"

#include <optional>
#include <span>
#include <string>

namespace vsculpt::devices {

class HidDigitizerDecoder {
  public:
    /// Picks an input report that carries X, Y and a Tip Switch or In Range, preferring one in
    /// a Pen application collection over a generic Digitizer one over a Touch Screen / Touch
    /// Pad one (first of equals). nullopt (and `error` says why) when there is none.
    static std::optional<HidDigitizerDecoder> fromDescriptor(const HidDescriptor& descriptor,
                                                             std::string* error = nullptr);

    /// Decodes one input report as read from the device (first byte = report id when the
    /// descriptor uses ids). Never reads past the span.
    std::optional<PenSample> decode(std::span<const uint8_t> report, int64_t timeNs,
                                    DecodeStatus* status = nullptr) const;

    uint8_t reportId() const { return mReportId; }
    uint32_t reportBytes() const { return mReportBytes; }
    /// False when X/Y carry no length unit: positionMm then stays 0; use positionNormalized.
    bool hasPhysicalSize() const { return mXmm > 0 && mYmm > 0; }
    /// Size of the active area in mm (0 when unknown).
    double widthMm() const { return mWidthMm; }
    double heightMm() const { return mHeightMm; }

  private:
    struct Slot {
        std::optional<HidField> field;
        uint32_t index = 0;
    };
    Slot mTip, mInRange, mBarrel, mBarrel2, mInvert, mEraser, mX, mY, mPressure, mTiltX, mTiltY,
        mSerial;
    uint8_t mReportId = 0;
    bool mUsesIds = false;
    uint32_t mReportBytes = 0;
    double mXmm = 0, mYmm = 0;  ///< mm per physical unit
    double mWidthMm = 0, mHeightMm = 0;
};

/// Maps Wacom's vendor digitizer page (0xFF0D) onto the standard usages it mirrors; other
/// usages pass through. Fact from the Linux wacom driver's "equivalent usage" rule.
uint32_t hidEquivalentPenUsage(uint32_t usage);

}  // namespace vsculpt::devices
