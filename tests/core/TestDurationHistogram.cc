// SPDX-License-Identifier: MIT
#include "vsculpt/core/DurationHistogram.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using vsculpt::core::DurationHistogram;

namespace {

double exactQuantile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

}  // namespace

TEST(DurationHistogram, QuantilesMatchTheSortedSamplesWithinHalfABin) {
    std::mt19937 rng(7);
    // Frame-like times (lognormal around 1 ms) with a tail of long ones, over 6 decades.
    std::lognormal_distribution<double> body(0.0, 0.6);
    std::uniform_real_distribution<double> tail(std::log(0.01), std::log(5000.0));
    std::vector<double> samples;
    DurationHistogram h;
    for (int i = 0; i < 100000; ++i) {
        const double ms = i % 50 == 0 ? std::exp(tail(rng)) : body(rng);
        samples.push_back(ms);
        h.add(ms);
    }
    ASSERT_EQ(h.count(), samples.size());
    for (double q : {0.0, 0.01, 0.1, 0.5, 0.9, 0.99, 0.999, 1.0}) {
        const double exact = exactQuantile(samples, q);
        EXPECT_NEAR(h.quantile(q) / exact, 1.0, 0.005) << "q " << q << " exact " << exact;
    }
    EXPECT_EQ(h.min(), *std::min_element(samples.begin(), samples.end()));
    EXPECT_EQ(h.max(), *std::max_element(samples.begin(), samples.end()));
}

TEST(DurationHistogram, EmptyAndOutOfRangeDurations) {
    DurationHistogram h;
    EXPECT_EQ(h.count(), 0u);
    EXPECT_EQ(h.quantile(0.5), 0.0);
    h.add(-3);
    h.add(std::numeric_limits<double>::quiet_NaN());
    h.add(5e9);  // beyond the last bin: counted there, max exact
    EXPECT_EQ(h.count(), 3u);
    EXPECT_EQ(h.min(), 0.0);
    EXPECT_EQ(h.max(), 5e9);
    EXPECT_EQ(h.quantile(0.0), 0.0);
    EXPECT_EQ(h.quantile(1.0), 5e9);
    // The middle of three, a clamped negative: durations under 1 µs come back within 1 µs.
    EXPECT_NEAR(h.quantile(0.5), 0.0, 1.1e-3);
}

TEST(DurationHistogram, OneValueRepeatedIsReportedAsThatValue) {
    DurationHistogram h;
    for (int i = 0; i < 1000; ++i)
        h.add(11.1);
    for (double q : {0.0, 0.5, 0.99, 1.0})
        EXPECT_DOUBLE_EQ(h.quantile(q), 11.1) << q;  // clamped to [min, max]
}
