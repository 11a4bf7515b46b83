#include "vsculpt/sketch/KnotDivision.h"

#include "CleanupGeometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vsculpt::sketch {

namespace {

// Turns below this (rad) are straight as far as inflections go: spline samples on a straight
// stretch wobble in sign at rounding level.
constexpr double kMinTurn = 1e-6;

void divide(const Polyline2& c, std::size_t i0, std::size_t i1, double eps,
            std::vector<std::size_t>& keep) {
    if (i1 - i0 < 2) return;
    const glm::dvec2 p1 = c[i0], p2 = c[i1];
    const double len = glm::distance(p1, p2);
    const auto splitAt = [&](std::size_t k) {
        keep.push_back(k);
        divide(c, i0, k, eps, keep);
        divide(c, k, i1, eps, keep);
    };
    if (len <= 0.0) {
        // Interval returns to its start: split at the farthest point so both halves have chords.
        std::size_t far = i0 + 1;
        for (std::size_t k = i0 + 1; k < i1; ++k)
            if (glm::distance(c[k], p1) > glm::distance(c[far], p1)) far = k;
        if (glm::distance(c[far], p1) > 0.0) splitAt(far);
        return;
    }
    const glm::dvec2 dir = (p2 - p1) / len;
    std::vector<double> d(i1 - i0 + 1, 0.0);
    double posMax = 0.0, negMax = 0.0;
    std::size_t farthest = i0 + 1;
    for (std::size_t k = i0 + 1; k < i1; ++k) {
        d[k - i0] = detail::cross(dir, c[k] - p1);
        posMax = std::max(posMax, d[k - i0]);
        negMax = std::max(negMax, -d[k - i0]);
        if (std::abs(d[k - i0]) > std::abs(d[farthest - i0])) farthest = k;
    }
    if (std::max(posMax, negMax) <= eps * len) return;  // straight enough: drop interior points

    // (a) The curve crosses its chord, clearly on both sides: split at the first crossing.
    if (posMax > eps * len && negMax > eps * len) {
        double firstSign = 0.0;
        for (std::size_t k = i0 + 1; k < i1; ++k) {
            const double v = d[k - i0];
            if (firstSign == 0.0) {
                if (v != 0.0) firstSign = v;
                continue;
            }
            if (v * firstSign <= 0.0) {
                const std::size_t split =
                    (k - 1 > i0 && std::abs(d[k - 1 - i0]) < std::abs(v)) ? k - 1 : k;
                splitAt(split);
                return;
            }
        }
    }
    // (b) An inflection inside: split at the smallest interior local minimum of |d|.
    int turnSigns = 0;
    for (std::size_t k = i0 + 1; k < i1; ++k) {
        const glm::dvec2 a = c[k] - c[k - 1], b = c[k + 1] - c[k];
        const double la = glm::length(a), lb = glm::length(b);
        if (la <= 0.0 || lb <= 0.0) continue;
        const double turn = detail::cross(a, b) / (la * lb);
        if (turn > kMinTurn) turnSigns |= 1;
        if (turn < -kMinTurn) turnSigns |= 2;
    }
    if (turnSigns == 3) {
        std::size_t best = 0;
        for (std::size_t k = i0 + 1; k < i1; ++k) {
            const double v = std::abs(d[k - i0]);
            if (v < std::abs(d[k - 1 - i0]) && v <= std::abs(d[k + 1 - i0]) &&
                (best == 0 || v < std::abs(d[best - i0])))
                best = k;
        }
        if (best != 0) {
            splitAt(best);
            return;
        }
    }
    // (c) Kondo's knot extraction: keep the farthest point, h / L > eps here.
    splitAt(farthest);
}

}  // namespace

std::vector<std::size_t> knotDivision(const Polyline2& curve, bool closed,
                                      const KnotDivisionParams& params) {
    detail::requireFinite(curve, "knotDivision");
    if (!(params.epsilon > 0.0)) throw std::invalid_argument("knotDivision: epsilon must be > 0");
    std::vector<std::size_t> keep;
    if (curve.empty()) return keep;
    if (curve.size() == 1) return {0};
    if (!closed) {
        keep = {0, curve.size() - 1};
        divide(curve, 0, curve.size() - 1, params.epsilon, keep);
    } else {
        Polyline2 loop = curve;
        loop.push_back(curve.front());
        keep = {0};
        divide(loop, 0, loop.size() - 1, params.epsilon, keep);
    }
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
    return keep;
}

}  // namespace vsculpt::sketch
