// SPDX-License-Identifier: MIT
// Legacy Wacom (Graphire, Intuos 1-3) decoding on reports built from the documented bit
// layouts (devices_report.md §3.1).
#include "vsculpt/devices/WacomLegacy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace vsculpt::devices;

namespace {

using Bytes = std::vector<uint8_t>;
constexpr double kDeg = M_PI / 180.0;

TEST(WacomLegacy, ModelTableAndModeSwitch) {
    const auto i2 = findWacomModel(0x056a, 0x0042);
    ASSERT_TRUE(i2);
    EXPECT_EQ(i2->protocol, WacomProtocol::Intuos);
    EXPECT_EQ(i2->maxX, 20320u);
    EXPECT_EQ(i2->maxY, 16240u);
    EXPECT_DOUBLE_EQ(i2->maxX / i2->countsPerMm, 203.2);  // 8 inches
    const auto i3 = findWacomModel(0x056a, 0x00B1);
    ASSERT_TRUE(i3);
    EXPECT_EQ(i3->protocol, WacomProtocol::Intuos3);
    EXPECT_DOUBLE_EQ(i3->maxX / i3->countsPerMm, 203.2);
    const auto g = findWacomModel(0x056a, 0x0010);
    ASSERT_TRUE(g);
    EXPECT_EQ(g->pressureMax, 511u);
    EXPECT_FALSE(findWacomModel(0x056a, 0x0357));  // an Intuos Pro: HID generic, not legacy
    EXPECT_EQ(wacomModeSwitchReport(), (std::array<uint8_t, 2>{2, 2}));
}

TEST(WacomLegacy, GraphirePenEraserMouseAndOutOfProximity) {
    const WacomModel m = *findWacomModel(0x056a, 0x0010);
    WacomPenState state;
    // In proximity, pen, tip down, side button 1; x = 5103, y = 3711 (LE); pressure 511.
    const Bytes pen{2, 0x80 | 0x02 | 0x01, 0xEF, 0x13, 0x7F, 0x0E, 0xFF, 0x01};
    DecodeStatus st;
    auto s = decodeWacomLegacyReport(pen, m, state, 9, &st);
    ASSERT_TRUE(s);
    EXPECT_EQ(st, DecodeStatus::Ok);
    EXPECT_EQ(s->timeNs, 9);
    EXPECT_TRUE(s->inProximity && s->touching && s->hasPosition);
    EXPECT_EQ(s->tool, PenTool::Pen);
    EXPECT_EQ(s->buttons, 1u);
    EXPECT_DOUBLE_EQ(s->positionMm.x, 5103 / 80.0);
    EXPECT_DOUBLE_EQ(s->positionMm.y, 3711 / 80.0);
    EXPECT_DOUBLE_EQ(s->positionNormalized.x, 0.5);
    EXPECT_DOUBLE_EQ(s->pressure, 1.0);
    EXPECT_FALSE(s->hasTilt);

    Bytes eraser = pen;
    eraser[1] = 0x80 | 0x20;  // tool bits = 1, hovering
    eraser[6] = 0;
    eraser[7] = 0;
    s = decodeWacomLegacyReport(eraser, m, state, 0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->tool, PenTool::Eraser);
    EXPECT_FALSE(s->touching);
    EXPECT_DOUBLE_EQ(s->pressure, 0.0);

    Bytes mouse = pen;
    mouse[1] = 0x80 | 0x60 | 0x04;  // tool bits = 3, middle button
    s = decodeWacomLegacyReport(mouse, m, state, 0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->tool, PenTool::Mouse);
    EXPECT_EQ(s->buttons, 4u);

    const Bytes away{2, 0, 0, 0, 0, 0, 0, 0};
    s = decodeWacomLegacyReport(away, m, state, 0);
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->inProximity);
    EXPECT_EQ(s->tool, PenTool::None);
}

TEST(WacomLegacy, Intuos3ProximityDataAndExit) {
    const WacomModel m = *findWacomModel(0x056a, 0x00B1);
    WacomPenState state;
    // Enter proximity: tool id 0x823 (Intuos3 grip pen), serial 0x12345678.
    const Bytes enter{2, 0xC2, 0x82, 0x31, 0x23, 0x45, 0x67, 0x80, 0x00, 0x00};
    auto s = decodeWacomLegacyReport(enter, m, state, 1);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->inProximity);
    EXPECT_FALSE(s->hasPosition);
    EXPECT_EQ(state.toolId, 0x823u);
    EXPECT_EQ(state.serial, 0x12345678u);
    EXPECT_EQ(s->tool, PenTool::Pen);
    EXPECT_EQ(s->toolSerial, 0x12345678u);

    // Data: x = 20001 (BE 10000 << 1 | 1), y = 15000 (BE 7500 << 1 | 0), 11-bit pressure 1500
    // (kept as 750 of 1023), tilt x +20, tilt y -10, side button 1.
    const Bytes data{2, 0xE2, 0x27, 0x10, 0x1D, 0x4C, 0xBB, 0xAA, 0x36, 0x02};
    s = decodeWacomLegacyReport(data, m, state, 2);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->inProximity && s->touching && s->hasPosition && s->hasTilt);
    EXPECT_DOUBLE_EQ(s->positionMm.x, 20001 / 200.0);
    EXPECT_DOUBLE_EQ(s->positionMm.y, 15000 / 200.0);
    EXPECT_DOUBLE_EQ(s->pressure, 750.0 / 1023.0);
    EXPECT_DOUBLE_EQ(s->tiltRad.x, 20 * kDeg);
    EXPECT_DOUBLE_EQ(s->tiltRad.y, -10 * kDeg);
    EXPECT_EQ(s->buttons, 1u);
    EXPECT_EQ(s->toolSerial, 0x12345678u);

    const Bytes exit{2, 0x80, 0, 0, 0, 0, 0, 0, 0, 0};
    s = decodeWacomLegacyReport(exit, m, state, 3);
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->inProximity);
    EXPECT_EQ(state.tool, PenTool::None);
}

TEST(WacomLegacy, IntuosEraserAndNoExtraResolutionBit) {
    const WacomModel m = *findWacomModel(0x056a, 0x0042);
    WacomPenState state;
    const Bytes enter{2, 0xC0, 0x82, 0xA0, 0, 0, 0, 0, 0, 0};  // tool id 0x82A: eraser
    ASSERT_TRUE(decodeWacomLegacyReport(enter, m, state, 0));
    EXPECT_EQ(state.tool, PenTool::Eraser);
    const Bytes data{2, 0xE0, 0x27, 0x10, 0x1D, 0x4C, 0, 0, 0x40, 0x03};
    const auto s = decodeWacomLegacyReport(data, m, state, 0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->tool, PenTool::Eraser);
    EXPECT_DOUBLE_EQ(s->positionMm.x, 100.0);  // 10000 counts at 100/mm; [9] is not position
    EXPECT_DOUBLE_EQ(s->positionMm.y, 75.0);
    EXPECT_FALSE(s->touching);
    EXPECT_DOUBLE_EQ(s->tiltRad.y, 0.0);  // 0x40 - 64
}

TEST(WacomLegacy, ToolTypes) {
    EXPECT_EQ(wacomToolType(0x007), PenTool::Mouse);
    EXPECT_EQ(wacomToolType(0x096), PenTool::Lens);
    EXPECT_EQ(wacomToolType(0x912), PenTool::Airbrush);
    EXPECT_EQ(wacomToolType(0x85A), PenTool::Eraser);
    EXPECT_EQ(wacomToolType(0x80C), PenTool::Eraser);
    EXPECT_EQ(wacomToolType(0x852), PenTool::Pen);
    EXPECT_EQ(wacomToolType(0x823), PenTool::Pen);
}

TEST(WacomLegacy, ShortUnknownAndEmptyReports) {
    const WacomModel i3 = *findWacomModel(0x056a, 0x00B0);
    const WacomModel g = *findWacomModel(0x056a, 0x0010);
    WacomPenState state;
    DecodeStatus st;
    EXPECT_FALSE(decodeWacomLegacyReport({}, i3, state, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Empty);
    EXPECT_FALSE(decodeWacomLegacyReport(Bytes{2, 0xE0, 0, 0, 0, 0, 0, 0, 0}, i3, state, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(decodeWacomLegacyReport(Bytes{2, 0x80, 0, 0, 0, 0, 0}, g, state, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    // Report 1 is the boot-mouse mode the tablet starts in.
    EXPECT_FALSE(decodeWacomLegacyReport(Bytes{1, 0, 0, 0, 0, 0, 0, 0}, g, state, 0, &st));
    EXPECT_EQ(st, DecodeStatus::UnknownReport);
    // Packet type 7 is not a defined Intuos packet.
    EXPECT_FALSE(
        decodeWacomLegacyReport(Bytes{2, 0xEE, 0, 0, 0, 0, 0, 0, 0, 0}, i3, state, 0, &st));
    EXPECT_EQ(st, DecodeStatus::UnknownReport);
}

}  // namespace
