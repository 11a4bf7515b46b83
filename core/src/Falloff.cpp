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

namespace {
/// Coefficients in u of the cubic Hermite segment from (u0, v0) with slope m0 to (u1, v1)
/// with slope m1, with tangent u-components equal to the width (so u(t) is linear).
void hermiteInU(double u0, double u1, double v0, double v1, double m0, double m1, double c[4]) {
    const double w = u1 - u0;
    // In t = (u - u0) / w: v0 + m0 w t + (3(v1 - v0) - (2 m0 + m1) w) t^2
    //                      + (2(v0 - v1) + (m0 + m1) w) t^3
    const double b0 = v0, b1 = m0 * w, b2 = 3 * (v1 - v0) - (2 * m0 + m1) * w,
                 b3 = 2 * (v0 - v1) + (m0 + m1) * w;
    // Substitute t = (u - u0) / w and expand.
    const double s = 1 / w, s2 = s * s, s3 = s2 * s;
    c[0] = b0 - b1 * u0 * s + b2 * u0 * u0 * s2 - b3 * u0 * u0 * u0 * s3;
    c[1] = b1 * s - 2 * b2 * u0 * s2 + 3 * b3 * u0 * u0 * s3;
    c[2] = b2 * s2 - 3 * b3 * u0 * s3;
    c[3] = b3 * s3;
}
}  // namespace

HermiteFalloff::HermiteFalloff(const FalloffParams& p) : mParams(p) {
    if (const std::string why = validateFalloff(p); !why.empty()) throw std::invalid_argument(why);
    mA = p.controlU;
    hermiteInU(0.0, mA, p.f0, p.controlValue, 0.0, p.controlSlope, mC1);
    hermiteInU(mA, 1.0, p.controlValue, 0.0, p.controlSlope, 0.0, mC2);
}

double HermiteFalloff::inverse(double level) const {
    if (!(level > 0 && level < mParams.f0))
        throw std::invalid_argument("HermiteFalloff::inverse: level outside (0, f0)");
    double lo = 0, hi = 1;  // F(lo) > level >= F(hi)
    for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
        const double mid = 0.5 * (lo + hi);
        (value(mid) > level ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace vsculpt::core
