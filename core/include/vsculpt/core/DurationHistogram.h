// SPDX-License-Identifier: MIT
/// @file DurationHistogram.h
/// @brief Quantiles of durations in fixed memory, for statistics kept over a whole session
/// (frame times, how far the mesh trails the edits): a headset session runs at 90 Hz for
/// hours, and keeping every sample would grow without bound.
///
/// Durations are counted in logarithmic bins 1 % wide from 1 µs to 1000 s (about 2 100 bins,
/// 17 KB); a quantile is the geometric middle of its bin, within 0.5 % of the exact sample.
/// Durations outside that span count in the first or last bin; min() and max() are exact.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vsculpt::core {

class DurationHistogram {
  public:
    DurationHistogram();

    /// Counts one duration, in milliseconds (negative and NaN count as 0).
    void add(double ms);
    size_t count() const { return mCount; }
    /// The q-quantile in milliseconds (q in [0, 1]): the sample of rank floor(q n) in sorted
    /// order, to within half a bin; 0 when empty.
    double quantile(double q) const;
    double min() const { return mCount ? mMin : 0; }
    double max() const { return mCount ? mMax : 0; }

  private:
    std::vector<uint64_t> mBins;
    size_t mCount = 0;
    double mMin = 0, mMax = 0;
};

}  // namespace vsculpt::core
