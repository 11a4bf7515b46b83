// SPDX-License-Identifier: MIT
// Seeded random and mutated input into every decoder of this area and the HID descriptor
// parser: no crash, no read past the span (run under ASan to see that), only valid statuses,
// and every accepted output within its documented ranges.
#include "vsculpt/devices/HidDescriptor.h"
#include "vsculpt/devices/HidDigitizer.h"
#include "vsculpt/devices/HidMultiAxis.h"
#include "vsculpt/devices/Polhemus.h"
#include "vsculpt/devices/WacomLegacy.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

using namespace vsculpt::devices;

namespace {

using Bytes = std::vector<uint8_t>;

Bytes loadHex(const std::string& name) {
    std::ifstream in(std::string(VSCULPT_DEVICES_DATA_DIR) + "/" + name);
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

bool validStatus(DecodeStatus s) {
    return s == DecodeStatus::Ok || s == DecodeStatus::Empty || s == DecodeStatus::Truncated ||
           s == DecodeStatus::UnknownReport || s == DecodeStatus::Malformed;
}

// Random length, random bytes; half the time starting like a real report.
struct Gen {
    std::mt19937 rng;
    explicit Gen(unsigned seed) : rng(seed) {}
    int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
    Bytes bytes(int maxLen) {
        Bytes b(size_t(uniform(0, maxLen)));
        for (auto& x : b)
            x = uint8_t(uniform(0, 255));
        return b;
    }
    void mutate(Bytes& b, int flips) {
        for (int k = 0; k < flips && !b.empty(); ++k)
            b[size_t(uniform(0, int(b.size()) - 1))] ^= uint8_t(1 << uniform(0, 7));
    }
};

void checkPen(const PenSample& s) {
    ASSERT_GE(s.pressure, 0.0);
    ASSERT_LE(s.pressure, 1.0);
    ASSERT_TRUE(std::isfinite(s.positionMm.x) && std::isfinite(s.positionMm.y));
    ASSERT_TRUE(std::isfinite(s.tiltRad.x) && std::isfinite(s.tiltRad.y));
    ASSERT_GE(s.positionNormalized.x, 0.0);
    ASSERT_LE(s.positionNormalized.x, 1.0);
    if (!s.inProximity) {
        ASSERT_EQ(s.tool, PenTool::None);
    }
}

TEST(DecoderFuzz, WacomLegacyReports) {
    Gen g(1);
    const WacomModel models[] = {*findWacomModel(0x056a, 0x0010), *findWacomModel(0x056a, 0x0042),
                                 *findWacomModel(0x056a, 0x00B2)};
    WacomPenState state;
    int ok = 0;
    for (int i = 0; i < 200000; ++i) {
        Bytes r = g.bytes(12);
        if (i % 2) r.resize(models[i % 3].protocol == WacomProtocol::Graphire ? 8 : 10);
        if (i % 2) r[0] = 2;
        DecodeStatus st = DecodeStatus::Malformed;
        const auto s = decodeWacomLegacyReport(r, models[i % 3], state, i, &st);
        ASSERT_TRUE(validStatus(st));
        ASSERT_EQ(s.has_value(), st == DecodeStatus::Ok);
        if (s) {
            checkPen(*s);
            ++ok;
        }
    }
    EXPECT_GT(ok, 50000);
}

TEST(DecoderFuzz, PolhemusRecordsAndStream) {
    Gen g(2);
    PolhemusConfig liberty;
    PolhemusConfig fastrak = defaultPolhemusConfig(*findPolhemusModel(0x0f44, 0x0002));
    for (int i = 0; i < 200000; ++i) {
        Bytes r = g.bytes(60);
        if (r.size() > 8 && i % 2) {  // a plausible header, random payload
            r[0] = 'L', r[1] = 'Y', r[2] = uint8_t(1 + i % 4), r[3] = 'C', r[6] = 37, r[7] = 0;
        }
        DecodeStatus st = DecodeStatus::Ok;
        const auto s = decodePolhemusRecord(r, i % 3 ? liberty : fastrak, i, &st);
        ASSERT_TRUE(validStatus(st));
        ASSERT_EQ(s.has_value(), st == DecodeStatus::Ok);
        if (s) {
            ASSERT_NEAR(glm::length(s->orientation), 1.0, 1e-9);
        }
    }

    // A stream of valid records, mutated, cut anywhere and interleaved with noise that never
    // starts a header ('L'/'P' left out), so every byte is either in a record, dropped, or
    // still pending.
    PolhemusStreamDecoder dec(liberty);
    std::vector<TrackerSample> out;
    uint64_t fed = 0;
    for (int i = 0; i < 20000; ++i) {
        Bytes chunk;
        if (g.uniform(0, 3)) {
            Bytes rec{'L', 'Y', uint8_t(g.uniform(1, 4)), 'C', ' ', 0, 37, 0};
            for (float v : {1.f, 2.f, 3.f, 1.f, 0.f, 0.f, 0.f}) {
                const uint32_t u = std::bit_cast<uint32_t>(v);
                for (int k = 0; k < 4; ++k)
                    rec.push_back(uint8_t(u >> (8 * k)));
            }
            rec.resize(44, 0);
            rec.push_back(' ');
            if (g.uniform(0, 9) == 0) g.mutate(rec, 1);
            chunk = rec;
        } else {
            chunk = g.bytes(20);
            for (auto& b : chunk)
                if (b == 'L' || b == 'P') b = 'x';
        }
        for (size_t at = 0; at < chunk.size();) {
            const size_t n = std::min(size_t(g.uniform(1, 30)), chunk.size() - at);
            dec.feed(std::span(chunk).subspan(at, n), i, out);
            at += n;
        }
        fed += chunk.size();
    }
    for (const TrackerSample& s : out) {
        ASSERT_GE(s.station, 1);
        ASSERT_LE(s.station, 16);
        ASSERT_NEAR(glm::length(s.orientation), 1.0, 1e-9);
    }
    EXPECT_EQ(dec.records(), out.size());
    EXPECT_GT(out.size(), 10000u);
    EXPECT_EQ(fed,
              dec.droppedBytes() + dec.records() * 45 + dec.otherReplyBytes() + dec.pendingBytes());
}

TEST(DecoderFuzz, HidParserOnRandomAndMutatedDescriptors) {
    Gen g(3);
    const Bytes real[] = {
        loadHex("spacenavigator.rdesc.hex"), loadHex("spacemouse-wireless.rdesc.hex"),
        loadHex("xppen-deco01v3-pen.rdesc.hex"), loadHex("goodix-gxtp-27c6-0113.rdesc.hex")};
    int parsed = 0;
    for (int i = 0; i < 30000; ++i) {
        Bytes d;
        if (i % 3 == 0) {
            d = g.bytes(64);
        } else {
            d = real[g.uniform(0, 3)];
            g.mutate(d, g.uniform(1, 6));
            if (g.uniform(0, 4) == 0) d.resize(size_t(g.uniform(0, int(d.size()))));
        }
        std::string err;
        const auto desc = parseHidDescriptor(d, &err);
        if (!desc) {
            ASSERT_FALSE(err.empty());
            continue;
        }
        ++parsed;
        for (const HidReport& r : desc->reports)
            for (const HidField& f : r.fields)
                ASSERT_LE(uint64_t(f.bitOffset) + uint64_t(f.bitSize) * f.count, r.bitLength);
        // Whatever the parser accepted, decoders built on it must survive random reports.
        const auto pen = HidDigitizerDecoder::fromDescriptor(*desc);
        const auto axes = HidMultiAxisDecoder::fromDescriptor(*desc);
        for (int k = 0; k < 20; ++k) {
            Bytes r = g.bytes(24);
            DecodeStatus st = DecodeStatus::Ok;
            if (pen) {
                const auto s = pen->decode(r, k, &st);
                ASSERT_TRUE(validStatus(st));
                if (s) checkPen(*s);
            }
            if (axes) {
                axes->decode(r, k, &st);
                ASSERT_TRUE(validStatus(st));
            }
        }
    }
    EXPECT_GT(parsed, 1000);
}

TEST(DecoderFuzz, HidDecodersOnRealDescriptors) {
    Gen g(4);
    const auto penDesc = parseHidDescriptor(loadHex("xppen-deco01v3-pen.rdesc.hex"));
    const auto navDesc = parseHidDescriptor(loadHex("spacenavigator.rdesc.hex"));
    ASSERT_TRUE(penDesc && navDesc);
    const auto pen = HidDigitizerDecoder::fromDescriptor(*penDesc);
    const auto nav = HidMultiAxisDecoder::fromDescriptor(*navDesc);
    ASSERT_TRUE(pen && nav);
    int penOk = 0, navOk = 0;
    for (int i = 0; i < 200000; ++i) {
        Bytes r = g.bytes(14);
        if (!r.empty() && i % 2) r[0] = 7;
        DecodeStatus st = DecodeStatus::Ok;
        const auto s = pen->decode(r, i, &st);
        ASSERT_TRUE(validStatus(st));
        ASSERT_EQ(s.has_value(), st == DecodeStatus::Ok);
        if (s) {
            checkPen(*s);
            ASSERT_LE(s->positionMm.x, 254.0 + 1e-9);
            ++penOk;
        }
        if (!r.empty() && i % 2) r[0] = uint8_t(1 + i % 3);
        const auto m = nav->decode(r, i, &st);
        ASSERT_TRUE(validStatus(st));
        if (m) ++navOk;
    }
    EXPECT_GT(penOk, 30000);
    EXPECT_GT(navOk, 30000);
}

}  // namespace
