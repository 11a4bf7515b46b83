// SPDX-License-Identifier: MIT
#include "vsculpt/devices/HidDigitizer.h"

#include <algorithm>
#include <cmath>

namespace vsculpt::devices {

namespace {

constexpr uint16_t kDesktop = 0x01, kDigitizer = 0x0D;

std::optional<PenSample> fail(DecodeStatus* status, DecodeStatus why) {
    if (status) *status = why;
    return std::nullopt;
}

}  // namespace

uint32_t hidEquivalentPenUsage(uint32_t usage) {
    if ((usage >> 16) != 0xFF0D) return usage;
    // Wacom packs a standard usage into the id: high byte = its page (0 = Digitizer), low byte
    // = its id.
    const uint16_t page = (usage >> 8) & 0xFF, id = usage & 0xFF;
    return hidUsage(page ? page : kDigitizer, id);
}

std::optional<HidDigitizerDecoder> HidDigitizerDecoder::fromDescriptor(const HidDescriptor& d,
                                                                       std::string* error) {
    // Touch screens with a pen describe fingers with the same Tip Switch and X/Y usages, often
    // in an earlier report: prefer a report in a Pen application, then a generic Digitizer
    // one, and take a Touch Screen / Touch Pad report only when there is nothing else.
    auto rank = [](const HidReport& r) {
        const uint32_t app =
            r.fields.empty() ? 0 : hidEquivalentPenUsage(r.fields[0].applicationUsage);
        if (app == hidUsage(kDigitizer, 0x02)) return 0;
        if (app == hidUsage(kDigitizer, 0x01)) return 1;
        if (app == hidUsage(kDigitizer, 0x04) || app == hidUsage(kDigitizer, 0x05)) return 3;
        return 2;
    };
    std::optional<HidDigitizerDecoder> best;
    int bestRank = 4;
    for (const HidReport& r : d.reports) {
        if (r.kind != HidReportKind::Input || rank(r) >= bestRank) continue;
        HidDigitizerDecoder dec;
        auto bind = [](Slot& s, const HidField& f, uint32_t i) {
            if (s.field) return;  // first occurrence wins (multi-touch repeats usages)
            s.field = f;
            s.index = i;
        };
        for (const HidField& f : r.fields) {
            if (f.isConstant() || !f.isVariable()) continue;
            for (uint32_t i = 0; i < f.count; ++i) {
                switch (hidEquivalentPenUsage(f.usageAt(i))) {
                    case hidUsage(kDigitizer, 0x42):
                        bind(dec.mTip, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x32):
                        bind(dec.mInRange, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x44):
                        bind(dec.mBarrel, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x5A):
                        bind(dec.mBarrel2, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x3C):
                        bind(dec.mInvert, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x45):
                        bind(dec.mEraser, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x30):
                        bind(dec.mPressure, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x3D):
                        bind(dec.mTiltX, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x3E):
                        bind(dec.mTiltY, f, i);
                        break;
                    case hidUsage(kDigitizer, 0x5B):
                        bind(dec.mSerial, f, i);
                        break;
                    case hidUsage(kDesktop, 0x30):
                        bind(dec.mX, f, i);
                        break;
                    case hidUsage(kDesktop, 0x31):
                        bind(dec.mY, f, i);
                        break;
                    default:
                        break;
                }
            }
        }
        if (!dec.mX.field || !dec.mY.field || !(dec.mTip.field || dec.mInRange.field)) continue;
        if (dec.mX.field->bitSize > 32 || dec.mY.field->bitSize > 32) continue;
        dec.mReportId = r.id;
        dec.mUsesIds = d.usesReportIds;
        dec.mReportBytes = r.byteLength();
        auto size = [](const HidField& f, double& mmPerUnit, double& extent) {
            if (f.physicalMin == f.physicalMax) return;
            if (auto mm = hidMillimetresPerUnit(f)) {
                mmPerUnit = *mm;
                extent = (double(f.physicalMax) - f.physicalMin) * *mm;
            }
        };
        size(*dec.mX.field, dec.mXmm, dec.mWidthMm);
        size(*dec.mY.field, dec.mYmm, dec.mHeightMm);
        best = dec;
        bestRank = rank(r);
    }
    if (!best && error) *error = "no input report with X, Y and Tip Switch or In Range";
    return best;
}

std::optional<PenSample> HidDigitizerDecoder::decode(std::span<const uint8_t> r, int64_t timeNs,
                                                     DecodeStatus* status) const {
    if (r.empty()) return fail(status, DecodeStatus::Empty);
    if (mUsesIds && r[0] != mReportId) return fail(status, DecodeStatus::UnknownReport);
    if (r.size() < mReportBytes) return fail(status, DecodeStatus::Truncated);

    auto value = [&](const Slot& s) -> std::optional<int32_t> {
        if (!s.field) return std::nullopt;
        return extractField(r, *s.field, s.index);
    };
    // Out-of-range values (devices that overshoot, or Null-state fields) are pinned to the
    // declared range so positions stay on the tablet.
    auto clamped = [](const HidField& f, int32_t v) {
        return f.logicalMax > f.logicalMin ? std::clamp(v, f.logicalMin, f.logicalMax) : v;
    };
    auto flag = [&](const Slot& s) { return value(s).value_or(0) != 0; };
    auto normalized = [](const HidField& f, int32_t v) {
        if (f.logicalMax <= f.logicalMin) return 0.0;
        return std::clamp((double(v) - f.logicalMin) / (double(f.logicalMax) - f.logicalMin), 0.0,
                          1.0);
    };

    PenSample s;
    s.timeNs = timeNs;
    const bool tip = flag(mTip), invert = flag(mInvert), eraser = flag(mEraser);
    s.inProximity = mInRange.field ? flag(mInRange) : tip;
    s.touching = tip || eraser;
    s.inProximity = s.inProximity || s.touching;
    s.tool = !s.inProximity ? PenTool::None : (invert || eraser) ? PenTool::Eraser : PenTool::Pen;
    s.buttons = (flag(mBarrel) ? 1u : 0u) | (flag(mBarrel2) ? 2u : 0u);

    auto x = value(mX), y = value(mY);
    if (!x || !y) return fail(status, DecodeStatus::Truncated);
    x = clamped(*mX.field, *x);
    y = clamped(*mY.field, *y);
    s.hasPosition = true;
    s.positionNormalized = {normalized(*mX.field, *x), normalized(*mY.field, *y)};
    if (hasPhysicalSize())
        s.positionMm = {(hidPhysicalValue(*mX.field, *x) - mX.field->physicalMin) * mXmm,
                        (hidPhysicalValue(*mY.field, *y) - mY.field->physicalMin) * mYmm};

    if (const auto p = value(mPressure))
        s.pressure = normalized(*mPressure.field, *p);
    else
        s.pressure = s.touching ? 1.0 : 0.0;

    const auto tx = value(mTiltX), ty = value(mTiltY);
    if (tx && ty) {
        auto angle = [](const HidField& f, int32_t v) {
            if (auto rad = hidRadiansPerUnit(f)) return hidPhysicalValue(f, v) * *rad;
            return v * M_PI / 180.0;
        };
        s.hasTilt = true;
        s.tiltRad = {angle(*mTiltX.field, *tx), angle(*mTiltY.field, *ty)};
    }
    if (const auto serial = value(mSerial)) s.toolSerial = uint32_t(*serial);

    if (status) *status = DecodeStatus::Ok;
    return s;
}

}  // namespace vsculpt::devices
