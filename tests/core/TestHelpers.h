// SPDX-License-Identifier: MIT
/// @file TestHelpers.h
/// @brief Shared helpers for the core tests: configs and tube-radius measurement through the
/// real field evaluator.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Sculpture.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace vsculpt::test {

using core::Vec3;

inline core::SculptConfig emptyConfig(core::PlacementMode mode) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 0;
    cfg.placement = mode;
    return cfg;
}

/// A straight tool path from a to b sampled every `step` mm (both ends included).
inline std::vector<Vec3> linePath(const Vec3& a, const Vec3& b, double step) {
    const int n = std::max(1, int(std::ceil(glm::length(b - a) / step)));
    std::vector<Vec3> path;
    for (int i = 0; i <= n; ++i)
        path.push_back(a + (b - a) * (double(i) / n));
    return path;
}

struct Radius {
    double mean = 0, min = 0, max = 0;
};

/// Iso-surface radius around the axis through `center` along `dir`, from rays at `angles`
/// angles and `offsets` axial offsets spread over +-axialSpan: the first crossing of f = 0
/// going outward (0 if the axis point itself is outside).
/// With `hole` set, measures an empty tunnel instead: the first crossing into material.
inline Radius tubeRadius(const core::Sculpture& s, const Vec3& center, const Vec3& dir,
                         double axialSpan, double maxRadius, int angles = 16, int offsets = 5,
                         bool hole = false) {
    core::FieldProbe probe(s);
    const Vec3 d = glm::normalize(dir);
    const Vec3 helper = std::abs(d.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    const Vec3 e1 = glm::normalize(glm::cross(d, helper));
    const Vec3 e2 = glm::cross(d, e1);
    Radius out;
    out.min = 1e300;
    double sum = 0;
    int n = 0;
    for (int j = 0; j < offsets; ++j) {
        const double t = offsets == 1 ? 0 : axialSpan * (2.0 * j / (offsets - 1) - 1);
        const Vec3 q = center + d * t;
        for (int i = 0; i < angles; ++i) {
            const double th = 2 * std::numbers::pi * (i + 0.37) / angles;
            const Vec3 e = std::cos(th) * e1 + std::sin(th) * e2;
            double r = 0;
            auto same = [&](double t) { return (probe.value(q + t * e) > 0) != hole; };
            if (same(0)) {
                const double step = maxRadius / 200;
                double lo = 0, hi = step;
                while (hi < maxRadius && same(hi)) {
                    lo = hi;
                    hi += step;
                }
                for (int it = 0; it < 50; ++it) {
                    const double mid = 0.5 * (lo + hi);
                    (same(mid) ? lo : hi) = mid;
                }
                r = 0.5 * (lo + hi);
            }
            sum += r;
            ++n;
            out.min = std::min(out.min, r);
            out.max = std::max(out.max, r);
        }
    }
    out.mean = sum / n;
    return out;
}

}  // namespace vsculpt::test
