// Knot-division extraction (seed 000 section 5.3 (3), 節点分割抽出法): chooses a few knots on a
// densely sampled curve so that a spline through them keeps the intended oscillations and drops
// the small bumps that joining overdrawn strokes leaves behind.
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <cstddef>
#include <vector>

namespace vsculpt::sketch {

struct KnotDivisionParams {
    /// A point is kept only where the curve leaves its chord by more than epsilon * chord length
    /// (Kondo's h/L rule). The seed gives no value; 0.03.
    double epsilon = 0.03;
};

/// Indices of the kept points, increasing, always including the first and last. On an interval
/// whose largest deviation h from the chord satisfies h / L <= epsilon all interior points are
/// dropped. Otherwise the interval is split, keeping the split point, at (a) the first point
/// where the curve crosses the chord (significant on both sides), else (b) when it has an
/// inflection, the smallest interior local minimum of the distance to the chord, else (c) the
/// farthest point (Kondo). When `closed` the loop is first split at the point farthest from
/// point 0. Throws std::invalid_argument for non-finite points or epsilon <= 0.
std::vector<std::size_t> knotDivision(const Polyline2& curve, bool closed,
                                      const KnotDivisionParams& params = {});

}  // namespace vsculpt::sketch
