// SPDX-License-Identifier: MIT
#include "vsculpt/core/DurationHistogram.h"

#include <algorithm>
#include <cmath>

namespace vsculpt::core {

namespace {

constexpr double kLowestMs = 1e-3;  // 1 µs
constexpr double kHighestMs = 1e6;  // 1000 s
constexpr double kRatio = 1.01;     // bin width: 1 %
const double kLogRatio = std::log(kRatio);
const size_t kBins = size_t(std::ceil(std::log(kHighestMs / kLowestMs) / kLogRatio)) + 1;

}  // namespace

DurationHistogram::DurationHistogram() : mBins(kBins, 0) {}

void DurationHistogram::add(double ms) {
    if (!(ms > 0)) ms = 0;  // NaN too
    size_t bin = 0;
    if (ms > kLowestMs) bin = std::min(kBins - 1, size_t(std::log(ms / kLowestMs) / kLogRatio));
    ++mBins[bin];
    mMin = mCount ? std::min(mMin, ms) : ms;
    mMax = mCount ? std::max(mMax, ms) : ms;
    ++mCount;
}

double DurationHistogram::quantile(double q) const {
    if (mCount == 0) return 0;
    const size_t rank = std::min(mCount - 1, size_t(std::clamp(q, 0.0, 1.0) * double(mCount)));
    // The extremes are known exactly.
    if (rank == 0) return mMin;
    if (rank == mCount - 1) return mMax;
    size_t seen = 0;
    for (size_t b = 0; b < kBins; ++b) {
        seen += mBins[b];
        if (seen > rank)
            return std::clamp(kLowestMs * std::pow(kRatio, double(b) + 0.5), mMin, mMax);
    }
    return mMax;
}

}  // namespace vsculpt::core
