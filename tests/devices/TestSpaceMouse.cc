// SPDX-License-Identifier: MIT
// The 3D-mouse decoder on byte vectors built from the documented layouts
// (devices_report.md §2.2), including short and garbage input.
#include "vsculpt/devices/SpaceMouse.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace vsculpt::devices;

namespace {

std::vector<uint8_t> le16(std::initializer_list<int> values, uint8_t id) {
    std::vector<uint8_t> r{id};
    for (int v : values) {
        r.push_back(uint8_t(v & 0xFF));
        r.push_back(uint8_t((v >> 8) & 0xFF));
    }
    return r;
}

TEST(SpaceMouse, SeparateTranslationAndRotationReports) {
    DecodeStatus st;
    const auto t = decodeSpaceMouseReport(le16({100, -350, 7}, 1), 42, &st);
    ASSERT_TRUE(t);
    EXPECT_EQ(st, DecodeStatus::Ok);
    EXPECT_EQ(t->timeNs, 42);
    EXPECT_TRUE(t->hasTranslation);
    EXPECT_FALSE(t->hasRotation);
    EXPECT_EQ(t->translation, (std::array<int16_t, 3>{100, -350, 7}));
    const auto r = decodeSpaceMouseReport(le16({-1, 350, -32768}, 2), 43);
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->hasRotation);
    EXPECT_FALSE(r->hasTranslation);
    EXPECT_EQ(r->rotation, (std::array<int16_t, 3>{-1, 350, -32768}));
}

TEST(SpaceMouse, CombinedSixAxisReport) {
    const auto s = decodeSpaceMouseReport(le16({1, 2, 3, -4, -5, -6}, 1), 0);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->hasTranslation && s->hasRotation);
    EXPECT_EQ(s->translation, (std::array<int16_t, 3>{1, 2, 3}));
    EXPECT_EQ(s->rotation, (std::array<int16_t, 3>{-4, -5, -6}));
}

TEST(SpaceMouse, ButtonsAndBattery) {
    // Observed: 03 01 00 = button 1, 03 02 00 = button 2, 03 03 00 = both.
    EXPECT_EQ(decodeSpaceMouseReport(std::vector<uint8_t>{3, 1, 0}, 0)->buttons, 1u);
    EXPECT_EQ(decodeSpaceMouseReport(std::vector<uint8_t>{3, 2, 0}, 0)->buttons, 2u);
    EXPECT_EQ(decodeSpaceMouseReport(std::vector<uint8_t>{3, 3, 0}, 0)->buttons, 3u);
    EXPECT_EQ(decodeSpaceMouseReport(std::vector<uint8_t>{3, 0, 0x80, 0x01}, 0)->buttons,
              0x18000u);  // button 16 and 17 on bigger models
    const auto b = decodeSpaceMouseReport(std::vector<uint8_t>{0x17, 87}, 0);
    ASSERT_TRUE(b);
    EXPECT_TRUE(b->hasBattery);
    EXPECT_EQ(b->battery, 87);
}

TEST(SpaceMouse, ShortAndUnknownReportsAreRefused) {
    DecodeStatus st;
    EXPECT_FALSE(decodeSpaceMouseReport({}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Empty);
    EXPECT_FALSE(decodeSpaceMouseReport(std::vector<uint8_t>{1, 0x10, 0x00, 0x20}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(decodeSpaceMouseReport(std::vector<uint8_t>{2, 1}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(decodeSpaceMouseReport(std::vector<uint8_t>{3}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(decodeSpaceMouseReport(std::vector<uint8_t>{9, 1, 2, 3}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::UnknownReport);
    EXPECT_STREQ(toString(st), "unknown report id");
}

TEST(SpaceMouse, RandomBytesNeverCrashOrReadPastTheEnd) {
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> len(0, 20), byte(0, 255);
    int decoded = 0;
    for (int i = 0; i < 200000; ++i) {
        std::vector<uint8_t> r(size_t(len(rng)));
        for (auto& b : r)
            b = uint8_t(byte(rng));
        if (!r.empty() && i % 2) r[0] = uint8_t(1 + i % 3);  // often a known id
        decoded += decodeSpaceMouseReport(r, i).has_value();
    }
    EXPECT_GT(decoded, 50000);
}

TEST(SpaceMouse, AxisMappingScalesClampsDeadZonesAndSwapsYZ) {
    AxisMapping m;
    m.swapInvertYZ = false;
    auto a = mapAxes({175, -350, 3}, {700, 0, -6}, m);
    EXPECT_DOUBLE_EQ(a.translation[0], 0.5);
    EXPECT_DOUBLE_EQ(a.translation[1], -1.0);
    EXPECT_DOUBLE_EQ(a.translation[2], 0.0);  // 3/350 < 2% dead zone
    EXPECT_DOUBLE_EQ(a.rotation[0], 1.0);     // clamped
    EXPECT_DOUBLE_EQ(a.rotation[2], 0.0);     // 6/350 < 2%
    EXPECT_DOUBLE_EQ(mapAxes({0, 0, 7}, {0, 0, 0}, m).translation[2], 0.02);  // at the edge: kept
    m.swapInvertYZ = true;
    a = mapAxes({0, 175, -350}, {0, 0, 0}, m);
    EXPECT_DOUBLE_EQ(a.translation[1], 1.0);   // y <- -z
    EXPECT_DOUBLE_EQ(a.translation[2], -0.5);  // z <- -y
}

TEST(SpaceMouse, ModelTable) {
    const auto nav = findSpaceMouseModel(0x046d, 0xc626);
    ASSERT_TRUE(nav);
    EXPECT_STREQ(nav->name, "SpaceNavigator");
    EXPECT_TRUE(nav->swapInvertYZ);
    EXPECT_TRUE(findSpaceMouseModel(0x256f, 0xc635));
    EXPECT_FALSE(findSpaceMouseModel(0x046d, 0xc650));  // a CadMouse: not a 3D mouse
}

}  // namespace
