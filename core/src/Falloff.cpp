// SPDX-License-Identifier: MIT
#include "vsculpt/core/Falloff.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace vsculpt::core {

std::string validateFalloff(const FalloffParams& p) {
    std::ostringstream why;
    if (!(std::isfinite(p.f0) && p.f0 > 0)) {
        why << "f0 must be a positive number (got " << p.f0 << ")";
    } else if (!(p.controlU > 0 && p.controlU < 1)) {
        why << "control_point.u must lie strictly between 0 and 1 (got " << p.controlU << ")";
    } else if (!(p.controlValue > 0 && p.controlValue < p.f0)) {
        why << "control_point.value must lie strictly between 0 and f0=" << p.f0 << " (got "
            << p.controlValue << ")";
    } else {
        // A cubic Hermite segment with one end slope 0 is monotone iff the other end slope is
        // between 0 and 3x the secant slope (Fritsch & Carlson).
        const double secant1 = (p.controlValue - p.f0) / p.controlU;
        const double secant2 = -p.controlValue / (1 - p.controlU);
        const double steepest = 3 * std::max(secant1, secant2);
        if (!(std::isfinite(p.controlSlope) && p.controlSlope <= 0 && p.controlSlope >= steepest)) {
            why << "control_slope must lie in [" << steepest << ", 0] for F to stay monotone"
                << " with this control point (got " << p.controlSlope << ")";
        }
    }
    return why.str();
}

HermiteFalloff::HermiteFalloff(const FalloffParams& p) : mParams(p) {
    if (const std::string why = validateFalloff(p); !why.empty()) throw std::invalid_argument(why);
    mF0 = p.f0;
    mA = p.controlU;
    mFa = p.controlValue;
    mS = p.controlSlope;
    mW = 1 - mA;
    mInvA = 1 / mA;
    mInvW = 1 / mW;
}

double HermiteFalloff::inverse(double level) const {
    if (!(level > 0 && level < mF0))
        throw std::invalid_argument("HermiteFalloff::inverse: level outside (0, f0)");
    double lo = 0, hi = 1;  // F(lo) > level >= F(hi)
    for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
        const double mid = 0.5 * (lo + hi);
        (value(mid) > level ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace vsculpt::core
