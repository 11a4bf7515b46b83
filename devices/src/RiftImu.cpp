// SPDX-License-Identifier: MIT
#include "vsculpt/devices/RiftImu.h"

#include <algorithm>

namespace vsculpt::devices {

namespace {

uint16_t readU16(std::span<const uint8_t> b, size_t offset) {
    return uint16_t(uint16_t(b[offset]) | uint16_t(b[offset + 1]) << 8);
}

uint32_t readU32(std::span<const uint8_t> b, size_t offset) {
    return uint32_t(b[offset]) | uint32_t(b[offset + 1]) << 8 | uint32_t(b[offset + 2]) << 16 |
           uint32_t(b[offset + 3]) << 24;
}

void putU16(uint8_t* p, uint16_t v) {
    p[0] = uint8_t(v & 0xFF);
    p[1] = uint8_t(v >> 8);
}

std::optional<RiftTrackerReport> fail(DecodeStatus* status, DecodeStatus why) {
    if (status) *status = why;
    return std::nullopt;
}

int32_t signExtend21(uint32_t v) {
    // Two's complement from bit 20, without shifting into the sign bit of a signed type.
    v &= 0x1FFFFF;
    return (v & 0x100000) ? int32_t(v) - 0x200000 : int32_t(v);
}

void readSamples(std::span<const uint8_t> r, size_t offset, int count, RiftTrackerReport& out) {
    for (int i = 0; i < count; ++i) {
        const size_t base = offset + 16 * size_t(i);
        out.accel[size_t(i)] = unpackRift21(r.subspan(base).first<8>());
        out.gyro[size_t(i)] = unpackRift21(r.subspan(base + 8).first<8>());
    }
}

constexpr int64_t kSamplePeriodNs = 1'000'000;  // 1 kHz on all three models

}  // namespace

std::optional<RiftIdentity> findRiftModel(uint16_t vendor, uint16_t product) {
    static const RiftIdentity kModels[] = {
        {kOculusVendorId, 0x0001, RiftModel::Dk1, "Rift DK1", 0},
        {kOculusVendorId, 0x0021, RiftModel::Dk2, "Rift DK2", 0},
        {kOculusVendorId, 0x2021, RiftModel::Dk2, "Rift DK2", 0},
        {kOculusVendorId, 0x0031, RiftModel::Cv1, "Rift CV1", 0},
    };
    for (const RiftIdentity& m : kModels)
        if (m.vendor == vendor && m.product == product) return m;
    return std::nullopt;
}

std::array<uint8_t, 7> buildRiftSensorConfig(uint16_t commandId, uint8_t flags,
                                             uint8_t packetInterval, uint16_t keepAliveMs) {
    std::array<uint8_t, 7> r{0x02};
    putU16(&r[1], commandId);
    r[3] = flags;
    r[4] = packetInterval;
    putU16(&r[5], keepAliveMs);
    return r;
}

std::array<uint8_t, 5> buildRiftDk1KeepAlive(uint16_t commandId, uint16_t intervalMs) {
    std::array<uint8_t, 5> r{0x08};
    putU16(&r[1], commandId);
    putU16(&r[3], intervalMs);
    return r;
}

std::array<uint8_t, 6> buildRiftDk2KeepAlive(uint16_t commandId, bool leds, uint16_t intervalMs) {
    std::array<uint8_t, 6> r{0x11};
    putU16(&r[1], commandId);
    r[3] = leds ? 0x0b : 0x01;
    putU16(&r[4], intervalMs);
    return r;
}

std::array<uint8_t, 4> buildRiftCv1EnableComponents(uint16_t commandId, bool display, bool audio,
                                                    bool leds) {
    std::array<uint8_t, 4> r{0x1d};
    putU16(&r[1], commandId);
    r[3] = uint8_t((display ? 1 : 0) | (audio ? 2 : 0) | (leds ? 4 : 0));
    return r;
}

int64_t riftKeepAliveResendNs(uint16_t intervalMs) {
    return std::max<int64_t>(1, int64_t(intervalMs) - 200) * 1'000'000;
}

std::array<int32_t, 3> unpackRift21(std::span<const uint8_t, 8> b) {
    const uint32_t x = uint32_t(b[0]) << 13 | uint32_t(b[1]) << 5 | uint32_t(b[2]) >> 3;
    const uint32_t y = (uint32_t(b[2]) & 7) << 18 | uint32_t(b[3]) << 10 | uint32_t(b[4]) << 2 |
                       uint32_t(b[5]) >> 6;
    const uint32_t z = (uint32_t(b[5]) & 0x3F) << 15 | uint32_t(b[6]) << 7 | uint32_t(b[7]) >> 1;
    return {signExtend21(x), signExtend21(y), signExtend21(z)};
}

std::optional<RiftTrackerReport> decodeRiftTrackerReport(std::span<const uint8_t> r,
                                                         DecodeStatus* status) {
    if (r.empty()) return fail(status, DecodeStatus::Empty);
    RiftTrackerReport out;
    if (r[0] == kRiftDk1TrackerReportId) {
        if (r.size() < kRiftDk1TrackerReportSize) return fail(status, DecodeStatus::Truncated);
        out.format = RiftReportFormat::Dk1;
        out.numSamples = r[1];
        out.samplesInReport = std::min<int>(out.numSamples, 3);
        out.timestamp = readU16(r, 2);
        out.lastCommandId = readU16(r, 4);
        out.temperature = int16_t(readU16(r, 6));
        readSamples(r, 8, out.samplesInReport, out);
        for (size_t a = 0; a < 3; ++a)
            out.magnetometer[a] = int16_t(readU16(r, 56 + 2 * a));
    } else if (r[0] == kRiftDk2TrackerReportId) {
        if (r.size() < kRiftDk2TrackerReportSize) return fail(status, DecodeStatus::Truncated);
        out.format = RiftReportFormat::Dk2;
        out.lastCommandId = readU16(r, 1);
        out.numSamples = r[3];
        out.samplesInReport = std::min<int>(out.numSamples, 2);
        out.totalSampleCount = readU16(r, 4);
        out.temperature = int16_t(readU16(r, 6));
        out.timestamp = readU32(r, 8);
        readSamples(r, 12, out.samplesInReport, out);
        for (size_t a = 0; a < 3; ++a)
            out.magnetometer[a] = int16_t(readU16(r, 44 + 2 * a));
        out.frameCount = readU16(r, 50);
        out.frameTimestampUs = readU32(r, 52);
        out.frameId = r[56];
        out.ledPatternPhase = r[57];
        out.exposureCount = readU16(r, 58);
        out.exposureTimestampUs = readU32(r, 60);
    } else {
        return fail(status, DecodeStatus::UnknownReport);
    }
    if (status) *status = DecodeStatus::Ok;
    return out;
}

int riftSamplesToSi(const RiftTrackerReport& r, std::array<ImuSample, 3>& out) {
    constexpr double kScale = 1e-4;  // accel m/s^2, gyro rad/s, magnetometer gauss per count
    const glm::dvec3 mag =
        kScale * glm::dvec3(r.magnetometer[0], r.magnetometer[1], r.magnetometer[2]);
    const int n = std::clamp(r.samplesInReport, 0, 3);
    for (size_t i = 0; i < size_t(n); ++i) {
        ImuSample& s = out[i];
        s = ImuSample{};
        s.accelMps2 = kScale * glm::dvec3(r.accel[i][0], r.accel[i][1], r.accel[i][2]);
        s.gyroRadps = kScale * glm::dvec3(r.gyro[i][0], r.gyro[i][1], r.gyro[i][2]);
        s.magneticGauss = mag;
        s.temperatureC = 0.01 * r.temperature;
    }
    return n;
}

void RiftImuStream::reset() {
    mStarted = false;
    mBackwardRun = 0;
}

RiftPushResult RiftImuStream::push(std::span<const uint8_t> report, int64_t hostTimeNs,
                                   std::vector<ImuSample>& out) {
    RiftPushResult result;
    const std::optional<RiftTrackerReport> r = decodeRiftTrackerReport(report, &result.status);
    if (!r) {
        ++mStats.decodeErrors;
        return result;
    }
    const bool dk1 = r->format == RiftReportFormat::Dk1;
    const uint64_t modulus = dk1 ? (uint64_t(1) << 16) : (uint64_t(1) << 32);
    const int64_t tickNs = dk1 ? 1'000'000 : 1'000;
    const int n = r->samplesInReport;

    if (mStarted && r->format != mFormat) {  // another headset on the same stream: start over
        mStarted = false;
        ++mStats.resyncs;
    }

    int64_t newestNs = 0;
    int missed = 0;
    if (!mStarted) {
        // The very first report keeps the device's own clock; a restart continues our
        // timeline so that time never goes back for the consumer.
        newestNs = mEverStarted ? mLastSampleNs + std::max(1, n) * kSamplePeriodNs
                                : int64_t(r->timestamp) * tickNs;
        if (dk1) missed = std::max(0, int(r->numSamples) - n);
    } else {
        const uint64_t delta = (uint64_t(r->timestamp) - uint64_t(mLastRaw)) & (modulus - 1);
        if (delta == 0 || delta >= modulus / 2) {
            if (++mBackwardRun < kResyncAfter) {
                ++mStats.outOfOrder;
                result.outOfOrder = true;
                return result;
            }
            // The clock jumped back for good (device reset): continue our timeline from here.
            ++mStats.resyncs;
            newestNs = mLastSampleNs + std::max(1, n) * kSamplePeriodNs;
        } else {
            newestNs = mLastReportNs + int64_t(delta) * tickNs;
            if (dk1) {
                missed = int(std::clamp<int64_t>(int64_t(delta) - n, 0, 1 << 16));
            } else {
                const uint16_t gap = uint16_t(r->totalSampleCount - mExpectedTotal);
                missed = gap < 0x8000 ? gap : 0;
            }
        }
    }

    std::array<ImuSample, 3> samples;
    riftSamplesToSi(*r, samples);
    for (int i = 0; i < n; ++i) {
        int64_t t = newestNs - int64_t(n - 1 - i) * kSamplePeriodNs;
        if (mEverStarted) t = std::max(t, mLastSampleNs + i + 1);
        ImuSample& s = samples[size_t(i)];
        s.deviceTimeNs = t;
        s.hostTimeNs = hostTimeNs - (newestNs - t);
        out.push_back(s);
    }
    const int64_t lastNs = n > 0 ? samples[size_t(n - 1)].deviceTimeNs : newestNs;
    mLastSampleNs = mEverStarted ? std::max(mLastSampleNs, lastNs) : lastNs;

    mStarted = mEverStarted = true;
    mFormat = r->format;
    mLastRaw = r->timestamp;
    mLastReportNs = newestNs;
    mExpectedTotal = uint16_t(r->totalSampleCount + r->numSamples);
    mBackwardRun = 0;
    ++mStats.reports;
    mStats.samples += uint64_t(n);
    mStats.missedSamples += uint64_t(missed);
    result.samples = n;
    result.missedSamples = missed;
    return result;
}

}  // namespace vsculpt::devices
