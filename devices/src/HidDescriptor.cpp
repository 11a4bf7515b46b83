// SPDX-License-Identifier: MIT
#include "vsculpt/devices/HidDescriptor.h"

#include <algorithm>
#include <cmath>

namespace vsculpt::devices {

namespace {

// Limits in the spirit of the Linux HID core: anything beyond is a broken descriptor, and
// bounding it keeps a hostile one from making us allocate without end.
constexpr uint32_t kMaxReportSize = 256;     // bits per element
constexpr uint32_t kMaxReportCount = 12288;  // elements per main item
constexpr uint32_t kMaxReportBits = 16384 * 8;
constexpr uint32_t kMaxUsagesPerItem = 4096;
constexpr size_t kMaxPushDepth = 32;
constexpr size_t kMaxCollectionDepth = 64;

struct Globals {
    uint16_t usagePage = 0;
    int32_t logicalMin = 0;
    uint32_t logicalMaxRaw = 0;
    int32_t logicalMaxSigned = 0;
    int32_t physicalMin = 0;
    uint32_t physicalMaxRaw = 0;
    int32_t physicalMaxSigned = 0;
    int8_t unitExponent = 0;
    uint32_t unit = 0;
    uint32_t reportSize = 0;
    uint8_t reportId = 0;
    uint32_t reportCount = 0;
};

struct Locals {
    std::vector<uint32_t> usages;
    // Plain flags rather than std::optional: GCC 12 warns falsely on optionals here.
    uint32_t usageMin = 0, usageMax = 0;
    bool hasMin = false, hasMax = false;
    void clear() {
        usages.clear();
        hasMin = hasMax = false;
    }
};

int32_t signExtend(uint32_t v, unsigned sizeBytes) {
    switch (sizeBytes) {
        case 1:
            return int8_t(uint8_t(v));
        case 2:
            return int16_t(uint16_t(v));
        default:
            return int32_t(v);
    }
}

// HID 1.11 states Logical/Physical Maximum are signed, but devices whose minimum is >= 0
// routinely write e.g. 0x25 0xFF for 255; the Linux HID core reads them unsigned in that case,
// and so do we (when the value fits).
int32_t resolveMax(int32_t min, uint32_t raw, int32_t asSigned) {
    if (min >= 0 && raw <= uint32_t(INT32_MAX)) return int32_t(raw);
    return asSigned;
}

uint32_t resolveUsage(uint32_t data, unsigned sizeBytes, uint16_t page) {
    return sizeBytes == 4 ? data : hidUsage(page, uint16_t(data));
}

}  // namespace

uint32_t HidField::usageAt(uint32_t i) const {
    if (usages.empty()) return 0;
    return usages[std::min<size_t>(i, usages.size() - 1)];
}

const HidReport* HidDescriptor::find(HidReportKind kind, uint8_t id) const {
    for (const HidReport& r : reports)
        if (r.kind == kind && r.id == id) return &r;
    return nullptr;
}

std::optional<HidDescriptor::FieldRef> HidDescriptor::findUsage(HidReportKind kind,
                                                                uint32_t usage) const {
    for (const HidReport& r : reports) {
        if (r.kind != kind) continue;
        for (const HidField& f : r.fields) {
            if (f.isConstant() || !f.isVariable()) continue;
            for (uint32_t i = 0; i < f.count; ++i)
                if (f.usageAt(i) == usage) return FieldRef{&r, &f, i};
        }
    }
    return std::nullopt;
}

std::optional<HidDescriptor> parseHidDescriptor(std::span<const uint8_t> b, std::string* error) {
    auto fail = [&](size_t at, const std::string& what) -> std::optional<HidDescriptor> {
        if (error) *error = "HID descriptor byte " + std::to_string(at) + ": " + what;
        return std::nullopt;
    };
    if (b.empty()) return fail(0, "empty descriptor");

    HidDescriptor out;
    Globals g;
    std::vector<Globals> stack;
    Locals l;
    struct Collection {
        uint32_t usage;
        uint8_t type;
    };
    std::vector<Collection> collections;
    uint32_t applicationUsage = 0;

    size_t i = 0;
    while (i < b.size()) {
        const size_t at = i;
        const uint8_t prefix = b[i];
        if (prefix == 0xFE) {  // long item: bDataSize, bLongItemTag, data
            if (i + 3 > b.size()) return fail(at, "truncated long item");
            const size_t size = b[i + 1];
            if (i + 3 + size > b.size()) return fail(at, "long item data past the end");
            i += 3 + size;
            continue;
        }
        const unsigned size = (prefix & 3) == 3 ? 4 : (prefix & 3);
        const unsigned type = (prefix >> 2) & 3, tag = prefix >> 4;
        if (i + 1 + size > b.size()) return fail(at, "item data past the end");
        uint32_t data = 0;
        for (unsigned k = 0; k < size; ++k)
            data |= uint32_t(b[i + 1 + k]) << (8 * k);
        const int32_t sdata = signExtend(data, size);
        i += 1 + size;

        if (type == 0) {  // main
            switch (tag) {
                case 0x8:    // Input
                case 0x9:    // Output
                case 0xB: {  // Feature
                    const HidReportKind kind = tag == 0x8   ? HidReportKind::Input
                                               : tag == 0x9 ? HidReportKind::Output
                                                            : HidReportKind::Feature;
                    if (g.reportSize > kMaxReportSize)
                        return fail(at, "Report Size " + std::to_string(g.reportSize) + " > " +
                                            std::to_string(kMaxReportSize));
                    if (g.reportCount > kMaxReportCount)
                        return fail(at,
                                    "Report Count " + std::to_string(g.reportCount) + " too large");
                    HidReport* report = nullptr;
                    for (HidReport& r : out.reports)
                        if (r.kind == kind && r.id == g.reportId) report = &r;
                    if (!report) {
                        out.reports.push_back(
                            HidReport{kind, g.reportId, g.reportId ? 8u : 0u, {}});
                        report = &out.reports.back();
                    }
                    const uint32_t bits = g.reportSize * g.reportCount;
                    if (report->bitLength + bits > kMaxReportBits)
                        return fail(at, "report longer than " + std::to_string(kMaxReportBits / 8) +
                                            " bytes");
                    if (bits > 0) {
                        HidField f;
                        f.kind = kind;
                        f.reportId = g.reportId;
                        f.bitOffset = report->bitLength;
                        f.bitSize = g.reportSize;
                        f.count = g.reportCount;
                        f.flags = data;
                        f.usages = std::move(l.usages);
                        if (f.isVariable() && f.usages.size() > f.count) f.usages.resize(f.count);
                        f.logicalMin = g.logicalMin;
                        f.logicalMax =
                            resolveMax(g.logicalMin, g.logicalMaxRaw, g.logicalMaxSigned);
                        f.physicalMin = g.physicalMin;
                        f.physicalMax =
                            resolveMax(g.physicalMin, g.physicalMaxRaw, g.physicalMaxSigned);
                        f.unit = g.unit;
                        f.unitExponent = g.unitExponent;
                        f.applicationUsage = applicationUsage;
                        f.collectionUsage = collections.empty() ? 0 : collections.back().usage;
                        report->fields.push_back(std::move(f));
                    }
                    report->bitLength += bits;
                    break;
                }
                case 0xA: {  // Collection
                    if (collections.size() >= kMaxCollectionDepth)
                        return fail(at, "collections nested too deep");
                    uint32_t usage =
                        !l.usages.empty() ? l.usages.front() : (l.hasMin ? l.usageMin : 0);
                    collections.push_back({usage, uint8_t(data)});
                    if (data == 1) applicationUsage = usage;
                    break;
                }
                case 0xC:  // End Collection
                    if (collections.empty()) return fail(at, "End Collection without Collection");
                    collections.pop_back();
                    if (std::none_of(collections.begin(), collections.end(),
                                     [](const Collection& c) { return c.type == 1; }))
                        applicationUsage = 0;
                    break;
                default:
                    break;  // reserved main items carry nothing we use
            }
            l.clear();
        } else if (type == 1) {  // global
            switch (tag) {
                case 0x0:
                    g.usagePage = uint16_t(data);
                    break;
                case 0x1:
                    g.logicalMin = sdata;
                    break;
                case 0x2:
                    g.logicalMaxRaw = data;
                    g.logicalMaxSigned = sdata;
                    break;
                case 0x3:
                    g.physicalMin = sdata;
                    break;
                case 0x4:
                    g.physicalMaxRaw = data;
                    g.physicalMaxSigned = sdata;
                    break;
                case 0x5:
                    // Usually a 4-bit two's complement nibble (0xD = -3); some devices write a
                    // full signed byte instead.
                    g.unitExponent = int8_t(data < 16 ? (data >= 8 ? int(data) - 16 : int(data))
                                                      : std::clamp(sdata, -128, 127));
                    break;
                case 0x6:
                    g.unit = data;
                    break;
                case 0x7:
                    g.reportSize = data;
                    break;
                case 0x8:
                    if (data == 0 || data > 255)
                        return fail(at, "Report ID " + std::to_string(data) + " out of 1..255");
                    g.reportId = uint8_t(data);
                    out.usesReportIds = true;
                    break;
                case 0x9:
                    g.reportCount = data;
                    break;
                case 0xA:
                    if (stack.size() >= kMaxPushDepth) return fail(at, "Push nested too deep");
                    stack.push_back(g);
                    break;
                case 0xB:
                    if (stack.empty()) return fail(at, "Pop without Push");
                    g = stack.back();
                    stack.pop_back();
                    break;
                default:
                    break;
            }
        } else if (type == 2) {  // local
            auto addRange = [&] {
                if (!l.hasMin || !l.hasMax) return;
                // A range spans one page; the page comes from the minimum.
                const uint32_t lo = l.usageMin, hi = (lo & 0xFFFF0000u) | (l.usageMax & 0xFFFF);
                for (uint32_t u = lo; u <= hi && l.usages.size() < kMaxUsagesPerItem; ++u)
                    l.usages.push_back(u);
                l.hasMin = l.hasMax = false;
            };
            switch (tag) {
                case 0x0:
                    if (l.usages.size() < kMaxUsagesPerItem)
                        l.usages.push_back(resolveUsage(data, size, g.usagePage));
                    break;
                case 0x1:
                    l.usageMin = resolveUsage(data, size, g.usagePage);
                    l.hasMin = true;
                    addRange();
                    break;
                case 0x2:
                    l.usageMax = resolveUsage(data, size, g.usagePage);
                    l.hasMax = true;
                    addRange();
                    break;
                default:
                    break;  // designators, strings, delimiters: not needed to decode
            }
        }
        // type 3 (reserved short item): skipped
    }
    if (!collections.empty()) return fail(b.size(), "unclosed collection");
    return out;
}

std::optional<uint64_t> extractBits(std::span<const uint8_t> r, uint32_t bitOffset,
                                    uint32_t bitSize) {
    if (bitSize == 0 || bitSize > 64) return std::nullopt;
    if (uint64_t(bitOffset) + bitSize > uint64_t(r.size()) * 8) return std::nullopt;
    uint64_t v = 0;
    for (uint32_t k = 0; k < bitSize;) {
        const uint32_t bit = bitOffset + k;
        const uint32_t inByte = bit % 8, take = std::min(8 - inByte, bitSize - k);
        const uint64_t chunk = (uint64_t(r[bit / 8]) >> inByte) & ((1u << take) - 1);
        v |= chunk << k;
        k += take;
    }
    return v;
}

std::optional<int32_t> extractField(std::span<const uint8_t> r, const HidField& f, uint32_t index) {
    if (index >= f.count || f.bitSize > 32) return std::nullopt;
    const auto raw = extractBits(r, f.bitOffset + index * f.bitSize, f.bitSize);
    if (!raw) return std::nullopt;
    uint32_t v = uint32_t(*raw);
    if (f.logicalMin < 0 && f.bitSize < 32 && (v >> (f.bitSize - 1)) & 1) v |= ~0u << f.bitSize;
    return int32_t(v);
}

double hidPhysicalValue(const HidField& f, int32_t logical) {
    if (f.physicalMin == 0 && f.physicalMax == 0) return logical;
    if (f.logicalMax == f.logicalMin) return f.physicalMin;
    return f.physicalMin + (double(logical) - f.logicalMin) *
                               (double(f.physicalMax) - f.physicalMin) /
                               (double(f.logicalMax) - f.logicalMin);
}

std::optional<double> hidMillimetresPerUnit(const HidField& f) {
    const double scale = std::pow(10.0, f.unitExponent);
    if (f.unit == 0x11) return 10.0 * scale;  // SI linear, length^1: centimetre
    if (f.unit == 0x13) return 25.4 * scale;  // English linear, length^1: inch
    return std::nullopt;
}

std::optional<double> hidRadiansPerUnit(const HidField& f) {
    const double scale = std::pow(10.0, f.unitExponent);
    if (f.unit == 0x12) return scale;                 // SI rotation: radian
    if (f.unit == 0x14) return scale * M_PI / 180.0;  // English rotation: degree
    return std::nullopt;
}

}  // namespace vsculpt::devices
