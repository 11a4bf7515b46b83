// SPDX-License-Identifier: MIT
// Polhemus: model table, start-up command bytes, record decoding and the stream framer, on
// records built from the documented layouts (devices_report.md §1.3).
#include "vsculpt/devices/Polhemus.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

using namespace vsculpt::devices;

namespace {

using Bytes = std::vector<uint8_t>;

void putF32(Bytes& b, float v) {
    const uint32_t u = std::bit_cast<uint32_t>(v);
    for (int k = 0; k < 4; ++k)
        b.push_back(uint8_t(u >> (8 * k)));
}
void putU32(Bytes& b, uint32_t u) {
    for (int k = 0; k < 4; ++k)
        b.push_back(uint8_t(u >> (8 * k)));
}

struct Pno {
    int station = 1;
    float pos[3] = {0, 0, 0};
    float quat[4] = {1, 0, 0, 0};
    uint32_t timeMs = 0, frame = 0;
};

// O*,2,7,8,9,0: 8-byte header, pos, quat w x y z, timestamp, frame count, ' ' = 45 bytes.
Bytes libertyRecord(const Pno& p, const char* tag = "LY", uint8_t cmd = 'C') {
    Bytes b{uint8_t(tag[0]), uint8_t(tag[1]), uint8_t(p.station), cmd, ' ', 0, 37, 0};
    for (float v : p.pos)
        putF32(b, v);
    for (float v : p.quat)
        putF32(b, v);
    putU32(b, p.timeMs);
    putU32(b, p.frame);
    b.push_back(' ');
    return b;
}

PolhemusConfig libertyConfig(PolhemusUnits units = PolhemusUnits::Centimetres) {
    PolhemusConfig c;
    c.family = PolhemusFamily::Liberty;
    c.units = units;
    return c;
}

TEST(Polhemus, ModelTable) {
    const auto hs = findPolhemusModel(0x0f44, 0xff20);
    ASSERT_TRUE(hs);
    EXPECT_EQ(hs->family, PolhemusFamily::Liberty);
    EXPECT_TRUE(hs->highSpeed);
    EXPECT_EQ(hs->writeEndpoint, 0x04);
    EXPECT_EQ(hs->readEndpoint, 0x88);
    EXPECT_TRUE(hs->supported);
    const auto loader = findPolhemusModel(0x0f44, 0xef21);
    ASSERT_TRUE(loader);
    EXPECT_TRUE(loader->needsFirmware);
    EXPECT_FALSE(loader->supported);
    const auto fastrak = findPolhemusModel(0x0f44, 0x0002);
    ASSERT_TRUE(fastrak);
    EXPECT_EQ(fastrak->family, PolhemusFamily::Fastrak);
    EXPECT_EQ(fastrak->maxStations, 4);
    EXPECT_FALSE(findPolhemusModel(0x0f44, 0x1234));
    EXPECT_FALSE(findPolhemusModel(0x046d, 0xff20));
}

std::vector<std::string> asStrings(const std::vector<Bytes>& cmds) {
    std::vector<std::string> out;
    for (const Bytes& c : cmds)
        out.emplace_back(c.begin(), c.end());
    return out;
}

TEST(Polhemus, LibertyStartupCommands) {
    auto c = defaultPolhemusConfig(*findPolhemusModel(0x0f44, 0xff20));
    EXPECT_EQ(asStrings(polhemusStartupCommands(c)),
              (std::vector<std::string>{"P\r", "F1\r", "U1\r", "O*,2,7,8,9,0\r", "@B0\r", "C\r"}));
    c.highSpeed = false;
    c.units = PolhemusUnits::Inches;
    c.station = 3;
    c.items = {PolhemusItem::Position, PolhemusItem::Euler, PolhemusItem::StylusButton,
               PolhemusItem::CrLf};
    EXPECT_EQ(asStrings(polhemusStartupCommands(c)),
              (std::vector<std::string>{"P\r", "F1\r", "U0\r", "O3,2,4,10,1\r", "C\r"}));
    EXPECT_EQ(polhemusStopCommand(PolhemusFamily::Patriot), (Bytes{'P', '\r'}));
}

TEST(Polhemus, FastrakStartupCommandsAndLimits) {
    auto c = defaultPolhemusConfig(*findPolhemusModel(0x0f44, 0x0002));
    EXPECT_EQ(asStrings(polhemusStartupCommands(c)),
              (std::vector<std::string>{"c", "f", "U", "O1,2,11,16,0\r", "O2,2,11,16,0\r",
                                        "O3,2,11,16,0\r", "O4,2,11,16,0\r", "C"}));
    EXPECT_EQ(polhemusStopCommand(PolhemusFamily::Fastrak), (Bytes{'c'}));
    c.items.push_back(PolhemusItem::Timestamp);  // FASTRAK has no such item
    EXPECT_THROW(polhemusStartupCommands(c), std::invalid_argument);
    c = defaultPolhemusConfig(*findPolhemusModel(0x0f44, 0xcf01));
    EXPECT_THROW(polhemusStartupCommands(c), std::invalid_argument);  // G4
    c = libertyConfig();
    c.station = 17;
    EXPECT_THROW(polhemusStartupCommands(c), std::invalid_argument);
}

TEST(Polhemus, RecordSizesMatchTheDocumentedLayouts) {
    EXPECT_EQ(polhemusRecordBytes(libertyConfig()), 45u);  // VRPN LibertyHS O*,2,7,8,9,0
    PolhemusConfig c = libertyConfig();
    c.items = {PolhemusItem::Timestamp, PolhemusItem::FrameCount, PolhemusItem::Distortion,
               PolhemusItem::Position, PolhemusItem::Quaternion};
    EXPECT_EQ(polhemusRecordBytes(c), 48u);  // shadow driver O*,8,9,11,3,7
    c.family = PolhemusFamily::Fastrak;
    c.items = {PolhemusItem::Position, PolhemusItem::Quaternion, PolhemusItem::Space};
    EXPECT_EQ(polhemusRecordBytes(c), 32u);  // VRPN basic FASTRAK record
}

TEST(Polhemus, LibertyRecordInCentimetres) {
    Pno p;
    p.station = 2;
    p.pos[0] = 1.5f;
    p.pos[1] = -2.25f;
    p.pos[2] = 10.0f;
    const float h = float(std::sqrt(0.5));
    p.quat[0] = h;
    p.quat[3] = h;  // 90 degrees about z
    p.timeMs = 123456;
    p.frame = 789;
    DecodeStatus st;
    const auto s = decodePolhemusRecord(libertyRecord(p), libertyConfig(), 77, &st);
    ASSERT_TRUE(s);
    EXPECT_EQ(st, DecodeStatus::Ok);
    EXPECT_EQ(s->timeNs, 77);
    EXPECT_EQ(s->station, 2);
    EXPECT_DOUBLE_EQ(s->positionMm.x, 15.0);
    EXPECT_DOUBLE_EQ(s->positionMm.y, -22.5);
    EXPECT_DOUBLE_EQ(s->positionMm.z, 100.0);
    const glm::dvec3 xAxis = s->orientation * glm::dvec3(1, 0, 0);
    EXPECT_NEAR(xAxis.x, 0.0, 1e-7);
    EXPECT_NEAR(xAxis.y, 1.0, 1e-7);
    EXPECT_TRUE(s->hasDeviceTime && s->hasFrameCount);
    EXPECT_EQ(s->deviceTimeMs, 123456u);
    EXPECT_EQ(s->frameCount, 789u);
    EXPECT_EQ(s->errorCode, ' ');
    // Patriot and Latus tags decode the same way.
    EXPECT_TRUE(decodePolhemusRecord(libertyRecord(p, "PA"), libertyConfig(), 0));
    EXPECT_TRUE(decodePolhemusRecord(libertyRecord(p, "LU"), libertyConfig(), 0));
}

TEST(Polhemus, InchesAreConvertedExactly) {
    Pno p;
    p.pos[0] = 1.0f;
    p.pos[1] = -0.5f;
    p.pos[2] = 12.0f;
    const auto s = decodePolhemusRecord(libertyRecord(p), libertyConfig(PolhemusUnits::Inches), 0);
    ASSERT_TRUE(s);
    EXPECT_DOUBLE_EQ(s->positionMm.x, 25.4);
    EXPECT_DOUBLE_EQ(s->positionMm.y, -12.7);
    EXPECT_DOUBLE_EQ(s->positionMm.z, 304.8);
}

TEST(Polhemus, EulerAnglesFollowAzimuthElevationRoll) {
    PolhemusConfig c = libertyConfig();
    c.items = {PolhemusItem::Position, PolhemusItem::Euler, PolhemusItem::StylusButton,
               PolhemusItem::CrLf};
    Bytes b{'L', 'Y', 1, 'C', ' ', 0, 30, 0};
    for (float v : {0.f, 0.f, 0.f, 90.f, 30.f, 77.f})
        putF32(b, v);
    putU32(b, 1);  // stylus pressed
    b.push_back('\r');
    b.push_back('\n');
    const auto s = decodePolhemusRecord(b, c, 0);
    ASSERT_TRUE(s);
    // R = Rz(az) Ry(el) Rx(roll) takes the sensor's x axis to (0, cos el, -sin el).
    const glm::dvec3 x = s->orientation * glm::dvec3(1, 0, 0);
    EXPECT_NEAR(x.x, 0.0, 1e-6);
    EXPECT_NEAR(x.y, std::cos(M_PI / 6), 1e-6);
    EXPECT_NEAR(x.z, -0.5, 1e-6);
    EXPECT_EQ(s->buttons, 1u);
}

TEST(Polhemus, BadRecordsAreRefusedWithAReason) {
    const PolhemusConfig c = libertyConfig();
    const Bytes good = libertyRecord(Pno{});
    DecodeStatus st;
    EXPECT_FALSE(decodePolhemusRecord({}, c, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Empty);
    EXPECT_FALSE(decodePolhemusRecord(std::span(good).first(44), c, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(decodePolhemusRecord(std::span(good).first(5), c, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    auto mutate = [&](size_t at, uint8_t v) {
        Bytes b = good;
        b[at] = v;
        decodePolhemusRecord(b, c, 0, &st);
        return st;
    };
    EXPECT_EQ(mutate(0, 'X'), DecodeStatus::Malformed);     // tag
    EXPECT_EQ(mutate(2, 0), DecodeStatus::Malformed);       // station 0
    EXPECT_EQ(mutate(2, 17), DecodeStatus::Malformed);      // station past 16
    EXPECT_EQ(mutate(6, 36), DecodeStatus::Malformed);      // length
    EXPECT_EQ(mutate(44, 'x'), DecodeStatus::Malformed);    // trailing space
    EXPECT_EQ(mutate(3, 21), DecodeStatus::UnknownReport);  // ^U reply
    EXPECT_EQ(mutate(23, 0x7f), DecodeStatus::Malformed);   // quaternion w = +infinity
    Pno zero;
    zero.quat[0] = 0;
    EXPECT_FALSE(decodePolhemusRecord(libertyRecord(zero), c, 0, &st));
    EXPECT_EQ(st, DecodeStatus::Malformed);
}

TEST(Polhemus, FastrakRecordWithStylus) {
    auto c = defaultPolhemusConfig(*findPolhemusModel(0x0f44, 0x0002));
    c.units = PolhemusUnits::Inches;
    Bytes b{'0', '3', ' '};
    for (float v : {2.f, 4.f, -8.f, 1.f, 0.f, 0.f, 0.f})
        putF32(b, v);
    b.push_back(' ');
    b.push_back('1');
    b.push_back(' ');
    ASSERT_EQ(b.size(), polhemusRecordBytes(c));
    const auto s = decodePolhemusRecord(b, c, 5);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->station, 3);
    EXPECT_DOUBLE_EQ(s->positionMm.x, 50.8);
    EXPECT_DOUBLE_EQ(s->positionMm.z, -203.2);
    EXPECT_EQ(s->buttons, 1u);
    b[1] = '5';  // FASTRAK has 4 stations
    EXPECT_FALSE(decodePolhemusRecord(b, c, 0));
}

TEST(Polhemus, FramerSurvivesArbitraryChunksGarbageAndReplies) {
    const PolhemusConfig c = libertyConfig();
    Bytes stream;
    std::vector<Pno> sent;
    size_t garbage = 0;
    for (int i = 0; i < 12; ++i) {
        Pno p;
        p.station = 1 + i % 3;
        p.pos[0] = float(i);
        p.frame = uint32_t(i);
        sent.push_back(p);
        const Bytes r = libertyRecord(p);
        stream.insert(stream.end(), r.begin(), r.end());
        if (i == 3) {  // noise that only looks like the start of a header
            for (uint8_t g : Bytes{'x', 'L', 'Q', 'L', 'Y', 2, 'C'})
                stream.push_back(g);
            garbage += 7;
        }
        if (i == 7) {  // a well-framed reply to ^U: header + 4 bytes
            for (uint8_t g : Bytes{'L', 'Y', 1, 21, ' ', 0, 4, 0, 1, 0, 1, 0})
                stream.push_back(g);
        }
    }
    std::mt19937 rng(11);
    std::uniform_int_distribution<size_t> chunk(1, 17);
    PolhemusStreamDecoder dec(c);
    std::vector<TrackerSample> out;
    for (size_t at = 0; at < stream.size();) {
        const size_t n = std::min(chunk(rng), stream.size() - at);
        dec.feed(std::span(stream).subspan(at, n), int64_t(at), out);
        at += n;
    }
    ASSERT_EQ(out.size(), sent.size());
    for (size_t i = 0; i < sent.size(); ++i) {
        EXPECT_EQ(out[i].station, sent[i].station);
        EXPECT_DOUBLE_EQ(out[i].positionMm.x, 10.0 * sent[i].pos[0]);
        EXPECT_EQ(out[i].frameCount, sent[i].frame);
    }
    EXPECT_EQ(dec.droppedBytes(), garbage);
    EXPECT_EQ(dec.otherReplies(), 1u);
    EXPECT_EQ(dec.records(), sent.size());
    EXPECT_EQ(dec.pendingBytes(), 0u);
}

TEST(Polhemus, FramerWaitsForTheRestOfARecord) {
    PolhemusStreamDecoder dec(libertyConfig());
    const Bytes r = libertyRecord(Pno{});
    std::vector<TrackerSample> out;
    EXPECT_EQ(dec.feed(std::span(r).first(44), 1, out), 0u);
    EXPECT_EQ(dec.pendingBytes(), 44u);
    EXPECT_EQ(dec.feed(std::span(r).last(1), 2, out), 1u);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].timeNs, 2);  // stamped with the read that completed it
    EXPECT_EQ(dec.droppedBytes(), 0u);
}

}  // namespace
