// SPDX-License-Identifier: MIT
#include "vsculpt/core/ToolLevels.h"

#include "vsculpt/core/CalibrateSupport.h"
#include "vsculpt/core/CalibrationTable.h"

#include <cmath>
#include <stdexcept>

namespace vsculpt::core {

ToolLevels::ToolLevels(const SculptConfig& cfg)
    : mFalloff(cfg.falloff), mIso(cfg.iso), mMode(cfg.placement) {
    double ratio = 0;  // R_k / D_k when calibrated
    // The shipped settings' calibration is compiled in (CalibrationTable.h): no start-up cost.
    const TabulatedCalibration* table =
        cfg.manualSupport
            ? nullptr
            : findTabulatedCalibration(mMode, cfg.falloff, cfg.spacingOverDiameter, cfg.iso);
    if (table) {
        mReport = table->report;
        ratio = table->report.supportOverDiameter;
        mCalibrated = true;
    } else if (!cfg.manualSupport) {
        const CalibrationResult cal =
            calibrateSupport(mMode, mFalloff, cfg.spacingOverDiameter, cfg.iso);
        mReport = cal.report;
        ratio = cal.report.supportOverDiameter;
        mCalibrated = true;
    }
    for (int k = 1; k <= kLevelCount; ++k) {
        ToolLevel& l = mLevels[k - 1];
        l.level = k;
        l.diameterMm = cfg.d4Mm * std::pow(cfg.growth, k - kReferenceLevel);
        l.spacingMm = cfg.spacingOverDiameter * l.diameterMm;
        if (cfg.manualSupport) {
            l.supportMm = cfg.manualSupport->r4Mm * cfg.manualSupport->scale[k - 1];
        } else {
            l.supportMm = ratio * l.diameterMm;
        }
    }
    for (ToolLevel& l : mLevels)
        l.scale = l.supportMm / mLevels[kReferenceLevel - 1].supportMm;

    // With manual support radii R/D differs per level, and so does the coverage table; the
    // free placement mode uses the reference level's table for all levels in that case.
    const ToolLevel& ref = mLevels[kReferenceLevel - 1];
    if (table) {
        mCoverage.assign(table->coverage.begin(), table->coverage.end());
        mWall = table->wall;
        return;
    }
    // Calibrated: R/D itself (as the table has it), not R_4 / D_4 recomputed from it.
    const double supportOverDiameter = mCalibrated ? ratio : ref.supportMm / ref.diameterMm;
    mCoverage = strokeCoverageTable(mMode, mFalloff, cfg.spacingOverDiameter, supportOverDiameter);
    mWall = core::strokeWallValue(mMode, mFalloff, cfg.spacingOverDiameter, supportOverDiameter,
                                  mCoverage);
}

const ToolLevel& ToolLevels::level(int k) const {
    if (k < 1 || k > kLevelCount)
        throw std::out_of_range("tool level " + std::to_string(k) + " outside 1..7");
    return mLevels[k - 1];
}

double ToolLevels::strokeCoverage(double lateral) const {
    const double x = std::clamp(lateral, 0.0, 1.0) * double(mCoverage.size() - 1);
    const size_t i0 = std::min(size_t(x), mCoverage.size() - 2);
    const double f = x - double(i0);
    return mCoverage[i0] * (1 - f) + mCoverage[i0 + 1] * f;
}

}  // namespace vsculpt::core
