// SPDX-License-Identifier: MIT
/// @file WacomLegacy.h
/// @brief Legacy Wacom USB tablets (Graphire, Intuos, Intuos2, Intuos3) whose pen data is an
/// opaque vendor payload in input report 2 that no descriptor parser can decode: model table,
/// the mode-switch feature report, and the pure report decoder.
///
/// Layouts (devices_report.md §3.1, from the Linux wacom driver and OpenTabletDriver):
///  - Graphire, 8 bytes: [1] bit7 proximity, bits 6..5 tool (0 pen, 1 eraser, 2/3 mouse),
///    bit0 tip, bit1/bit2 side buttons; x, y = LE u16 at [2], [4]; pressure = [6] | ([7]&3)<<8.
///  - Intuos 1-3, 10 bytes: [1] selects enter-proximity (0xC0..0xC3, carries tool id and
///    serial), hover (0x20/0x21), exit (0x80/0x81) or a data packet; data packets: x, y = BE u16
///    at [2], [4] (Intuos3: one more low bit each from [9]), 11-bit pressure, tilt -64..63.
/// Frame: see PenSample.h (origin top-left, y down, mm).
#pragma once

#include "vsculpt/devices/DecodeStatus.h"
#include "vsculpt/devices/PenSample.h"

#include <array>
#include <cstdint>
#include <optional>
#include <span>

namespace vsculpt::devices {

enum class WacomProtocol { Graphire, Intuos, Intuos3 };

struct WacomModel {
    uint16_t vendor = 0x056a, product = 0;
    const char* name = "";
    WacomProtocol protocol = WacomProtocol::Graphire;
    uint32_t maxX = 0, maxY = 0;  ///< counts
    double countsPerMm = 0;       ///< 80 Graphire, 100 Intuos/Intuos2, 200 Intuos3
    uint32_t pressureMax = 0;     ///< 511 Graphire, 1023 Intuos 1-3
};

/// Known models by USB id; nullopt for anything else.
std::optional<WacomModel> findWacomModel(uint16_t vendor, uint16_t product);

/// The feature report (id 2, value 2) that switches the tablet from its boot mouse mode
/// (report 1) to Wacom mode (report 2): SET_REPORT(Feature, id 2). The transport reads it back
/// with GET_REPORT and retries until the mode sticks.
std::array<uint8_t, 2> wacomModeSwitchReport();

/// What the Intuos protocol tells only on entering proximity (the tool), kept between reports.
struct WacomPenState {
    PenTool tool = PenTool::None;
    uint32_t toolId = 0, serial = 0;
};

/// Tool type of an Intuos tool id (mouse, lens, airbrush, eraser, else pen), after the Linux
/// driver's table.
PenTool wacomToolType(uint32_t toolId);

/// Decodes one input report (first byte = report id). Report 1 (mouse mode) and other ids give
/// UnknownReport; short reports Truncated. `state` carries the tool across Intuos reports.
std::optional<PenSample> decodeWacomLegacyReport(std::span<const uint8_t> report,
                                                 const WacomModel& model, WacomPenState& state,
                                                 int64_t timeNs, DecodeStatus* status = nullptr);

}  // namespace vsculpt::devices
