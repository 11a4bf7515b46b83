// SPDX-License-Identifier: MIT
#include "vsculpt/devices/HidMultiAxis.h"

#include <algorithm>

namespace vsculpt::devices {

namespace {

constexpr uint16_t kDesktop = 0x01, kButton = 0x09, kGenericDevice = 0x06;
constexpr uint32_t kMultiAxisController = hidUsage(kDesktop, 0x08);

std::optional<SpaceMouseSample> fail(DecodeStatus* status, DecodeStatus why) {
    if (status) *status = why;
    return std::nullopt;
}

}  // namespace

std::optional<HidMultiAxisDecoder> HidMultiAxisDecoder::fromDescriptor(const HidDescriptor& d,
                                                                       std::string* error) {
    bool hasMultiAxisApp = false;
    for (const HidReport& r : d.reports)
        for (const HidField& f : r.fields)
            hasMultiAxisApp = hasMultiAxisApp || f.applicationUsage == kMultiAxisController;
    // Without a Multi-axis Controller, joysticks and gamepads qualify; a pen's or a mouse's
    // X/Y do not.
    auto accepted = [&](uint32_t app) {
        if (hasMultiAxisApp) return app == kMultiAxisController;
        return app == hidUsage(kDesktop, 0x04) || app == hidUsage(kDesktop, 0x05);
    };

    HidMultiAxisDecoder dec;
    dec.mUsesIds = d.usesReportIds;
    for (const HidReport& r : d.reports) {
        if (r.kind != HidReportKind::Input) continue;
        Report rep;
        rep.id = r.id;
        rep.bytes = r.byteLength();
        for (const HidField& f : r.fields) {
            if (f.isConstant() || !f.isVariable() || f.bitSize > 32) continue;
            if (!accepted(f.applicationUsage)) continue;
            for (uint32_t i = 0; i < f.count; ++i) {
                const uint32_t u = f.usageAt(i);
                if (u >= hidUsage(kDesktop, 0x30) && u <= hidUsage(kDesktop, 0x35)) {
                    const int axis = int(u - hidUsage(kDesktop, 0x30));
                    rep.axes.push_back({f, i, axis});
                    if (axis == 0 && !dec.mMmPerCount && f.logicalMax != f.logicalMin &&
                        f.physicalMax != f.physicalMin) {
                        if (auto mm = hidMillimetresPerUnit(f))
                            dec.mMmPerCount = *mm * (double(f.physicalMax) - f.physicalMin) /
                                              (double(f.logicalMax) - f.logicalMin);
                    }
                } else if ((u >> 16) == kButton && (u & 0xFFFF) >= 1 && (u & 0xFFFF) <= 32) {
                    rep.buttons.push_back({f, i, int(u & 0xFFFF) - 1});
                } else if (u == hidUsage(kGenericDevice, 0x20) && !rep.battery) {
                    rep.battery = std::make_pair(f, i);
                }
            }
        }
        if (!rep.axes.empty() || !rep.buttons.empty() || rep.battery)
            dec.mReports.push_back(std::move(rep));
    }
    if (std::none_of(dec.mReports.begin(), dec.mReports.end(),
                     [](const Report& r) { return !r.axes.empty(); })) {
        if (error) *error = "no input report with a Generic Desktop X..Rz axis";
        return std::nullopt;
    }
    return dec;
}

std::optional<SpaceMouseSample> HidMultiAxisDecoder::decode(std::span<const uint8_t> r,
                                                            int64_t timeNs,
                                                            DecodeStatus* status) const {
    if (r.empty()) return fail(status, DecodeStatus::Empty);
    const uint8_t id = mUsesIds ? r[0] : 0;
    const auto rep =
        std::find_if(mReports.begin(), mReports.end(), [&](const Report& x) { return x.id == id; });
    if (rep == mReports.end()) return fail(status, DecodeStatus::UnknownReport);
    if (r.size() < rep->bytes) return fail(status, DecodeStatus::Truncated);

    SpaceMouseSample s;
    s.timeNs = timeNs;
    for (const Axis& a : rep->axes) {
        const auto v = extractField(r, a.field, a.index);
        if (!v) return fail(status, DecodeStatus::Truncated);
        const int16_t clamped = int16_t(std::clamp<int32_t>(*v, INT16_MIN, INT16_MAX));
        if (a.axis < 3) {
            s.hasTranslation = true;
            s.translation[a.axis] = clamped;
        } else {
            s.hasRotation = true;
            s.rotation[a.axis - 3] = clamped;
        }
    }
    for (const Button& b : rep->buttons) {
        s.hasButtons = true;
        if (extractField(r, b.field, b.index).value_or(0) != 0) s.buttons |= 1u << b.bit;
    }
    if (rep->battery) {
        if (const auto v = extractField(r, rep->battery->first, rep->battery->second)) {
            s.hasBattery = true;
            s.battery = std::clamp<int32_t>(*v, 0, 100);
        }
    }
    if (status) *status = DecodeStatus::Ok;
    return s;
}

}  // namespace vsculpt::devices
