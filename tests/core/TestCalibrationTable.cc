// SPDX-License-Identifier: MIT
// The compiled-in calibrations (CalibrationTable.h) are what the calibration code computes
// now, bit for bit; processes with the shipped settings use them and skip calibrating.
#include "vsculpt/core/CalibrationTable.h"

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Sculpture.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

using namespace vsculpt::core;

namespace {

// The settings the table must hold: the shipped config in every placement mode.
std::vector<SculptConfig> shippedSettings() {
    std::vector<SculptConfig> out;
    for (PlacementMode m : {PlacementMode::Thesis, PlacementMode::Free, PlacementMode::Swept}) {
        SculptConfig c;
        c.placement = m;
        out.push_back(c);
    }
    return out;
}

void printEntry(const TabulatedCalibration& t) {
    const char* mode = t.mode == PlacementMode::Thesis ? "Thesis"
                       : t.mode == PlacementMode::Free ? "Free"
                                                       : "Swept";
    std::printf("    {PlacementMode::%s,\n     {%a, %a, %a, %a},\n     %a,\n     %a,\n", mode,
                t.falloff.f0, t.falloff.controlU, t.falloff.controlValue, t.falloff.controlSlope,
                t.spacingOverDiameter, t.iso);
    std::printf("     {%a, %a, %a, %a, %d},\n     {", t.report.supportOverDiameter,
                t.report.meanRadiusError, t.report.worstDirectionError, t.report.maxLocalDeviation,
                t.report.directions);
    for (size_t i = 0; i < t.coverage.size(); ++i)
        std::printf("%s%a", i ? ", " : "", t.coverage[i]);
    std::printf("},\n     %a},\n", t.wall);
}

TEST(CalibrationTable, EveryShippedSettingIsTabulatedAndEqualsAFreshCalibration) {
    const bool print = std::getenv("VSCULPT_PRINT_CALIBRATION_TABLE") != nullptr;
    if (print) std::printf("constexpr TabulatedCalibration kEntries[] = {\n");
    for (const SculptConfig& c : shippedSettings()) {
        const TabulatedCalibration fresh =
            computeCalibration(c.placement, c.falloff, c.spacingOverDiameter, c.iso);
        if (print) printEntry(fresh);
        const TabulatedCalibration* t =
            findTabulatedCalibration(c.placement, c.falloff, c.spacingOverDiameter, c.iso);
        if (!t) {
            ADD_FAILURE() << toString(c.placement)
                          << ": not tabulated (VSCULPT_PRINT_CALIBRATION_TABLE=1 prints it)";
            continue;
        }
        EXPECT_EQ(t->report.supportOverDiameter, fresh.report.supportOverDiameter);
        EXPECT_EQ(t->report.meanRadiusError, fresh.report.meanRadiusError);
        EXPECT_EQ(t->report.worstDirectionError, fresh.report.worstDirectionError);
        EXPECT_EQ(t->report.maxLocalDeviation, fresh.report.maxLocalDeviation);
        EXPECT_EQ(t->report.directions, fresh.report.directions);
        for (size_t i = 0; i < fresh.coverage.size(); ++i)
            EXPECT_EQ(t->coverage[i], fresh.coverage[i]) << "coverage " << i;
        EXPECT_EQ(t->wall, fresh.wall);
    }
    if (print) std::printf("};\n");
}

TEST(CalibrationTable, ToolLevelsUseTheTableOrCalibrateTheSame) {
    // The shipped settings come from the table; a setting off the table is calibrated and
    // gives the same tool levels as the table would for its own inputs.
    const SculptConfig shipped;
    const ToolLevels levels(shipped);
    const TabulatedCalibration* t = findTabulatedCalibration(
        shipped.placement, shipped.falloff, shipped.spacingOverDiameter, shipped.iso);
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(levels.calibration().supportOverDiameter, t->report.supportOverDiameter);
    EXPECT_EQ(levels.strokeWallValue(), t->wall);
    SculptConfig other = shipped;
    other.iso = 0.45;
    EXPECT_EQ(findTabulatedCalibration(other.placement, other.falloff, other.spacingOverDiameter,
                                       other.iso),
              nullptr);
    const ToolLevels calibrated(other);
    EXPECT_TRUE(calibrated.calibrated());
    const TabulatedCalibration fresh =
        computeCalibration(other.placement, other.falloff, other.spacingOverDiameter, other.iso);
    EXPECT_EQ(calibrated.calibration().supportOverDiameter, fresh.report.supportOverDiameter);
    EXPECT_EQ(calibrated.strokeWallValue(), fresh.wall);
}

}  // namespace
