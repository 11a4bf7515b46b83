// SPDX-License-Identifier: MIT
#include "vsculpt/devices/WacomLegacy.h"

#include <algorithm>
#include <cmath>

namespace vsculpt::devices {

namespace {

std::optional<PenSample> fail(DecodeStatus* status, DecodeStatus why) {
    if (status) *status = why;
    return std::nullopt;
}

void setPosition(PenSample& s, const WacomModel& m, uint32_t x, uint32_t y) {
    s.hasPosition = true;
    s.positionMm = {x / m.countsPerMm, y / m.countsPerMm};
    s.positionNormalized = {m.maxX ? std::min(1.0, double(x) / m.maxX) : 0.0,
                            m.maxY ? std::min(1.0, double(y) / m.maxY) : 0.0};
}

std::optional<PenSample> decodeGraphire(std::span<const uint8_t> r, const WacomModel& m,
                                        int64_t timeNs, DecodeStatus* status) {
    if (r.size() < 8) return fail(status, DecodeStatus::Truncated);
    PenSample s;
    s.timeNs = timeNs;
    s.inProximity = r[1] & 0x80;
    if (!s.inProximity) {
        if (status) *status = DecodeStatus::Ok;
        return s;
    }
    const int tool = (r[1] >> 5) & 3;
    s.tool = tool == 0 ? PenTool::Pen : tool == 1 ? PenTool::Eraser : PenTool::Mouse;
    setPosition(s, m, uint32_t(r[2]) | uint32_t(r[3]) << 8, uint32_t(r[4]) | uint32_t(r[5]) << 8);
    if (s.tool == PenTool::Mouse) {
        s.buttons = r[1] & 7;  // left, right, middle
    } else {
        s.touching = r[1] & 1;
        s.buttons = (r[1] >> 1) & 3;
        const uint32_t p = uint32_t(r[6]) | uint32_t(r[7] & 3) << 8;
        s.pressure = m.pressureMax ? std::min(1.0, double(p) / m.pressureMax) : 0.0;
    }
    if (status) *status = DecodeStatus::Ok;
    return s;
}

std::optional<PenSample> decodeIntuos(std::span<const uint8_t> r, const WacomModel& m,
                                      WacomPenState& state, int64_t timeNs, DecodeStatus* status) {
    if (r.size() < 10) return fail(status, DecodeStatus::Truncated);
    PenSample s;
    s.timeNs = timeNs;
    if ((r[1] & 0xFC) == 0xC0) {  // enter proximity: who the tool is
        state.serial = uint32_t(r[3] & 0x0F) << 28 | uint32_t(r[4]) << 20 | uint32_t(r[5]) << 12 |
                       uint32_t(r[6]) << 4 | uint32_t(r[7]) >> 4;
        state.toolId = uint32_t(r[2]) << 4 | uint32_t(r[3]) >> 4 | uint32_t(r[7] & 0x0F) << 16 |
                       uint32_t(r[8] & 0xF0) << 8;
        state.tool = wacomToolType(state.toolId);
        s.inProximity = true;
        s.tool = state.tool;
        s.toolSerial = state.serial;
        if (status) *status = DecodeStatus::Ok;
        return s;
    }
    if ((r[1] & 0xFE) == 0x80) {  // exit proximity
        state = WacomPenState{};
        if (status) *status = DecodeStatus::Ok;
        return s;
    }
    s.inProximity = true;
    s.tool = state.tool == PenTool::None ? PenTool::Pen : state.tool;
    s.toolSerial = state.serial;
    if ((r[1] & 0xFE) == 0x20) {  // in range, no data yet
        if (status) *status = DecodeStatus::Ok;
        return s;
    }
    uint32_t x = uint32_t(r[2]) << 8 | r[3], y = uint32_t(r[4]) << 8 | r[5];
    if (m.protocol == WacomProtocol::Intuos3) {
        x = x << 1 | ((r[9] >> 1) & 1);
        y = y << 1 | (r[9] & 1);
    }
    const int type = (r[1] >> 1) & 0x0F;
    if (type <= 3) {  // pen or eraser: pressure, tilt, barrel buttons
        if (s.tool != PenTool::Eraser && s.tool != PenTool::Airbrush) s.tool = PenTool::Pen;
        setPosition(s, m, x, y);
        uint32_t p = uint32_t(r[6]) << 3 | uint32_t(r[7] & 0xC0) >> 5 | (r[1] & 1);
        if (m.pressureMax < 2047) p >>= 1;
        s.pressure = m.pressureMax ? std::min(1.0, double(p) / m.pressureMax) : 0.0;
        s.touching = p > 10;  // the kernel's contact threshold
        const int tiltX = int(((r[7] << 1) & 0x7E) | (r[8] >> 7)) - 64;
        const int tiltY = int(r[8] & 0x7F) - 64;
        s.hasTilt = true;  // one unit per degree (the kernel says 57 units/rad)
        s.tiltRad = {tiltX * M_PI / 180.0, tiltY * M_PI / 180.0};
        s.buttons = (r[1] >> 1) & 3;
    } else if (type == 4 || type == 5 || type == 6 || type == 8 || type == 0x0A) {
        // Mouse, lens, 4D-mouse rotation and airbrush-wheel packets: position only here.
        setPosition(s, m, x, y);
    } else {
        return fail(status, DecodeStatus::UnknownReport);
    }
    if (status) *status = DecodeStatus::Ok;
    return s;
}

}  // namespace

std::optional<WacomModel> findWacomModel(uint16_t vendor, uint16_t product) {
    using P = WacomProtocol;
    // devices_report.md §3.1; sizes from the Linux driver's feature table (input-wacom).
    static const WacomModel kModels[] = {
        {0x056a, 0x0010, "Graphire", P::Graphire, 10206, 7422, 80, 511},
        {0x056a, 0x0011, "Graphire2 4x5", P::Graphire, 10206, 7422, 80, 511},
        {0x056a, 0x0012, "Graphire2 5x7", P::Graphire, 13918, 10206, 80, 511},
        {0x056a, 0x0013, "Graphire3", P::Graphire, 10208, 7424, 80, 511},
        {0x056a, 0x0014, "Graphire3 6x8", P::Graphire, 16704, 12064, 80, 511},
        // Graphire4 differs from Graphire only in the mouse wheel and pad, not the pen.
        {0x056a, 0x0015, "Graphire4 4x5", P::Graphire, 10208, 7424, 80, 511},
        {0x056a, 0x0016, "Graphire4 6x8", P::Graphire, 16704, 12064, 80, 511},
        {0x056a, 0x0020, "Intuos 4x5", P::Intuos, 12700, 10600, 100, 1023},
        {0x056a, 0x0021, "Intuos 6x8", P::Intuos, 20320, 16240, 100, 1023},
        {0x056a, 0x0022, "Intuos 9x12", P::Intuos, 30480, 24060, 100, 1023},
        {0x056a, 0x0023, "Intuos 12x12", P::Intuos, 30480, 31680, 100, 1023},
        {0x056a, 0x0024, "Intuos 12x18", P::Intuos, 45720, 31680, 100, 1023},
        {0x056a, 0x0041, "Intuos2 4x5", P::Intuos, 12700, 10600, 100, 1023},
        {0x056a, 0x0042, "Intuos2 6x8", P::Intuos, 20320, 16240, 100, 1023},
        {0x056a, 0x0043, "Intuos2 9x12", P::Intuos, 30480, 24060, 100, 1023},
        {0x056a, 0x0044, "Intuos2 12x12", P::Intuos, 30480, 31680, 100, 1023},
        {0x056a, 0x0045, "Intuos2 12x18", P::Intuos, 45720, 31680, 100, 1023},
        {0x056a, 0x0047, "Intuos2 6x8", P::Intuos, 20320, 16240, 100, 1023},
        {0x056a, 0x00B0, "Intuos3 4x5", P::Intuos3, 25400, 20320, 200, 1023},
        {0x056a, 0x00B1, "Intuos3 6x8", P::Intuos3, 40640, 30480, 200, 1023},
        {0x056a, 0x00B2, "Intuos3 9x12", P::Intuos3, 60960, 45720, 200, 1023},
        {0x056a, 0x00B3, "Intuos3 12x12", P::Intuos3, 60960, 60960, 200, 1023},
        {0x056a, 0x00B4, "Intuos3 12x19", P::Intuos3, 97536, 60960, 200, 1023},
        {0x056a, 0x00B5, "Intuos3 6x11", P::Intuos3, 54204, 31750, 200, 1023},
        {0x056a, 0x00B7, "Intuos3 4x6", P::Intuos3, 31496, 19685, 200, 1023},
    };
    for (const WacomModel& m : kModels)
        if (m.vendor == vendor && m.product == product) return m;
    return std::nullopt;
}

std::array<uint8_t, 2> wacomModeSwitchReport() {
    return {0x02, 0x02};
}

PenTool wacomToolType(uint32_t id) {
    switch (id) {
        case 0x007:  // 4D and 2D mouse
        case 0x09C:
        case 0x094:
        case 0x017:  // Intuos3 2D mouse
        case 0x806:
            return PenTool::Mouse;
        case 0x096:  // lens cursor
        case 0x097:
        case 0x006:
            return PenTool::Lens;
        case 0x112:  // airbrushes
        case 0x912:
        case 0xD12:
        case 0x913:
        case 0x902:
            return PenTool::Airbrush;
        default:
            break;
    }
    // Erasers are the pens' ids with 0xA, 0xB or 0xC in the low nibble (0x82A, 0x85A, 0x91B,
    // 0x80C, ...).
    const uint32_t nibble = id & 0x0F;
    return nibble >= 0x0A && nibble <= 0x0C ? PenTool::Eraser : PenTool::Pen;
}

std::optional<PenSample> decodeWacomLegacyReport(std::span<const uint8_t> r, const WacomModel& m,
                                                 WacomPenState& state, int64_t timeNs,
                                                 DecodeStatus* status) {
    if (r.empty()) return fail(status, DecodeStatus::Empty);
    if (r[0] != 2) return fail(status, DecodeStatus::UnknownReport);
    if (m.protocol == WacomProtocol::Graphire) return decodeGraphire(r, m, timeNs, status);
    return decodeIntuos(r, m, state, timeNs, status);
}

}  // namespace vsculpt::devices
