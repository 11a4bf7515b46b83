// SPDX-License-Identifier: MIT
/// @file HidDescriptor.h
/// @brief A generic USB HID report-descriptor parser and a bit-field extractor. Pure code:
/// descriptor bytes in, per-report field lists out; the transport reads the descriptor
/// (HIDIOCGRDESC or GET_DESCRIPTOR) and the reports.
///
/// Handles short items with global/local state, Push/Pop, usage ranges, extended (32-bit)
/// usages, report ids and collections; long items are skipped. Device bytes never throw: a
/// malformed descriptor gives nullopt and a message saying what and where.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vsculpt::devices {

enum class HidReportKind : uint8_t { Input, Output, Feature };

/// A usage with its page: page << 16 | id.
constexpr uint32_t hidUsage(uint16_t page, uint16_t id) {
    return uint32_t(page) << 16 | id;
}

/// Main-item flag bits (HID 1.11 §6.2.2.5).
enum HidFieldFlag : uint32_t {
    HidConstant = 1u << 0,
    HidVariable = 1u << 1,  ///< else an array of usage indices
    HidRelative = 1u << 2,
    HidWrap = 1u << 3,
    HidNullState = 1u << 6,
};

/// One main item (Input/Output/Feature): reportCount fields of reportSize bits each.
struct HidField {
    HidReportKind kind = HidReportKind::Input;
    uint8_t reportId = 0;  ///< 0 when the descriptor declares no report ids
    /// From the first byte of the report as read from the device, i.e. counting the report-id
    /// byte when the descriptor uses ids.
    uint32_t bitOffset = 0;
    uint32_t bitSize = 0;  ///< per element (Report Size)
    uint32_t count = 0;    ///< elements (Report Count)
    uint32_t flags = 0;    ///< HidFieldFlag bits
    /// Variable items: the usage of each element (the last one repeats when there are fewer
    /// usages than elements). Array items: the usages that element values index, from
    /// logicalMin up.
    std::vector<uint32_t> usages;
    int32_t logicalMin = 0, logicalMax = 0;
    int32_t physicalMin = 0, physicalMax = 0;  ///< both 0 = same as logical
    uint32_t unit = 0;                         ///< HID unit code (system nibble + exponents)
    int8_t unitExponent = 0;                   ///< power of ten
    uint32_t applicationUsage = 0;             ///< usage of the enclosing application collection
    uint32_t collectionUsage = 0;              ///< usage of the innermost enclosing collection

    bool isConstant() const { return flags & HidConstant; }
    bool isVariable() const { return flags & HidVariable; }
    /// Usage of element i of a variable item (0 if there is none).
    uint32_t usageAt(uint32_t i) const;
};

struct HidReport {
    HidReportKind kind = HidReportKind::Input;
    uint8_t id = 0;
    uint32_t bitLength = 0;  ///< including the id byte when ids are used
    std::vector<HidField> fields;
    uint32_t byteLength() const { return (bitLength + 7) / 8; }
};

struct HidDescriptor {
    bool usesReportIds = false;
    std::vector<HidReport> reports;  ///< in order of first appearance
    const HidReport* find(HidReportKind kind, uint8_t id) const;
    /// The first variable, non-constant field with this usage in a report of this kind, and the
    /// element index within it.
    struct FieldRef {
        const HidReport* report = nullptr;
        const HidField* field = nullptr;
        uint32_t index = 0;
    };
    std::optional<FieldRef> findUsage(HidReportKind kind, uint32_t usage) const;
};

/// Parses a report descriptor. nullopt on malformed bytes (truncated item, Pop without Push,
/// unbalanced collections, report id 0, absurd sizes); `error` then says what and at which
/// byte offset.
std::optional<HidDescriptor> parseHidDescriptor(std::span<const uint8_t> bytes,
                                                std::string* error = nullptr);

/// Reads bitSize (1..64) bits starting at bitOffset, little-endian bit order as HID packs
/// them. nullopt if the field reaches past the span or bitSize is out of range.
std::optional<uint64_t> extractBits(std::span<const uint8_t> report, uint32_t bitOffset,
                                    uint32_t bitSize);

/// Element i of a field, sign-extended when the field's logical minimum is negative.
/// nullopt when the report is too short or the field is wider than 32 bits.
std::optional<int32_t> extractField(std::span<const uint8_t> report, const HidField& field,
                                    uint32_t index = 0);

/// Maps a logical value to the physical range (the logical value itself when the physical range
/// is empty), not yet scaled by the unit exponent.
double hidPhysicalValue(const HidField& field, int32_t logical);

/// Millimetres per physical unit of a length field (cm or inch, times 10^exponent); nullopt
/// when the unit is not a length.
std::optional<double> hidMillimetresPerUnit(const HidField& field);

/// Radians per physical unit of an angle field (radians or degrees, times 10^exponent);
/// nullopt when the unit is not an angle.
std::optional<double> hidRadiansPerUnit(const HidField& field);

}  // namespace vsculpt::devices
