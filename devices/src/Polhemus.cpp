// SPDX-License-Identifier: MIT
#include "vsculpt/devices/Polhemus.h"

#include <glm/gtc/quaternion.hpp>

#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace vsculpt::devices {

namespace {

constexpr size_t kLibertyHeader = 8, kFastrakHeader = 3;
constexpr size_t kMaxReplyPayload = 4096;  // longer "lengths" are garbage, not a reply

bool isLibertyLike(PolhemusFamily f) {
    return f == PolhemusFamily::Liberty || f == PolhemusFamily::Patriot;
}

// The number of each item in the device's output-list command (-1: the family has none).
int itemNumber(PolhemusFamily family, PolhemusItem item) {
    const bool fastrak = family == PolhemusFamily::Fastrak;
    switch (item) {
        case PolhemusItem::Space:
            return 0;
        case PolhemusItem::CrLf:
            return 1;
        case PolhemusItem::Position:
            return 2;
        case PolhemusItem::Euler:
            return 4;
        case PolhemusItem::Quaternion:
            return fastrak ? 11 : 7;
        case PolhemusItem::Timestamp:
            return fastrak ? -1 : 8;
        case PolhemusItem::FrameCount:
            return fastrak ? -1 : 9;
        case PolhemusItem::StylusButton:
            return fastrak ? 16 : 10;
        case PolhemusItem::Distortion:
            return fastrak ? -1 : 11;
    }
    return -1;
}

size_t itemBytes(PolhemusFamily family, PolhemusItem item) {
    switch (item) {
        case PolhemusItem::Space:
            return 1;
        case PolhemusItem::CrLf:
            return 2;
        case PolhemusItem::Position:
        case PolhemusItem::Euler:
            return 12;
        case PolhemusItem::Quaternion:
            return 16;
        case PolhemusItem::StylusButton:
            return family == PolhemusFamily::Fastrak ? 2 : 4;
        case PolhemusItem::Timestamp:
        case PolhemusItem::FrameCount:
        case PolhemusItem::Distortion:
            return 4;
    }
    return 0;
}

size_t payloadBytes(const PolhemusConfig& c) {
    size_t n = 0;
    for (PolhemusItem i : c.items)
        n += itemBytes(c.family, i);
    return n;
}

uint32_t le32(std::span<const uint8_t> b, size_t o) {
    return uint32_t(b[o]) | uint32_t(b[o + 1]) << 8 | uint32_t(b[o + 2]) << 16 |
           uint32_t(b[o + 3]) << 24;
}

float f32(std::span<const uint8_t> b, size_t o) {
    return std::bit_cast<float>(le32(b, o));
}

std::vector<uint8_t> bytes(const std::string& s) {
    return {s.begin(), s.end()};
}

std::optional<TrackerSample> fail(DecodeStatus* status, DecodeStatus why) {
    if (status) *status = why;
    return std::nullopt;
}

bool validTag(uint8_t a, uint8_t b) {
    return (a == 'L' && (b == 'Y' || b == 'U')) || (a == 'P' && b == 'A');
}

}  // namespace

std::optional<PolhemusModel> findPolhemusModel(uint16_t vendor, uint16_t product) {
    using F = PolhemusFamily;
    // devices_report.md §1.1 (Tracker Terminal, VRPN, libpolhemus, the ROS drivers' udev rules).
    static const PolhemusModel kModels[] = {
        {0x0f44, 0x0001, "FASTRAK (firmware loader)", F::Fastrak, true, false, 0, 0, 4, false},
        {0x0f44, 0x0002, "FASTRAK", F::Fastrak, false, false, 0x02, 0x82, 4, true},
        {0x0f44, 0x0003, "FASTRAK 3", F::Fastrak, false, false, 0, 0, 4, true},
        {0x0f44, 0xff11, "Liberty (firmware loader)", F::Liberty, true, false, 0, 0, 16, false},
        {0x0f44, 0xff12, "Liberty", F::Liberty, false, false, 0x02, 0x82, 16, true},
        {0x0f44, 0xff21, "Liberty HS (firmware loader)", F::Liberty, true, true, 0, 0, 16, false},
        {0x0f44, 0xff20, "Liberty HS / Latus", F::Liberty, false, true, 0x04, 0x88, 16, true},
        {0x0f44, 0xef11, "Patriot (firmware loader)", F::Patriot, true, false, 0, 0, 2, false},
        {0x0f44, 0xef12, "Patriot", F::Patriot, false, false, 0x02, 0x82, 2, true},
        {0x0f44, 0xef21, "Patriot HS (firmware loader)", F::Patriot, true, true, 0, 0, 2, false},
        {0x0f44, 0xef20, "Patriot HS", F::Patriot, false, true, 0x04, 0x88, 2, true},
        {0x0f44, 0xcf01, "G4", F::G4, false, false, 0, 0, 0, false},
        {0x0f44, 0xbf01, "Viper", F::Viper, false, false, 0, 0, 16, false},
    };
    for (const PolhemusModel& m : kModels)
        if (m.vendor == vendor && m.product == product) return m;
    return std::nullopt;
}

std::vector<PolhemusItem> polhemusDefaultItems(PolhemusFamily family) {
    using I = PolhemusItem;
    if (family == PolhemusFamily::Fastrak)
        return {I::Position, I::Quaternion, I::StylusButton, I::Space};
    return {I::Position, I::Quaternion, I::Timestamp, I::FrameCount, I::Space};
}

PolhemusConfig defaultPolhemusConfig(const PolhemusModel& m) {
    PolhemusConfig c;
    c.family = m.family;
    c.highSpeed = m.highSpeed;
    c.maxStations = m.maxStations > 0 ? m.maxStations : 16;
    c.items = polhemusDefaultItems(m.family);
    return c;
}

std::vector<std::vector<uint8_t>> polhemusStartupCommands(const PolhemusConfig& c) {
    if (c.family != PolhemusFamily::Fastrak && !isLibertyLike(c.family))
        throw std::invalid_argument("Polhemus: G4 and Viper use other protocols; not supported");
    if (c.items.empty()) throw std::invalid_argument("Polhemus: empty output list");
    if (c.station < 0 || c.station > c.maxStations)
        throw std::invalid_argument("Polhemus: station " + std::to_string(c.station) +
                                    " out of 0.." + std::to_string(c.maxStations));
    std::string list;
    for (PolhemusItem i : c.items) {
        const int n = itemNumber(c.family, i);
        if (n < 0)
            throw std::invalid_argument(
                "Polhemus: FASTRAK has no output item for timestamp, "
                "frame count or distortion");
        list += "," + std::to_string(n);
    }
    std::vector<std::vector<uint8_t>> cmds;
    if (c.family == PolhemusFamily::Fastrak) {
        // FASTRAK single-letter commands take no CR; the output list does.
        cmds.push_back(bytes("c"));                                           // stop continuous
        cmds.push_back(bytes("f"));                                           // binary
        cmds.push_back(bytes(c.units == PolhemusUnits::Inches ? "u" : "U"));  // in / cm
        const int first = c.station ? c.station : 1, last = c.station ? c.station : c.maxStations;
        for (int s = first; s <= last; ++s)
            cmds.push_back(bytes("O" + std::to_string(s) + list + "\r"));
        cmds.push_back(bytes("C"));
    } else {
        cmds.push_back(bytes("P\r"));  // stops continuous output (one record may follow)
        cmds.push_back(bytes("F1\r"));
        cmds.push_back(bytes(c.units == PolhemusUnits::Inches ? "U0\r" : "U1\r"));
        cmds.push_back(bytes("O" + (c.station ? std::to_string(c.station) : "*") + list + "\r"));
        if (c.highSpeed) cmds.push_back(bytes("@B0\r"));
        cmds.push_back(bytes("C\r"));
    }
    return cmds;
}

std::vector<uint8_t> polhemusStopCommand(PolhemusFamily family) {
    return bytes(family == PolhemusFamily::Fastrak ? "c" : "P\r");
}

size_t polhemusRecordBytes(const PolhemusConfig& c) {
    return (c.family == PolhemusFamily::Fastrak ? kFastrakHeader : kLibertyHeader) +
           payloadBytes(c);
}

std::optional<TrackerSample> decodePolhemusRecord(std::span<const uint8_t> r,
                                                  const PolhemusConfig& c, int64_t timeNs,
                                                  DecodeStatus* status) {
    if (r.empty()) return fail(status, DecodeStatus::Empty);
    TrackerSample s;
    s.timeNs = timeNs;
    const bool fastrak = c.family == PolhemusFamily::Fastrak;
    size_t o = 0;
    if (fastrak) {
        if (r[0] != '0') return fail(status, DecodeStatus::Malformed);
        if (r.size() < kFastrakHeader) return fail(status, DecodeStatus::Truncated);
        s.station = int(r[1]) - '0';
        const bool statusOk =
            r[2] == ' ' || (r[2] >= 'A' && r[2] <= 'Z') || (r[2] >= 'a' && r[2] <= 'z');
        if (s.station < 1 || s.station > c.maxStations || !statusOk)
            return fail(status, DecodeStatus::Malformed);
        s.errorCode = char(r[2]);
        o = kFastrakHeader;
    } else {
        if (r.size() < 2) return fail(status, DecodeStatus::Truncated);
        if (!validTag(r[0], r[1])) return fail(status, DecodeStatus::Malformed);
        if (r.size() < kLibertyHeader) return fail(status, DecodeStatus::Truncated);
        s.station = r[2];
        s.errorCode = char(r[4]);
        const size_t length = size_t(r[6]) | size_t(r[7]) << 8;
        if (r[3] != 'C' && r[3] != 'P') return fail(status, DecodeStatus::UnknownReport);
        if (s.station < 1 || s.station > c.maxStations || length != payloadBytes(c))
            return fail(status, DecodeStatus::Malformed);
        o = kLibertyHeader;
    }
    if (r.size() < o + payloadBytes(c)) return fail(status, DecodeStatus::Truncated);

    const double mmPerUnit = c.units == PolhemusUnits::Inches ? 25.4 : 10.0;
    for (PolhemusItem item : c.items) {
        switch (item) {
            case PolhemusItem::Space:
                if (r[o] != ' ') return fail(status, DecodeStatus::Malformed);
                break;
            case PolhemusItem::CrLf:
                if (r[o] != '\r' || r[o + 1] != '\n') return fail(status, DecodeStatus::Malformed);
                break;
            case PolhemusItem::Position: {
                const glm::dvec3 p(f32(r, o), f32(r, o + 4), f32(r, o + 8));
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    return fail(status, DecodeStatus::Malformed);
                s.hasPosition = true;
                s.positionMm = p * mmPerUnit;
                break;
            }
            case PolhemusItem::Euler: {
                const glm::dvec3 deg(f32(r, o), f32(r, o + 4), f32(r, o + 8));
                if (!std::isfinite(deg.x) || !std::isfinite(deg.y) || !std::isfinite(deg.z))
                    return fail(status, DecodeStatus::Malformed);
                const glm::dvec3 rad = glm::radians(deg);
                s.hasOrientation = true;
                s.orientation = glm::angleAxis(rad.x, glm::dvec3(0, 0, 1)) *
                                glm::angleAxis(rad.y, glm::dvec3(0, 1, 0)) *
                                glm::angleAxis(rad.z, glm::dvec3(1, 0, 0));
                break;
            }
            case PolhemusItem::Quaternion: {
                const glm::dquat q(f32(r, o), f32(r, o + 4), f32(r, o + 8), f32(r, o + 12));
                const double n = glm::length(q);
                // The device sends unit quaternions; anything far off is misframed bytes.
                if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-3)
                    return fail(status, DecodeStatus::Malformed);
                s.hasOrientation = true;
                s.orientation = q / n;
                break;
            }
            case PolhemusItem::Timestamp:
                s.hasDeviceTime = true;
                s.deviceTimeMs = le32(r, o);
                break;
            case PolhemusItem::FrameCount:
                s.hasFrameCount = true;
                s.frameCount = le32(r, o);
                break;
            case PolhemusItem::StylusButton:
                if (fastrak) {
                    if (r[o + 1] != '0' && r[o + 1] != '1')
                        return fail(status, DecodeStatus::Malformed);
                    s.buttons = r[o + 1] == '1' ? 1u : 0u;
                } else {
                    s.buttons = le32(r, o) ? 1u : 0u;
                }
                break;
            case PolhemusItem::Distortion:
                s.distortion = int32_t(le32(r, o));
                break;
        }
        o += itemBytes(c.family, item);
    }
    if (status) *status = DecodeStatus::Ok;
    return s;
}

PolhemusStreamDecoder::PolhemusStreamDecoder(PolhemusConfig config)
    : mConfig(std::move(config)), mRecordBytes(polhemusRecordBytes(mConfig)) {}

void PolhemusStreamDecoder::reset() {
    mBuffer.clear();
}

size_t PolhemusStreamDecoder::feed(std::span<const uint8_t> in, int64_t timeNs,
                                   std::vector<TrackerSample>& out) {
    mBuffer.insert(mBuffer.end(), in.begin(), in.end());
    const bool fastrak = mConfig.family == PolhemusFamily::Fastrak;
    const std::span<const uint8_t> b(mBuffer);
    size_t pos = 0, emitted = 0;
    auto drop = [&] {
        ++pos;
        ++mDropped;
    };
    while (pos < b.size()) {
        const size_t avail = b.size() - pos;
        if (fastrak) {
            if (b[pos] != '0') {
                drop();
                continue;
            }
        } else {
            if (b[pos] != 'L' && b[pos] != 'P') {
                drop();
                continue;
            }
            if (avail < 2) break;
            if (!validTag(b[pos], b[pos + 1])) {
                drop();
                continue;
            }
            if (avail < kLibertyHeader) break;
            const uint8_t cmd = b[pos + 3];
            const size_t length = size_t(b[pos + 6]) | size_t(b[pos + 7]) << 8;
            if (cmd != 'C' && cmd != 'P') {
                // A reply to another command (e.g. the ^U station map): skip it whole.
                if (length > kMaxReplyPayload) {
                    drop();
                    continue;
                }
                if (avail < kLibertyHeader + length) break;
                pos += kLibertyHeader + length;
                ++mReplies;
                mReplyBytes += kLibertyHeader + length;
                continue;
            }
        }
        if (avail < mRecordBytes) break;
        DecodeStatus st;
        auto s = decodePolhemusRecord(b.subspan(pos, mRecordBytes), mConfig, timeNs, &st);
        if (!s) {
            drop();
            continue;
        }
        out.push_back(*s);
        ++emitted;
        ++mRecords;
        pos += mRecordBytes;
    }
    mBuffer.erase(mBuffer.begin(), mBuffer.begin() + std::ptrdiff_t(pos));
    return emitted;
}

}  // namespace vsculpt::devices
