// SPDX-License-Identifier: MIT
/// @file ToolLevels.h
/// @brief Per-level tool geometry derived from a SculptConfig: diameter, lattice spacing,
/// support radius of F, and the calibration that sets the support radius.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Falloff.h"

#include <algorithm>
#include <array>
#include <vector>

namespace vsculpt::core {

struct ToolLevel {
    int level = 0;          ///< 1..7
    double diameterMm = 0;  ///< D_k
    double spacingMm = 0;   ///< h_k, lattice spacing
    double supportMm = 0;   ///< R_k: F_k(d) = F(d / R_k), zero for d >= R_k
    double scale = 0;       ///< L_k = R_k / R_4 (thesis's horizontal-scale multiplier)
};

/// How well the calibrated support radius reproduces the tool size (see calibrateSupport()).
struct CalibrationReport {
    double supportOverDiameter = 0;  ///< R_k / D_k (the same at every level: see docs)
    double meanRadiusError = 0;      ///< |mean tube radius - D/2| / (D/2) over all test strokes
    double worstDirectionError = 0;  ///< max over stroke directions of |mean radius - D/2|/(D/2)
    double maxLocalDeviation = 0;    ///< max |local radius - D/2| / (D/2) (lattice ripple)
    int directions = 0;              ///< number of stroke directions/offsets used
};

/// Weight a fresh add stroke gives a vertex at lateral distance `s` (fraction of the tool
/// radius, 0..1) from its path. Thesis mode: 1 (the thesis's unit skeletons). Free mode:
/// (1 - s^2)^2, a smooth brush: it samples the swept tube like an antialiased raster, which
/// makes the tube radius far less dependent on how the stroke lies on the lattice
/// (docs/placement.md has the numbers).
inline double strokeProfile(PlacementMode mode, double s) {
    if (mode == PlacementMode::Thesis) return 1.0;
    const double t = 1.0 - std::min(s * s, 1.0);
    return t * t;
}

class ToolLevels {
  public:
    /// Builds the table; calibrates support radii unless cfg.manualSupport is set.
    /// @pre validateConfig(cfg) passed.
    explicit ToolLevels(const SculptConfig& cfg);

    const ToolLevel& level(int k) const;  ///< k in 1..7, checked
    const HermiteFalloff& falloff() const { return mFalloff; }
    double iso() const { return mIso; }
    bool calibrated() const { return mCalibrated; }
    const CalibrationReport& calibration() const { return mReport; }
    double maxSupportMm() const { return mLevels[kLevelCount - 1].supportMm; }

    PlacementMode mode() const { return mMode; }

    /// See strokeWallValue(): the share of a uniform carve that reaches the tool's surface.
    double strokeWallValue() const { return mWall; }

    /// Field value of a fresh straight stroke at a lattice vertex at lateral distance `lateral`
    /// (as a fraction of the tool radius, 0..1) from the stroke axis, averaged over stroke
    /// directions (the T of docs/placement.md).
    double strokeCoverage(double lateralOverRadius) const;
    /// strokeProfile / strokeCoverage: the weight that makes a stroke change the field by one
    /// unit along its path. Free-mode placement scales it by what it adds or removes.
    double strokeGain(double lateralOverRadius) const {
        return strokeProfile(mMode, lateralOverRadius) / strokeCoverage(lateralOverRadius);
    }

  private:
    std::array<ToolLevel, kLevelCount> mLevels{};
    HermiteFalloff mFalloff;
    double mIso;
    PlacementMode mMode;
    bool mCalibrated = false;
    CalibrationReport mReport;
    double mWall = 1;
    std::vector<double> mCoverage;  // tabulated over lateral distance 0..1, linear in between
};

}  // namespace vsculpt::core
