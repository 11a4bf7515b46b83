// SPDX-License-Identifier: MIT
/// @file CalibrationTable.h
/// @brief The support calibration of the shipped field settings, computed once at development
/// time and compiled in, so a process using them starts without the ~1 s of calibration
/// (issue #14: `vsculpt info` within 100 ms). Any other settings are calibrated at run time as
/// before. A test recomputes every entry and requires the same numbers bit for bit, so the
/// table cannot drift from the calibration code: when calibration changes, the test fails and
/// prints the new entries (docs/benchmarks.md, "Startup").
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Falloff.h"
#include "vsculpt/core/ToolLevels.h"

#include <array>
#include <span>

namespace vsculpt::core {

/// One calibration: its inputs (what calibrateSupport, strokeCoverageTable and
/// strokeWallValue read) and their results.
struct TabulatedCalibration {
    PlacementMode mode = PlacementMode::Free;
    FalloffParams falloff;
    double spacingOverDiameter = 0;
    double iso = 0;
    CalibrationReport report;
    std::array<double, 9> coverage{};  ///< strokeCoverageTable at lateral 0, 1/8, ..., 1
    double wall = 0;                   ///< strokeWallValue
};

/// Every compiled-in entry.
std::span<const TabulatedCalibration> calibrationTable();

/// The entry for exactly these inputs, or nullptr (then calibrate at run time).
const TabulatedCalibration* findTabulatedCalibration(PlacementMode mode,
                                                     const FalloffParams& falloff,
                                                     double spacingOverDiameter, double iso);

/// The calibration computed now for an entry's inputs (for the test that keeps the table in
/// step with the code, and to print new entries).
TabulatedCalibration computeCalibration(PlacementMode mode, const FalloffParams& falloff,
                                        double spacingOverDiameter, double iso);

}  // namespace vsculpt::core
