// SPDX-License-Identifier: MIT
// The HID report-descriptor parser, the field extractor and the two decoders built on them:
// on real descriptors (SpaceNavigator, SpaceMouse Wireless, XP-Pen Deco 01 V3, Goodix GXTP; see
// tests/data/devices/*.hex for their sources) and on small synthetic ones for each parser rule.
#include "vsculpt/devices/HidDescriptor.h"
#include "vsculpt/devices/HidDigitizer.h"
#include "vsculpt/devices/HidMultiAxis.h"
#include "vsculpt/devices/SpaceMouse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

using namespace vsculpt::devices;

namespace {

using Bytes = std::vector<uint8_t>;
constexpr double kDeg = M_PI / 180.0;

Bytes loadHex(const std::string& name) {
    std::ifstream in(std::string(VSCULPT_DEVICES_DATA_DIR) + "/" + name);
    EXPECT_TRUE(in) << name;
    Bytes out;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream words(line);
        std::string w;
        while (words >> w)
            out.push_back(uint8_t(std::stoul(w, nullptr, 16)));
    }
    return out;
}

HidDescriptor parseOrFail(const Bytes& b) {
    std::string err;
    auto d = parseHidDescriptor(b, &err);
    EXPECT_TRUE(d) << err;
    return d ? *d : HidDescriptor{};
}

// ---- SpaceNavigator (3D mouse) -------------------------------------------------------------

TEST(HidDescriptor, SpaceNavigatorLayout) {
    const Bytes raw = loadHex("spacenavigator.rdesc.hex");
    ASSERT_EQ(raw.size(), 217u);
    // The Rel flag the kernel quirk looks for sits at offsets 36/53 in this production run.
    EXPECT_EQ(raw[36], 0x81);
    EXPECT_EQ(raw[37], 0x06);
    EXPECT_EQ(raw[53], 0x81);
    EXPECT_EQ(raw[54], 0x06);
    const HidDescriptor d = parseOrFail(raw);
    EXPECT_TRUE(d.usesReportIds);

    const HidReport* t = d.find(HidReportKind::Input, 1);
    ASSERT_TRUE(t);
    EXPECT_EQ(t->byteLength(), 7u);
    ASSERT_EQ(t->fields.size(), 1u);
    const HidField& xyz = t->fields[0];
    EXPECT_EQ(xyz.bitOffset, 8u);
    EXPECT_EQ(xyz.bitSize, 16u);
    EXPECT_EQ(xyz.count, 3u);
    EXPECT_EQ(xyz.usages, (std::vector<uint32_t>{0x10030, 0x10031, 0x10032}));
    EXPECT_EQ(xyz.logicalMin, -350);
    EXPECT_EQ(xyz.logicalMax, 350);
    EXPECT_EQ(xyz.physicalMin, -1400);
    EXPECT_EQ(xyz.physicalMax, 1400);
    EXPECT_EQ(xyz.unit, 0x11u);
    EXPECT_EQ(xyz.unitExponent, -4);
    EXPECT_EQ(xyz.flags, uint32_t(HidVariable | HidRelative));
    EXPECT_EQ(xyz.applicationUsage, hidUsage(1, 0x08));

    const HidReport* r = d.find(HidReportKind::Input, 2);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->fields[0].usages, (std::vector<uint32_t>{0x10033, 0x10034, 0x10035}));
    EXPECT_EQ(r->fields[0].logicalMin, -350);  // globals carry over from report 1

    const HidReport* b = d.find(HidReportKind::Input, 3);
    ASSERT_TRUE(b);
    EXPECT_EQ(b->byteLength(), 3u);
    ASSERT_EQ(b->fields.size(), 2u);
    EXPECT_EQ(b->fields[0].usages, (std::vector<uint32_t>{0x90001, 0x90002}));  // usage range
    EXPECT_EQ(b->fields[0].bitSize, 1u);
    EXPECT_TRUE(b->fields[1].isConstant());
    EXPECT_EQ(b->fields[1].bitOffset, 10u);
    EXPECT_EQ(b->fields[1].count, 14u);

    const HidReport* led = d.find(HidReportKind::Output, 4);
    ASSERT_TRUE(led);
    EXPECT_EQ(led->byteLength(), 2u);
    EXPECT_EQ(led->fields[0].usages, (std::vector<uint32_t>{0x8004B}));

    const HidReport* f8 = d.find(HidReportKind::Feature, 8);
    ASSERT_TRUE(f8);
    EXPECT_EQ(f8->byteLength(), 8u);
    EXPECT_EQ(f8->fields[0].usages, (std::vector<uint32_t>{0xFF000023}));
    EXPECT_EQ(f8->fields[0].logicalMin, -128);
    ASSERT_TRUE(d.find(HidReportKind::Feature, 0x13));
    EXPECT_FALSE(d.find(HidReportKind::Input, 4));
}

TEST(HidMultiAxis, SpaceNavigatorMatchesTheHandWrittenDecoder) {
    const HidDescriptor d = parseOrFail(loadHex("spacenavigator.rdesc.hex"));
    std::string err;
    const auto dec = HidMultiAxisDecoder::fromDescriptor(d, &err);
    ASSERT_TRUE(dec) << err;
    // ±350 counts are ±1400e-4 cm = ±1.4 mm of knob travel.
    ASSERT_TRUE(dec->translationMmPerCount());
    EXPECT_NEAR(*dec->translationMmPerCount(), 1.4 / 350, 1e-15);

    // The captured report: rotation around the second axis.
    const Bytes captured{0x02, 0x00, 0x00, 0xe2, 0xff, 0x00, 0x00};
    const auto c = dec->decode(captured, 0);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->rotation, (std::array<int16_t, 3>{0, -30, 0}));

    std::mt19937 rng(3);
    std::uniform_int_distribution<int> axis(-350, 350), byte(0, 255), id(1, 3);
    for (int i = 0; i < 2000; ++i) {
        Bytes rep{uint8_t(id(rng))};
        if (rep[0] == 3) {
            rep.push_back(uint8_t(byte(rng) & 3));
            rep.push_back(0);
        } else {
            for (int a = 0; a < 3; ++a) {
                const int v = axis(rng);
                rep.push_back(uint8_t(v & 0xFF));
                rep.push_back(uint8_t((v >> 8) & 0xFF));
            }
        }
        const auto generic = dec->decode(rep, i);
        const auto manual = decodeSpaceMouseReport(rep, i);
        ASSERT_TRUE(generic && manual);
        EXPECT_EQ(generic->hasTranslation, manual->hasTranslation);
        EXPECT_EQ(generic->hasRotation, manual->hasRotation);
        EXPECT_EQ(generic->hasButtons, manual->hasButtons);
        EXPECT_EQ(generic->translation, manual->translation);
        EXPECT_EQ(generic->rotation, manual->rotation);
        EXPECT_EQ(generic->buttons, manual->buttons);
    }
    DecodeStatus st;
    EXPECT_FALSE(dec->decode(Bytes{1, 0, 0}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(dec->decode(Bytes{4, 1}, 0, &st));  // an output report id, not an input
    EXPECT_EQ(st, DecodeStatus::UnknownReport);
}

TEST(HidMultiAxis, SpaceMouseWirelessSixAxesAndBattery) {
    const Bytes raw = loadHex("spacemouse-wireless.rdesc.hex");
    ASSERT_EQ(raw.size(), 270u);
    const HidDescriptor d = parseOrFail(raw);
    const HidReport* six = d.find(HidReportKind::Input, 1);
    ASSERT_TRUE(six);
    EXPECT_EQ(six->byteLength(), 13u);
    EXPECT_EQ(six->fields[0].flags, uint32_t(HidVariable));  // Abs on this model
    const HidReport* battery = d.find(HidReportKind::Input, 0x17);
    ASSERT_TRUE(battery);
    EXPECT_EQ(battery->byteLength(), 3u);
    EXPECT_EQ(battery->fields[0].usages, (std::vector<uint32_t>{hidUsage(0x06, 0x20)}));
    ASSERT_TRUE(d.find(HidReportKind::Feature, 0x1A));

    const auto dec = HidMultiAxisDecoder::fromDescriptor(d);
    ASSERT_TRUE(dec);
    std::mt19937 rng(8);
    std::uniform_int_distribution<int> axis(-350, 350);
    for (int i = 0; i < 500; ++i) {
        Bytes rep{1};
        for (int a = 0; a < 6; ++a) {
            const int v = axis(rng);
            rep.push_back(uint8_t(v & 0xFF));
            rep.push_back(uint8_t((v >> 8) & 0xFF));
        }
        const auto generic = dec->decode(rep, 0);
        const auto manual = decodeSpaceMouseReport(rep, 0);
        ASSERT_TRUE(generic && manual);
        EXPECT_TRUE(generic->hasTranslation && generic->hasRotation);
        EXPECT_EQ(generic->translation, manual->translation);
        EXPECT_EQ(generic->rotation, manual->rotation);
    }
    const Bytes level{0x17, 87, 0x01};  // 87 %, vendor bit set
    const auto g = dec->decode(level, 0);
    const auto m = decodeSpaceMouseReport(level, 0);
    ASSERT_TRUE(g && m);
    EXPECT_TRUE(g->hasBattery);
    EXPECT_EQ(g->battery, 87);
    EXPECT_EQ(g->battery, m->battery);
}

// ---- XP-Pen Deco 01 V3 (pen tablet) --------------------------------------------------------

TEST(HidDescriptor, XpPenLayoutPushPopAndSignedTilt) {
    const Bytes raw = loadHex("xppen-deco01v3-pen.rdesc.hex");
    ASSERT_EQ(raw.size(), 109u);
    const HidDescriptor d = parseOrFail(raw);
    const HidReport* r = d.find(HidReportKind::Input, 7);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->byteLength(), 10u);
    EXPECT_EQ(d.reports.size(), 1u);

    auto field = [&](uint32_t usage) {
        const auto ref = d.findUsage(HidReportKind::Input, usage);
        EXPECT_TRUE(ref) << std::hex << usage;
        return ref ? *ref : HidDescriptor::FieldRef{};
    };
    const auto tip = field(hidUsage(0x0D, 0x42)), inRange = field(hidUsage(0x0D, 0x32));
    EXPECT_EQ(tip.field->bitOffset + tip.index, 8u);
    EXPECT_EQ(inRange.field->bitOffset + inRange.index, 13u);

    const auto x = field(hidUsage(0x01, 0x30));
    EXPECT_EQ(x.field->bitOffset, 16u);
    EXPECT_EQ(x.field->logicalMax, 32767);
    EXPECT_EQ(x.field->physicalMax, 10000);
    EXPECT_EQ(x.field->unit, 0x13u);  // inch
    EXPECT_EQ(x.field->unitExponent, -3);
    const auto y = field(hidUsage(0x01, 0x31));
    EXPECT_EQ(y.field->bitOffset, 32u);
    EXPECT_EQ(y.field->physicalMax, 6250);

    // After Pop the page is Digitizer again, so "Usage 0x30" is Tip Pressure, and the unit and
    // physical range pushed before X are back (none).
    const auto p = field(hidUsage(0x0D, 0x30));
    EXPECT_EQ(p.field->bitOffset, 48u);
    EXPECT_EQ(p.field->logicalMax, 16383);
    EXPECT_EQ(p.field->unit, 0u);
    EXPECT_EQ(p.field->physicalMax, 0);
    EXPECT_TRUE(p.field->flags & HidNullState);

    const auto tx = field(hidUsage(0x0D, 0x3D)), ty = field(hidUsage(0x0D, 0x3E));
    EXPECT_EQ(tx.field->bitOffset, 64u);
    EXPECT_EQ(ty.field->bitOffset, 72u);
    EXPECT_EQ(tx.field->logicalMin, -127);
    EXPECT_EQ(tx.field->logicalMax, 127);
    const Bytes rep{7, 0, 0, 0, 0, 0, 0, 0, 0xE2, 0x2D};
    EXPECT_EQ(extractField(rep, *tx.field, tx.index), -30);
    EXPECT_EQ(extractField(rep, *ty.field, ty.index), 45);
}

TEST(HidDigitizer, XpPenReportsDecodeToMillimetres) {
    const HidDescriptor d = parseOrFail(loadHex("xppen-deco01v3-pen.rdesc.hex"));
    std::string err;
    const auto dec = HidDigitizerDecoder::fromDescriptor(d, &err);
    ASSERT_TRUE(dec) << err;
    EXPECT_EQ(dec->reportId(), 7);
    EXPECT_TRUE(dec->hasPhysicalSize());
    EXPECT_DOUBLE_EQ(dec->widthMm(), 254.0);    // 10.000 in
    EXPECT_DOUBLE_EQ(dec->heightMm(), 158.75);  // 6.250 in

    // Tip + barrel + in range; x = 16384, y = 32767, pressure 8192, tilt (-30, 45).
    const Bytes touch{7, 0x23, 0x00, 0x40, 0xFF, 0x7F, 0x00, 0x20, 0xE2, 0x2D};
    DecodeStatus st;
    auto s = dec->decode(touch, 123, &st);
    ASSERT_TRUE(s);
    EXPECT_EQ(st, DecodeStatus::Ok);
    EXPECT_EQ(s->timeNs, 123);
    EXPECT_TRUE(s->inProximity && s->touching && s->hasPosition && s->hasTilt);
    EXPECT_EQ(s->tool, PenTool::Pen);
    EXPECT_EQ(s->buttons, 1u);
    EXPECT_NEAR(s->positionMm.x, 16384.0 / 32767.0 * 254.0, 1e-9);
    EXPECT_NEAR(s->positionMm.y, 158.75, 1e-9);
    EXPECT_NEAR(s->positionNormalized.y, 1.0, 1e-12);
    EXPECT_NEAR(s->pressure, 8192.0 / 16383.0, 1e-12);
    EXPECT_NEAR(s->tiltRad.x, -30 * kDeg, 1e-12);  // no unit: read as degrees
    EXPECT_NEAR(s->tiltRad.y, 45 * kDeg, 1e-12);

    const Bytes hoverInverted{7, 0x28, 0, 0, 0, 0, 0, 0, 0, 0};  // invert + in range
    s = dec->decode(hoverInverted, 0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->tool, PenTool::Eraser);
    EXPECT_TRUE(s->inProximity);
    EXPECT_FALSE(s->touching);

    const Bytes erasing{7, 0x04, 0, 0, 0, 0, 0, 0x10, 0, 0};  // eraser contact, no in-range
    s = dec->decode(erasing, 0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->tool, PenTool::Eraser);
    EXPECT_TRUE(s->touching && s->inProximity);

    const Bytes away{7, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    s = dec->decode(away, 0);
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->inProximity);
    EXPECT_EQ(s->tool, PenTool::None);

    EXPECT_FALSE(dec->decode(std::span(touch).first(9), 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(dec->decode(Bytes{6, 0, 0, 0, 0, 0, 0, 0, 0, 0}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::UnknownReport);
    EXPECT_FALSE(dec->decode({}, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Empty);
}

TEST(HidDigitizer, TouchScreenWithPenPicksThePenReport) {
    const Bytes raw = loadHex("goodix-gxtp-27c6-0113.rdesc.hex");
    ASSERT_EQ(raw.size(), 519u);
    const HidDescriptor d = parseOrFail(raw);
    // Finger report 1 (five contacts) also has Tip Switch and X/Y, and comes first.
    const HidReport* fingers = d.find(HidReportKind::Input, 1);
    ASSERT_TRUE(fingers);
    EXPECT_EQ(fingers->fields.front().applicationUsage, hidUsage(0x0D, 0x04));
    const auto dec = HidDigitizerDecoder::fromDescriptor(d);
    ASSERT_TRUE(dec);
    EXPECT_EQ(dec->reportId(), 8);
    EXPECT_EQ(dec->reportBytes(), 13u);
    EXPECT_NEAR(dec->widthMm(), 182.3, 1e-9);   // 1823e-2 cm
    EXPECT_NEAR(dec->heightMm(), 114.3, 1e-9);  // 1143e-2 cm

    // Tip + in range; x = 2560 of 5120, y = 3200 of 3200, pressure 2048 of 4095,
    // tilt (+4500, -1500) hundredths of a degree.
    const Bytes pen{8, 0x21, 0, 0x00, 0x0A, 0x80, 0x0C, 0x00, 0x08, 0x94, 0x11, 0x24, 0xFA};
    const auto s = dec->decode(pen, 0);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->touching && s->inProximity);
    EXPECT_EQ(s->tool, PenTool::Pen);
    EXPECT_NEAR(s->positionMm.x, 91.15, 1e-9);
    EXPECT_NEAR(s->positionMm.y, 114.3, 1e-9);
    EXPECT_NEAR(s->pressure, 2048.0 / 4095.0, 1e-12);
    EXPECT_NEAR(s->tiltRad.x, 45 * kDeg, 1e-12);
    EXPECT_NEAR(s->tiltRad.y, -15 * kDeg, 1e-12);
    // The controller drops In Range while the tip touches and moves: still in proximity.
    const Bytes touchNoRange{8, 0x01, 0, 0x00, 0x0A, 0x80, 0x0C, 0x00, 0x08, 0, 0, 0, 0};
    EXPECT_TRUE(dec->decode(touchNoRange, 0)->inProximity);
    DecodeStatus st;
    EXPECT_FALSE(dec->decode(Bytes{1, 1, 0, 0, 0, 0, 0}, 0, &st));  // a finger report
    EXPECT_EQ(st, DecodeStatus::UnknownReport);
}

TEST(HidDigitizer, RefusesADescriptorWithoutAPen) {
    const HidDescriptor d = parseOrFail(loadHex("spacenavigator.rdesc.hex"));
    std::string err;
    EXPECT_FALSE(HidDigitizerDecoder::fromDescriptor(d, &err));
    EXPECT_NE(err.find("Tip Switch"), std::string::npos);
    const HidDescriptor pen = parseOrFail(loadHex("xppen-deco01v3-pen.rdesc.hex"));
    EXPECT_FALSE(HidMultiAxisDecoder::fromDescriptor(pen, &err));
}

TEST(HidDigitizer, WacomVendorPageMirrorsStandardUsages) {
    EXPECT_EQ(hidEquivalentPenUsage(0xFF0D0130), hidUsage(0x01, 0x30));
    EXPECT_EQ(hidEquivalentPenUsage(0xFF0D0042), hidUsage(0x0D, 0x42));
    EXPECT_EQ(hidEquivalentPenUsage(0xFF0D003D), hidUsage(0x0D, 0x3D));
    EXPECT_EQ(hidEquivalentPenUsage(hidUsage(0x0D, 0x30)), hidUsage(0x0D, 0x30));
    // A minimal Wacom-style pen: page 0xFF0D, X in cm with exponent -3, tilt in degrees.
    const Bytes desc{
        0x06, 0x0D, 0xFF, 0x09, 0x01, 0xA1, 0x01, 0x85, 0x10,  // app, report 16
        0x09, 0x42, 0x09, 0x32, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x02, 0x81, 0x02,
        0x95, 0x06, 0x81, 0x03,  // tip, range, pad
        0x0A, 0x30, 0x01, 0x0A, 0x31, 0x01, 0x65, 0x11, 0x55, 0x0D, 0x35, 0x00, 0x46, 0x80,
        0x57, 0x27, 0x00, 0xAF, 0x00, 0x00, 0x75, 0x18, 0x95, 0x02, 0x81, 0x02,  // X, Y 24-bit
        0x09, 0x3D, 0x65, 0x14, 0x55, 0x00, 0x35, 0xC0, 0x45, 0x3F, 0x15, 0xC0, 0x25, 0x3F,
        0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0x09, 0x3E, 0x81, 0x02, 0xC0};
    const HidDescriptor d = parseOrFail(desc);
    const auto dec = HidDigitizerDecoder::fromDescriptor(d);
    ASSERT_TRUE(dec);
    EXPECT_DOUBLE_EQ(dec->widthMm(), 224.0);  // 22400e-3 cm
    // x = 44800 (full width), y = 22400; tilt (-64, 63) degrees.
    const Bytes rep{0x10, 0x03, 0x00, 0xAF, 0x00, 0x80, 0x57, 0x00, 0xC0, 0x3F};
    const auto s = dec->decode(rep, 0);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->touching);
    EXPECT_NEAR(s->positionMm.x, 224.0, 1e-9);
    EXPECT_NEAR(s->positionMm.y, 112.0, 1e-9);
    EXPECT_NEAR(s->tiltRad.x, -64 * kDeg, 1e-12);
    EXPECT_NEAR(s->tiltRad.y, 63 * kDeg, 1e-12);
}

// ---- parser rules on small synthetic descriptors --------------------------------------------

TEST(HidDescriptor, ExtractorBitOrderSignAndBounds) {
    const Bytes r{0xAB, 0xCD, 0xEF, 0x01};
    EXPECT_EQ(extractBits(r, 0, 8), 0xABu);
    EXPECT_EQ(extractBits(r, 4, 8), 0xDAu);  // high nibble of byte 0, low nibble of byte 1
    EXPECT_EQ(extractBits(r, 12, 12), 0xEFCu);
    EXPECT_EQ(extractBits(r, 0, 32), 0x01EFCDABu);
    EXPECT_EQ(extractBits(r, 31, 1), 0u);
    EXPECT_FALSE(extractBits(r, 25, 8));  // one bit past the end
    EXPECT_FALSE(extractBits(r, 0, 0));
    EXPECT_FALSE(extractBits(r, 0, 65));
    HidField f;
    f.bitOffset = 12;
    f.bitSize = 12;
    f.count = 1;
    f.logicalMin = -2048;
    f.logicalMax = 2047;
    EXPECT_EQ(extractField(r, f), int32_t(0xEFC) - 4096);  // sign-extended
    f.logicalMin = 0;
    f.logicalMax = 4095;
    EXPECT_EQ(extractField(r, f), 0xEFC);
    EXPECT_FALSE(extractField(r, f, 1));  // only one element
    f.count = 2;
    EXPECT_FALSE(extractField(r, f, 1));  // element 1 would end past the report
}

TEST(HidDescriptor, UnsignedMaximumRangesLongItemsAndExtendedUsages) {
    const Bytes desc{0x05, 0x01, 0x09, 0x04, 0xA1, 0x01,  // Generic Desktop, Joystick, application
                     0xFE, 0x02, 0x77, 0xAA, 0xBB,        // long item (skipped)
                     0x15, 0x00, 0x25, 0xFF,              // logical 0..255 written as 0xFF
                     0x0B, 0x36, 0x00, 0x02, 0x00,        // 4-byte usage: page 0x0002, id 0x36
                     0x19, 0x30, 0x29, 0x31,              // usage range X..Y
                     0x75, 0x08, 0x95, 0x03, 0x81, 0x02,  // 3 x 8 bits, no report ids
                     0x55, 0x0F, 0x65, 0x12,              // exponent -1, radians
                     0x09, 0x35, 0x95, 0x01, 0x81, 0x02,  // Rz
                     0xC0};
    const HidDescriptor d = parseOrFail(desc);
    EXPECT_FALSE(d.usesReportIds);
    const HidReport* r = d.find(HidReportKind::Input, 0);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->byteLength(), 4u);
    ASSERT_EQ(r->fields.size(), 2u);
    EXPECT_EQ(r->fields[0].bitOffset, 0u);  // no id byte
    EXPECT_EQ(r->fields[0].logicalMax, 255);
    EXPECT_EQ(r->fields[0].usages, (std::vector<uint32_t>{0x00020036, 0x10030, 0x10031}));
    EXPECT_EQ(r->fields[0].applicationUsage, hidUsage(1, 0x04));
    EXPECT_EQ(r->fields[1].unitExponent, -1);
    EXPECT_NEAR(*hidRadiansPerUnit(r->fields[1]), 0.1, 1e-15);
    EXPECT_FALSE(hidMillimetresPerUnit(r->fields[1]));
    EXPECT_EQ(extractField(Bytes{0, 0, 0xFF, 0}, r->fields[0], 2), 255);  // not -1
}

TEST(HidDescriptor, MalformedDescriptorsSayWhatAndWhere) {
    auto err = [](const Bytes& b) {
        std::string e;
        EXPECT_FALSE(parseHidDescriptor(b, &e));
        return e;
    };
    EXPECT_NE(err({}).find("empty"), std::string::npos);
    EXPECT_NE(err({0x05, 0x01, 0x26, 0xFF}).find("byte 2: item data past the end"),
              std::string::npos);
    EXPECT_NE(err({0xB4}).find("Pop without Push"), std::string::npos);
    EXPECT_NE(err({0xC0}).find("End Collection without Collection"), std::string::npos);
    EXPECT_NE(err({0xA1, 0x01}).find("unclosed collection"), std::string::npos);
    EXPECT_NE(err({0x85, 0x00}).find("Report ID 0"), std::string::npos);
    EXPECT_NE(err({0x76, 0x01, 0x01, 0x95, 0x01, 0x81, 0x02}).find("Report Size 257"),
              std::string::npos);
    EXPECT_NE(err({0xFE, 0x09, 0x00, 0x01}).find("long item"), std::string::npos);
    Bytes deep;
    for (int i = 0; i < 40; ++i)
        deep.push_back(0xA4);
    EXPECT_NE(err(deep).find("Push nested too deep"), std::string::npos);
}

}  // namespace
