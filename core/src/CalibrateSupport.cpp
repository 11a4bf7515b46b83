// SPDX-License-Identifier: MIT
#include "vsculpt/core/CalibrateSupport.h"

#include "vsculpt/core/SweptVertices.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace vsculpt::core {

namespace {

constexpr int kAngles = 8;
constexpr int kOffsets = 4;

/// Skeleton positions of one straight stroke, long enough that its ends do not reach the
/// measured middle part, with everything expressed relative to the stroke's origin.
struct Stroke {
    Vec3 origin, dir, e1, e2;
    std::vector<Vec3> skeletons;
    std::vector<double> weights;
    std::vector<SweptVertex> middle;  // swept vertices near the middle (for the coverage table)
};

Stroke makeStroke(PlacementMode mode, double diameter, double spacing, double maxSupport,
                  const Vec3& origin, const Vec3& direction) {
    Stroke s;
    s.origin = origin;
    s.dir = glm::normalize(direction);
    const Vec3 helper = std::abs(s.dir.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    s.e1 = glm::normalize(glm::cross(s.dir, helper));
    s.e2 = glm::cross(s.dir, s.e1);
    const double window = 2 * spacing;  // axial half-extent of the measured part
    const double halfLength = window + maxSupport + diameter + 2 * spacing;
    const Vec3 a = origin - s.dir * halfLength, b = origin + s.dir * halfLength;
    for (const SweptVertex& v : sweptVertices(spacing, a, b, 0.5 * diameter)) {
        const Vec3 pos = Vec3(v.coord.x, v.coord.y, v.coord.z) * spacing;
        s.skeletons.push_back(pos);
        s.weights.push_back(strokeProfile(mode, v.lateralMm / (0.5 * diameter)));
        if (std::abs(glm::dot(pos - origin, s.dir)) <= window) s.middle.push_back(v);
    }
    return s;
}

double rawSum(const HermiteFalloff& F, const std::vector<Vec3>& skel, const std::vector<double>& w,
              double support, const Vec3& p) {
    double sum = 0;
    const double s2 = support * support;
    for (size_t i = 0; i < skel.size(); ++i) {
        const Vec3 d = p - skel[i];
        const double r2 = glm::dot(d, d);
        if (r2 < s2) sum += w[i] * F.value(std::sqrt(r2) / support);
    }
    return sum;
}

/// Radius of the iso-surface along the ray q + r e (r >= 0): the first crossing.
double isoRadius(const HermiteFalloff& F, double iso, const std::vector<Vec3>& skel,
                 const std::vector<double>& w, double support, const Vec3& q, const Vec3& e,
                 double step, double rMax) {
    auto g = [&](double r) { return rawSum(F, skel, w, support, q + r * e) - iso; };
    if (g(0) <= 0) return 0;
    double lo = 0, hi = step;
    while (g(hi) > 0) {
        lo = hi;
        hi += step;
        if (hi > rMax) return rMax;
    }
    for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (lo + hi);
        (g(mid) > 0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

TubeMeasurement measure(const HermiteFalloff& F, double iso, const Stroke& s, double diameter,
                        double spacing, double support) {
    // Only skeletons that can reach the measured part matter.
    const double reach = 2 * spacing + support + diameter;
    std::vector<Vec3> near;
    std::vector<double> nearW;
    for (size_t i = 0; i < s.skeletons.size(); ++i)
        if (std::abs(glm::dot(s.skeletons[i] - s.origin, s.dir)) <= reach) {
            near.push_back(s.skeletons[i]);
            nearW.push_back(s.weights[i]);
        }
    TubeMeasurement m;
    m.min = std::numeric_limits<double>::infinity();
    m.max = 0;
    double sum = 0;
    const double rMax = 0.5 * diameter + support;
    for (int j = 0; j < kOffsets; ++j) {
        const Vec3 q = s.origin + s.dir * (2 * spacing * j / kOffsets);
        for (int i = 0; i < kAngles; ++i) {
            const double th = 2 * std::numbers::pi * (i + 0.5 * (j % 2)) / kAngles;
            const Vec3 e = std::cos(th) * s.e1 + std::sin(th) * s.e2;
            const double r = isoRadius(F, iso, near, nearW, support, q, e, 0.125 * diameter, rMax);
            sum += r;
            m.min = std::min(m.min, r);
            m.max = std::max(m.max, r);
        }
    }
    m.mean = sum / (kAngles * kOffsets);
    return m;
}

}  // namespace

const std::vector<StrokeLine>& calibrationLines() {
    // Four lattice-special lines, then 60 directions spread evenly over the half sphere
    // (Fibonacci spiral) with origins from a Halton sequence: the average then stands for an
    // arbitrary stroke, not for the axis-aligned ones.
    static const std::vector<StrokeLine> lines = [] {
        std::vector<StrokeLine> l = {
            {Vec3(1, 0, 0), Vec3(0, 0, 0)},
            {Vec3(1, 0, 0), Vec3(0, 0.5, 0.5)},
            {Vec3(1, 1, 0), Vec3(0, 0, 0)},
            {Vec3(1, 1, 1), Vec3(0, 0, 0)},
        };
        auto halton = [](int i, int base) {
            double f = 1, r = 0;
            for (; i > 0; i /= base) {
                f /= base;
                r += f * (i % base);
            }
            return r;
        };
        const int n = 60;
        const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
        for (int i = 0; i < n; ++i) {
            const double z = 1 - (i + 0.5) / n;  // upper half sphere
            const double r = std::sqrt(1 - z * z);
            const Vec3 dir(r * std::cos(golden * i), r * std::sin(golden * i), z);
            l.push_back({dir, Vec3(halton(i + 1, 2), halton(i + 1, 3), halton(i + 1, 5))});
        }
        return l;
    }();
    return lines;
}

TubeMeasurement measureTube(PlacementMode mode, const HermiteFalloff& falloff, double iso,
                            double diameter, double spacing, double support, const Vec3& origin,
                            const Vec3& direction) {
    const Stroke s = makeStroke(mode, diameter, spacing, support, origin, direction);
    return measure(falloff, iso, s, diameter, spacing, support);
}

CalibrationResult calibrateSupport(PlacementMode mode, const HermiteFalloff& F, double sigma,
                                   double iso) {
    // Work at D = 1: everything else scales with D.
    const double D = 1.0, h = sigma * D, rho = 0.5 * D;
    const double loBound = 0.25 * D, hiBound = 8.0 * D;
    std::vector<Stroke> strokes;
    for (const StrokeLine& l : calibrationLines())
        strokes.push_back(makeStroke(mode, D, h, hiBound, l.originInSpacings * h, l.direction));

    auto meanRadius = [&](double R) {
        double sum = 0;
        for (const Stroke& s : strokes)
            sum += measure(F, iso, s, D, h, R).mean;
        return sum / strokes.size();
    };
    double lo = loBound, hi = hiBound;
    if (meanRadius(lo) > rho || meanRadius(hi) < rho)
        throw std::runtime_error("calibrateSupport: no support radius gives a tube of radius D/2");
    for (int i = 0; i < 36; ++i) {  // R to ~1e-10 D
        const double mid = 0.5 * (lo + hi);
        (meanRadius(mid) < rho ? lo : hi) = mid;
    }
    const double R = 0.5 * (lo + hi);

    CalibrationResult out;
    out.report.supportOverDiameter = R / D;
    out.report.directions = int(strokes.size());
    double total = 0;
    for (const Stroke& s : strokes) {
        const TubeMeasurement m = measure(F, iso, s, D, h, R);
        total += m.mean;
        out.report.worstDirectionError =
            std::max(out.report.worstDirectionError, std::abs(m.mean - rho) / rho);
        out.report.maxLocalDeviation =
            std::max({out.report.maxLocalDeviation, std::abs(m.min - rho) / rho,
                      std::abs(m.max - rho) / rho});
    }
    out.report.meanRadiusError = std::abs(total / strokes.size() - rho) / rho;

    return out;
}

std::vector<double> strokeCoverageTable(PlacementMode mode, const HermiteFalloff& F, double sigma,
                                        double supportOverDiameter) {
    const double D = 1.0, h = sigma * D, rho = 0.5 * D, R = supportOverDiameter * D;
    std::vector<Stroke> strokes;
    for (const StrokeLine& l : calibrationLines())
        strokes.push_back(makeStroke(mode, D, h, R, l.originInSpacings * h, l.direction));
    // Coverage: the fresh stroke's own field at its vertices, by lateral distance (hat-binned).
    constexpr int kNodes = 9;
    std::vector<double> acc(kNodes, 0), wsum(kNodes, 0);
    for (const Stroke& s : strokes) {
        for (const SweptVertex& v : s.middle) {
            const Vec3 pos = Vec3(v.coord.x, v.coord.y, v.coord.z) * h;
            const double T = rawSum(F, s.skeletons, s.weights, R, pos);
            const double x = std::min(v.lateralMm / rho, 1.0) * (kNodes - 1);
            const int i0 = std::min(int(x), kNodes - 2);
            const double f = x - i0;
            acc[i0] += (1 - f) * T;
            wsum[i0] += 1 - f;
            acc[i0 + 1] += f * T;
            wsum[i0 + 1] += f;
        }
    }
    std::vector<double> table(kNodes, 0.0);
    std::vector<int> known;
    for (int i = 0; i < kNodes; ++i) {
        if (wsum[i] > 1e-6) {
            table[i] = acc[i] / wsum[i];
            known.push_back(i);
        }
    }
    if (known.empty()) throw std::runtime_error("strokeCoverageTable: no stroke vertices sampled");
    for (int i = 0; i < kNodes; ++i) {  // fill gaps linearly, hold the ends
        if (wsum[i] > 1e-6) continue;
        int l = -1, r = -1;
        for (int k : known) {
            if (k < i) l = k;
            if (k > i && r < 0) r = k;
        }
        if (l < 0)
            table[i] = table[r];
        else if (r < 0)
            table[i] = table[l];
        else
            table[i] = table[l] + (table[r] - table[l]) * (i - l) / (r - l);
    }
    return table;
}

double strokeWallValue(PlacementMode mode, const HermiteFalloff& F, double sigma,
                       double supportOverDiameter, const std::vector<double>& coverage) {
    const double D = 1.0, h = sigma * D, rho = 0.5 * D, R = supportOverDiameter * D;
    auto cov = [&](double s) {
        const double x = std::clamp(s, 0.0, 1.0) * double(coverage.size() - 1);
        const size_t i0 = std::min(size_t(x), coverage.size() - 2);
        const double f = x - double(i0);
        return coverage[i0] * (1 - f) + coverage[i0 + 1] * f;
    };
    std::vector<Stroke> strokes;
    for (const StrokeLine& l : calibrationLines()) {
        Stroke s = makeStroke(mode, D, h, R, l.originInSpacings * h, l.direction);
        // Re-weight by the gain: weights that change the field by one unit along the path.
        for (size_t i = 0; i < s.skeletons.size(); ++i) {
            const double lateral =
                distanceToSegment(s.skeletons[i], s.origin - s.dir * 1e3, s.origin + s.dir * 1e3) /
                rho;
            s.weights[i] = strokeProfile(mode, lateral) / cov(lateral);
        }
        strokes.push_back(std::move(s));
    }
    // The level L of that unit-change field whose iso-surface lies, on average, at the tool's
    // surface: carving by (A - c) / L then puts the carved wall at D/2 in material of any
    // field value A (the same measurement as the support calibration).
    auto meanRadius = [&](double level) {
        double sum = 0;
        for (const Stroke& s : strokes)
            sum += measure(F, level, s, D, h, R).mean;
        return sum / double(strokes.size());
    };
    double lo = 1e-3, hi = 1.0;
    while (meanRadius(hi) > rho && hi < 64)
        hi *= 2;
    for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (lo + hi);
        (meanRadius(mid) > rho ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace vsculpt::core
