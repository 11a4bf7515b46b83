// SPDX-License-Identifier: MIT
/// @file Falloff.h
/// @brief The distance-field function F of a point skeleton: a two-segment cubic Hermite
/// falloff on normalised distance u = d / R (R = support radius of the skeleton's level).
///
/// Shape (thesis eq. 11, reconstructed): F(0) = f0 with zero slope, passes through the control
/// point (a, Fa) with slope s = dF/du, reaches 0 at u = 1 with zero slope and stays 0 beyond.
/// Both segments use tangents whose u-components equal the segment widths, so u(t) is linear
/// and F(u) is an explicit cubic on each segment: C1 everywhere, compact support.
#pragma once

#include <string>

namespace vsculpt::core {

struct FalloffParams {
    double f0 = 1.0;             ///< F(0), dimensionless field value at the skeleton
    double controlU = 0.5;       ///< a: control point position as a fraction of the support radius
    double controlValue = 0.5;   ///< Fa: field value at the control point
    double controlSlope = -1.5;  ///< s = dF/du at the control point (u = d/R), <= 0
};

/// Why a parameter set is rejected, or an empty string when it is valid. Valid means:
/// f0 > 0, 0 < a < 1, 0 < Fa < f0, and 3*secant <= s <= 0 on both segments (the exact
/// monotonicity bound of a cubic Hermite segment whose other end slope is 0).
std::string validateFalloff(const FalloffParams& p);

class HermiteFalloff {
  public:
    /// @pre validateFalloff(p).empty(); checked, throws std::invalid_argument otherwise.
    explicit HermiteFalloff(const FalloffParams& p);

    /// F(u) for normalised distance u >= 0. Returns 0 for u >= 1.
    double value(double u) const {
        if (u >= 1.0) return 0.0;
        // Each segment's cubic expanded in u once (constructor), evaluated by Horner's rule.
        const double* c = u <= mA ? mC1 : mC2;
        return c[0] + u * (c[1] + u * (c[2] + u * c[3]));
    }

    /// dF/du for u >= 0 (0 for u >= 1 and at u = 0).
    double derivative(double u) const {
        if (u >= 1.0) return 0.0;
        const double* c = u <= mA ? mC1 : mC2;
        return c[1] + u * (2 * c[2] + u * 3 * c[3]);
    }

    /// The u in [0, 1] where F(u) = level, for 0 < level < f0 (F is monotone there).
    double inverse(double level) const;

    const FalloffParams& params() const { return mParams; }

  private:
    FalloffParams mParams;
    double mA;
    double mC1[4], mC2[4];  // polynomial coefficients in u of the two segments
};

}  // namespace vsculpt::core
