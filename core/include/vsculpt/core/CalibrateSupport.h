// SPDX-License-Identifier: MIT
/// @file CalibrateSupport.h
/// @brief Solves for the support radius of F so that a straight stroke on empty space gives a
/// tube of radius D/2, the criterion the thesis applied by hand.
///
/// Everything in one level scales with its diameter (lattice spacing sigma*D, tool radius D/2,
/// support radius R), so the ratio R/D solved here holds for every level; tests check each
/// level through the real placement and field code.
#pragma once

#include "vsculpt/core/Falloff.h"
#include "vsculpt/core/ToolLevels.h"

#include <vector>

namespace vsculpt::core {

struct CalibrationResult {
    CalibrationReport report;
};

/// The fresh straight stroke's own field value at its lattice vertices, tabulated over their
/// lateral distance from the axis (as a fraction of the tool radius, 9 even steps over 0..1),
/// averaged over calibrationLines(). See ToolLevels::strokeCoverage().
std::vector<double> strokeCoverageTable(PlacementMode mode, const HermiteFalloff& falloff,
                                        double spacingOverDiameter, double supportOverDiameter);

/// Field at the tool's surface (lateral distance D/2) of a straight stroke whose vertices carry
/// the unit-change weights strokeProfile/coverage: the fraction of a uniform change that
/// reaches the tool's surface. Free-mode carving divides by it so the carved wall lands on
/// the tool's surface.
double strokeWallValue(PlacementMode mode, const HermiteFalloff& falloff,
                       double spacingOverDiameter, double supportOverDiameter,
                       const std::vector<double>& coverage);

/// @param mode placement mode: sets the weights a fresh stroke gives its vertices
///        (strokeProfile())
/// @param falloff the F to calibrate
/// @param spacingOverDiameter sigma
/// @param iso c
/// Throws std::runtime_error if no support radius in [D/4, 8D] reaches the target (possible
/// only for extreme falloff shapes, which validateConfig() already rejects).
CalibrationResult calibrateSupport(PlacementMode mode, const HermiteFalloff& falloff,
                                   double spacingOverDiameter, double iso);

struct TubeMeasurement {
    double mean = 0, min = 0, max = 0;  ///< iso-surface radius, mm
};

/// Iso-surface radius of a straight stroke of a tool of diameter `diameter` (mm) with lattice
/// spacing `spacing` and support radius `support`, through `origin` along `direction`,
/// measured away from the stroke's ends at 16 angles and 8 axial offsets.
TubeMeasurement measureTube(PlacementMode mode, const HermiteFalloff& falloff, double iso,
                            double diameter, double spacing, double support, const Vec3& origin,
                            const Vec3& direction);

/// The stroke directions and origins (origin in units of the lattice spacing) calibration
/// averages over.
struct StrokeLine {
    Vec3 direction, originInSpacings;
};
const std::vector<StrokeLine>& calibrationLines();

}  // namespace vsculpt::core
