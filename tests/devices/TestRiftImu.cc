// SPDX-License-Identifier: MIT
// The Rift tracker-report decoder and stream on byte vectors built from the documented
// layouts (devices_report.md §4.1), including negative 21-bit values, short and garbage
// input, timestamp wrap, out-of-order and dropped reports.
#include "vsculpt/devices/RiftImu.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace vsculpt::devices;

namespace {

using Vec21 = std::array<int32_t, 3>;

// Packs three 21-bit two's-complement values MSB first into 8 bytes (the reverse of the
// documented unpacking: x in bits 63..43, y in 42..22, z in 21..1 of a big-endian word).
std::array<uint8_t, 8> pack21(const Vec21& v) {
    constexpr uint64_t kMask = 0x1FFFFF;
    const uint64_t word = (uint64_t(uint32_t(v[0])) & kMask) << 43 |
                          (uint64_t(uint32_t(v[1])) & kMask) << 22 |
                          (uint64_t(uint32_t(v[2])) & kMask) << 1;
    std::array<uint8_t, 8> b{};
    for (int i = 0; i < 8; ++i)
        b[size_t(i)] = uint8_t(word >> (56 - 8 * i));
    return b;
}

void put16(std::vector<uint8_t>& r, size_t at, int v) {
    r[at] = uint8_t(v & 0xFF);
    r[at + 1] = uint8_t((v >> 8) & 0xFF);
}

void put32(std::vector<uint8_t>& r, size_t at, uint32_t v) {
    for (size_t i = 0; i < 4; ++i)
        r[at + i] = uint8_t(v >> (8 * i));
}

struct Slot {
    Vec21 accel{}, gyro{};
};

void putSlots(std::vector<uint8_t>& r, size_t at, const std::vector<Slot>& slots) {
    for (size_t i = 0; i < slots.size(); ++i) {
        const auto a = pack21(slots[i].accel), g = pack21(slots[i].gyro);
        std::copy(a.begin(), a.end(), r.begin() + long(at + 16 * i));
        std::copy(g.begin(), g.end(), r.begin() + long(at + 16 * i + 8));
    }
}

std::vector<uint8_t> dk1Report(int num, uint16_t timestampMs, const std::vector<Slot>& slots = {},
                               int temperature = 0, std::array<int, 3> mag = {}, int cmd = 0) {
    std::vector<uint8_t> r(62, 0);
    r[0] = 1;
    r[1] = uint8_t(num);
    put16(r, 2, timestampMs);
    put16(r, 4, cmd);
    put16(r, 6, temperature);
    putSlots(r, 8, slots);
    for (size_t a = 0; a < 3; ++a)
        put16(r, 56 + 2 * a, mag[a]);
    return r;
}

std::vector<uint8_t> dk2Report(int num, uint32_t timestampUs, uint16_t total,
                               const std::vector<Slot>& slots = {}, int temperature = 0,
                               std::array<int, 3> mag = {}, int cmd = 0) {
    std::vector<uint8_t> r(64, 0);
    r[0] = 11;
    put16(r, 1, cmd);
    r[3] = uint8_t(num);
    put16(r, 4, total);
    put16(r, 6, temperature);
    put32(r, 8, timestampUs);
    putSlots(r, 12, slots);
    for (size_t a = 0; a < 3; ++a)
        put16(r, 44 + 2 * a, mag[a]);
    return r;
}

TEST(RiftImu, Unpack21HandBuiltVectors) {
    // x = -1, y = 0, z = 1.
    const std::array<uint8_t, 8> a{0xFF, 0xFF, 0xF8, 0x00, 0x00, 0x00, 0x00, 0x02};
    EXPECT_EQ(unpackRift21(a), (Vec21{-1, 0, 1}));
    // The extremes: x = -2^20, y = 2^20 - 1, z = -2.
    const std::array<uint8_t, 8> b{0x80, 0x00, 0x03, 0xFF, 0xFF, 0xFF, 0xFF, 0xFC};
    EXPECT_EQ(unpackRift21(b), (Vec21{-1048576, 1048575, -2}));
    // The unused lowest bit does not leak into z.
    const std::array<uint8_t, 8> c{0, 0, 0, 0, 0, 0, 0, 0x01};
    EXPECT_EQ(unpackRift21(c), (Vec21{0, 0, 0}));
}

TEST(RiftImu, Unpack21RoundTripsEveryBitPattern) {
    std::mt19937 rng(21);
    std::uniform_int_distribution<int32_t> value(-(1 << 20), (1 << 20) - 1);
    for (int i = 0; i < 20000; ++i) {
        const Vec21 v{value(rng), value(rng), value(rng)};
        EXPECT_EQ(unpackRift21(pack21(v)), v);
    }
    for (int bit = 0; bit < 21; ++bit) {  // one bit at a time, in each axis
        const int32_t single = bit == 20 ? -(1 << 20) : (1 << bit);
        for (size_t axis = 0; axis < 3; ++axis) {
            Vec21 v{};
            v[axis] = single;
            EXPECT_EQ(unpackRift21(pack21(v)), v) << "bit " << bit << " axis " << axis;
        }
    }
}

TEST(RiftImu, DecodesDk1Report) {
    const std::vector<Slot> slots{{{0, 98100, -1}, {-1234, 0, 31416}},
                                  {{1, 2, 3}, {-4, -5, -6}},
                                  {{-1048576, 0, 1048575}, {7, 8, 9}}};
    const auto bytes = dk1Report(3, 0xBEEF, slots, -525, {-300, 200, -1}, 0x1234);
    DecodeStatus st = DecodeStatus::Empty;
    const auto r = decodeRiftTrackerReport(bytes, &st);
    ASSERT_TRUE(r);
    EXPECT_EQ(st, DecodeStatus::Ok);
    EXPECT_EQ(r->format, RiftReportFormat::Dk1);
    EXPECT_EQ(r->numSamples, 3);
    EXPECT_EQ(r->samplesInReport, 3);
    EXPECT_EQ(r->timestamp, 0xBEEFu);
    EXPECT_EQ(r->lastCommandId, 0x1234);
    EXPECT_EQ(r->temperature, -525);
    EXPECT_EQ(r->magnetometer, (std::array<int16_t, 3>{-300, 200, -1}));
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(r->accel[i], slots[i].accel);
        EXPECT_EQ(r->gyro[i], slots[i].gyro);
    }
    std::array<ImuSample, 3> si;
    ASSERT_EQ(riftSamplesToSi(*r, si), 3);
    EXPECT_NEAR(si[0].accelMps2.y, 9.81, 1e-12);
    EXPECT_NEAR(si[0].accelMps2.z, -1e-4, 1e-15);
    EXPECT_NEAR(si[0].gyroRadps.x, -0.1234, 1e-12);
    EXPECT_NEAR(si[0].gyroRadps.z, 3.1416, 1e-12);
    EXPECT_NEAR(si[2].accelMps2.x, -104.8576, 1e-9);
    EXPECT_NEAR(si[1].magneticGauss.x, -0.03, 1e-12);
    EXPECT_NEAR(si[1].temperatureC, -5.25, 1e-12);
}

TEST(RiftImu, DecodesDk2ReportWithCameraSyncFields) {
    const std::vector<Slot> slots{{{-98100, 5, 0}, {0, -2, 17}}, {{3, 3, 3}, {-1, -1, -1}}};
    auto bytes = dk2Report(2, 0xFEDCBA98u, 0xABCD, slots, 3712, {1, -2, 3}, 0x0102);
    put16(bytes, 50, 0x1122);
    put32(bytes, 52, 0x33445566u);
    bytes[56] = 0x77;
    bytes[57] = 0x88;
    put16(bytes, 58, 0x99AA);
    put32(bytes, 60, 0xBBCCDDEEu);
    const auto r = decodeRiftTrackerReport(bytes);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->format, RiftReportFormat::Dk2);
    EXPECT_EQ(r->lastCommandId, 0x0102);
    EXPECT_EQ(r->numSamples, 2);
    EXPECT_EQ(r->samplesInReport, 2);
    EXPECT_EQ(r->totalSampleCount, 0xABCD);
    EXPECT_EQ(r->temperature, 3712);
    EXPECT_EQ(r->timestamp, 0xFEDCBA98u);
    EXPECT_EQ(r->accel[0], slots[0].accel);
    EXPECT_EQ(r->gyro[1], slots[1].gyro);
    EXPECT_EQ(r->accel[2], (Vec21{}));  // no third slot on the DK2
    EXPECT_EQ(r->magnetometer, (std::array<int16_t, 3>{1, -2, 3}));
    EXPECT_EQ(r->frameCount, 0x1122);
    EXPECT_EQ(r->frameTimestampUs, 0x33445566u);
    EXPECT_EQ(r->frameId, 0x77);
    EXPECT_EQ(r->ledPatternPhase, 0x88);
    EXPECT_EQ(r->exposureCount, 0x99AA);
    EXPECT_EQ(r->exposureTimestampUs, 0xBBCCDDEEu);
}

TEST(RiftImu, SampleCountIsClampedToTheSlotsAndUnusedSlotsAreIgnored) {
    const Slot junk{{1000, 1000, 1000}, {1000, 1000, 1000}};
    auto r = decodeRiftTrackerReport(dk1Report(7, 0, {junk, junk, junk}));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->numSamples, 7);
    EXPECT_EQ(r->samplesInReport, 3);
    r = decodeRiftTrackerReport(dk2Report(1, 0, 0, {{{1, 2, 3}, {4, 5, 6}}, junk}));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->samplesInReport, 1);
    EXPECT_EQ(r->accel[1], (Vec21{}));  // the second slot is junk when num < 2
    r = decodeRiftTrackerReport(dk2Report(9, 0, 0));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->samplesInReport, 2);
}

TEST(RiftImu, ShortUnknownAndLongReports) {
    DecodeStatus st;
    EXPECT_FALSE(decodeRiftTrackerReport({}, &st));
    EXPECT_EQ(st, DecodeStatus::Empty);
    auto dk1 = dk1Report(1, 5);
    EXPECT_FALSE(decodeRiftTrackerReport(std::span(dk1).first(61), &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    auto dk2 = dk2Report(1, 5, 0);
    EXPECT_FALSE(decodeRiftTrackerReport(std::span(dk2).first(63), &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    EXPECT_FALSE(decodeRiftTrackerReport(std::vector<uint8_t>{11}, &st));
    EXPECT_EQ(st, DecodeStatus::Truncated);
    std::vector<uint8_t> other(64, 0);
    other[0] = 0x0c;  // a feature-report id, not a tracker report
    EXPECT_FALSE(decodeRiftTrackerReport(other, &st));
    EXPECT_EQ(st, DecodeStatus::UnknownReport);
    dk1.resize(64, 0xEE);  // the 64-byte DK1 variant: trailing bytes ignored
    EXPECT_TRUE(decodeRiftTrackerReport(dk1, &st));
    EXPECT_EQ(st, DecodeStatus::Ok);
}

TEST(RiftImu, FeatureReportsAreByteExact) {
    EXPECT_EQ(buildRiftSensorConfig(0x0102),
              (std::array<uint8_t, 7>{0x02, 0x02, 0x01, 0x0c, 0x00, 0x10, 0x27}));
    EXPECT_EQ(buildRiftSensorConfig(7, kRiftConfigRawMode | kRiftConfigSensorCoordinates, 3, 500),
              (std::array<uint8_t, 7>{0x02, 7, 0, 0x41, 3, 0xF4, 0x01}));
    EXPECT_EQ(buildRiftDk1KeepAlive(0xA0B0),
              (std::array<uint8_t, 5>{0x08, 0xB0, 0xA0, 0x10, 0x27}));
    EXPECT_EQ(buildRiftDk2KeepAlive(1, true),
              (std::array<uint8_t, 6>{0x11, 1, 0, 0x0b, 0x10, 0x27}));
    EXPECT_EQ(buildRiftDk2KeepAlive(1, false, 1000),
              (std::array<uint8_t, 6>{0x11, 1, 0, 0x01, 0xE8, 0x03}));
    EXPECT_EQ(buildRiftCv1EnableComponents(2, true, false, true),
              (std::array<uint8_t, 4>{0x1d, 2, 0, 0x05}));
    EXPECT_EQ(riftKeepAliveResendNs(10000), 9'800'000'000);
    EXPECT_EQ(riftKeepAliveResendNs(100), 1'000'000);  // never zero or negative
}

TEST(RiftImu, ModelTable) {
    const auto dk2 = findRiftModel(0x2833, 0x0021);
    ASSERT_TRUE(dk2);
    EXPECT_EQ(dk2->model, RiftModel::Dk2);
    EXPECT_EQ(findRiftModel(0x2833, 0x2021)->model, RiftModel::Dk2);
    EXPECT_EQ(findRiftModel(0x2833, 0x0001)->model, RiftModel::Dk1);
    const auto cv1 = findRiftModel(0x2833, 0x0031);
    ASSERT_TRUE(cv1);
    EXPECT_EQ(cv1->model, RiftModel::Cv1);
    EXPECT_EQ(cv1->imuInterface, 0);
    EXPECT_FALSE(findRiftModel(0x2833, 0x0137));  // a Quest: not handled here
    EXPECT_FALSE(findRiftModel(0x046d, 0x0021));
}

TEST(RiftImu, StreamUnwrapsTheDk1MillisecondClock) {
    RiftImuStream stream;
    std::vector<ImuSample> out;
    for (uint16_t ts :
         {uint16_t(65533), uint16_t(65534), uint16_t(65535), uint16_t(0), uint16_t(1), uint16_t(2)})
        EXPECT_EQ(stream.push(dk1Report(1, ts, {{{0, 98100, 0}, {}}}), 0, out).samples, 1);
    ASSERT_EQ(out.size(), 6u);
    for (size_t i = 0; i < out.size(); ++i)
        EXPECT_EQ(out[i].deviceTimeNs, (65533 + int64_t(i)) * 1'000'000) << i;
    EXPECT_EQ(stream.stats().outOfOrder, 0u);
    EXPECT_EQ(stream.stats().missedSamples, 0u);
    EXPECT_NEAR(out[5].accelMps2.y, 9.81, 1e-12);
}

TEST(RiftImu, StreamUnwrapsTheDk2MicrosecondClockAndTimesSamplesWithinAReport) {
    RiftImuStream stream;
    std::vector<ImuSample> out;
    const uint32_t start = 0xFFFFFFFFu - 2500;  // wraps between the 2nd and 3rd report
    uint16_t total = 65530;                     // the sample counter wraps too
    for (int k = 0; k < 4; ++k) {
        const auto res =
            stream.push(dk2Report(2, start + uint32_t(2000 * k), total), 1000 * k, out);
        EXPECT_EQ(res.samples, 2);
        EXPECT_EQ(res.missedSamples, 0);
        total = uint16_t(total + 2);
    }
    ASSERT_EQ(out.size(), 8u);
    for (size_t i = 0; i < out.size(); ++i) {
        // Report k's newest sample is at its timestamp, the other 1 ms before.
        const int64_t expected = (int64_t(start) - 1000 + 1000 * int64_t(i)) * 1000;
        EXPECT_EQ(out[i].deviceTimeNs, expected) << i;
    }
    // Host time: arrival time minus the sample's age (1 ms for the older one).
    EXPECT_EQ(out[6].hostTimeNs, 3000 - 1'000'000);
    EXPECT_EQ(out[7].hostTimeNs, 3000);
    EXPECT_EQ(stream.stats().reports, 4u);
    EXPECT_EQ(stream.stats().samples, 8u);
}

TEST(RiftImu, StreamDropsOutOfOrderAndRepeatedReports) {
    RiftImuStream stream;
    std::vector<ImuSample> out;
    EXPECT_FALSE(stream.push(dk1Report(1, 100), 0, out).outOfOrder);
    EXPECT_FALSE(stream.push(dk1Report(1, 102), 0, out).outOfOrder);
    const auto late = stream.push(dk1Report(1, 101), 0, out);
    EXPECT_TRUE(late.outOfOrder);
    EXPECT_EQ(late.samples, 0);
    EXPECT_EQ(late.status, DecodeStatus::Ok);
    EXPECT_TRUE(stream.push(dk1Report(1, 102), 0, out).outOfOrder);  // repeated
    EXPECT_FALSE(stream.push(dk1Report(1, 103), 0, out).outOfOrder);
    EXPECT_EQ(stream.stats().outOfOrder, 2u);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[0].deviceTimeNs, 100'000'000);
    EXPECT_EQ(out[1].deviceTimeNs, 102'000'000);
    EXPECT_EQ(out[2].deviceTimeNs, 103'000'000);
    // Garbage between good reports is counted, not fatal.
    EXPECT_EQ(stream.push(std::vector<uint8_t>{1, 2, 3}, 0, out).status, DecodeStatus::Truncated);
    EXPECT_EQ(stream.stats().decodeErrors, 1u);
}

TEST(RiftImu, StreamCountsMissedSamples) {
    RiftImuStream dk1;
    std::vector<ImuSample> out;
    dk1.push(dk1Report(1, 10), 0, out);
    EXPECT_EQ(dk1.push(dk1Report(5, 15), 0, out).missedSamples, 2);  // 5 taken, 3 slots
    EXPECT_EQ(dk1.push(dk1Report(1, 20), 0, out).missedSamples, 4);  // a lost report
    EXPECT_EQ(dk1.stats().missedSamples, 6u);

    RiftImuStream dk2;
    dk2.push(dk2Report(2, 2000, 100), 0, out);
    EXPECT_EQ(dk2.push(dk2Report(2, 4000, 102), 0, out).missedSamples, 0);
    EXPECT_EQ(dk2.push(dk2Report(2, 10000, 108), 0, out).missedSamples, 4);
    EXPECT_EQ(dk2.stats().missedSamples, 4u);
}

TEST(RiftImu, StreamResynchronisesAfterADeviceClockReset) {
    RiftImuStream stream;
    std::vector<ImuSample> out;
    for (uint32_t t = 1; t <= 5; ++t)
        stream.push(dk2Report(1, 50'000'000 + 1000 * t, uint16_t(t)), 0, out);
    // The device restarted its clock: every report now looks old, until the stream gives up
    // and follows the new clock.
    int dropped = 0;
    for (uint32_t t = 1; t <= 40; ++t)
        dropped += stream.push(dk2Report(1, 1000 * t, uint16_t(t)), 0, out).outOfOrder;
    EXPECT_EQ(dropped, RiftImuStream::kResyncAfter - 1);
    EXPECT_EQ(stream.stats().resyncs, 1u);
    EXPECT_EQ(out.size(), 5u + 40u - size_t(dropped));
    for (size_t i = 1; i < out.size(); ++i)
        EXPECT_GT(out[i].deviceTimeNs, out[i - 1].deviceTimeNs) << i;
    EXPECT_EQ(out.back().deviceTimeNs - out[out.size() - 2].deviceTimeNs, 1'000'000);
}

TEST(RiftImu, FuzzedReportsNeverCrashAndTimeOnlyMovesForward) {
    std::mt19937 rng(2026);
    std::uniform_int_distribution<int> byte(0, 255), len(0, 70), pick(0, 9);
    RiftImuStream stream;
    std::vector<ImuSample> out;
    std::vector<uint8_t> valid = dk2Report(2, 1000, 0);
    int64_t lastNs = std::numeric_limits<int64_t>::min();
    uint64_t produced = 0;
    for (int i = 0; i < 200000; ++i) {
        std::vector<uint8_t> r;
        const int kind = pick(rng);
        if (kind < 4) {  // random bytes, often with a tracker id
            r.resize(size_t(len(rng)));
            for (auto& b : r)
                b = uint8_t(byte(rng));
            if (!r.empty() && kind < 2) r[0] = kind == 0 ? 1 : 11;
        } else {  // a valid report with a few flipped bytes, sometimes cut short
            r = (kind < 7) ? valid : dk1Report(byte(rng) % 5, uint16_t(i));
            for (int f = 0; f < 1 + pick(rng) % 4; ++f)
                r[1 + size_t(byte(rng)) % (r.size() - 1)] = uint8_t(byte(rng));
            if (kind == 9) r.resize(size_t(len(rng)) % r.size());
        }
        out.clear();
        const RiftPushResult res = stream.push(r, i, out);
        ASSERT_EQ(size_t(res.samples), out.size());
        for (const ImuSample& s : out) {
            ASSERT_GT(s.deviceTimeNs, lastNs);
            lastNs = s.deviceTimeNs;
            ASSERT_LE(std::abs(s.accelMps2.x), 104.8576);
            ASSERT_LE(std::abs(s.gyroRadps.z), 104.8576);
        }
        produced += out.size();
    }
    EXPECT_EQ(stream.stats().samples, produced);
    EXPECT_GT(stream.stats().reports, 10000u);
    EXPECT_GT(stream.stats().decodeErrors, 10000u);
}

}  // namespace
