#include "vsculpt/sketch/KnotDivision.h"

#include "CleanupGeometry.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

namespace vsculpt::sketch {

namespace {

// Turns below this (rad) are straight as far as inflections go: spline samples on a straight
// stretch wobble in sign at rounding level.
constexpr double kMinTurn = 1e-6;

// Where to split c[i0..i1], or nullopt to keep no interior point. `d` is scratch space.
std::optional<std::size_t> splitPoint(const Polyline2& c, std::size_t i0, std::size_t i1,
                                      double eps, std::vector<double>& d) {
    if (i1 - i0 < 2) return std::nullopt;
    const glm::dvec2 p1 = c[i0], p2 = c[i1];
    const double len = glm::distance(p1, p2);
    if (len <= 0.0) {
        // Interval returns to its start: split at the farthest point so both halves have chords.
        std::size_t far = i0 + 1;
        for (std::size_t k = i0 + 1; k < i1; ++k)
            if (glm::distance(c[k], p1) > glm::distance(c[far], p1)) far = k;
        if (glm::distance(c[far], p1) > 0.0) return far;
        return std::nullopt;
    }
    const glm::dvec2 dir = (p2 - p1) / len;
    d.assign(i1 - i0 + 1, 0.0);
    double posMax = 0.0, negMax = 0.0;
    std::size_t farthest = i0 + 1;
    for (std::size_t k = i0 + 1; k < i1; ++k) {
        d[k - i0] = detail::cross(dir, c[k] - p1);
        posMax = std::max(posMax, d[k - i0]);
        negMax = std::max(negMax, -d[k - i0]);
        if (std::abs(d[k - i0]) > std::abs(d[farthest - i0])) farthest = k;
    }
    if (std::max(posMax, negMax) <= eps * len) return std::nullopt;  // straight enough

    // (a) The curve crosses its chord, clearly on both sides: split at the first crossing.
    if (posMax > eps * len && negMax > eps * len) {
        double firstSign = 0.0;
        for (std::size_t k = i0 + 1; k < i1; ++k) {
            const double v = d[k - i0];
            if (firstSign == 0.0) {
                if (v != 0.0) firstSign = v;
                continue;
            }
            if (v * firstSign <= 0.0)
                return (k - 1 > i0 && std::abs(d[k - 1 - i0]) < std::abs(v)) ? k - 1 : k;
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
        if (best != 0) return best;
    }
    // (c) Kondo's knot extraction: keep the farthest point, h / L > eps here.
    return farthest;
}

// Splits c[i0..i1] until every interval is straight enough. An explicit stack and one scratch
// buffer: recursion kept each level's distances alive, so a curve split near one end every
// time (a zigzag) needed memory quadratic in its length and a stack as deep as its points.
void divide(const Polyline2& c, std::size_t i0, std::size_t i1, double eps,
            std::vector<std::size_t>& keep) {
    std::vector<std::pair<std::size_t, std::size_t>> todo{{i0, i1}};
    std::vector<double> scratch;
    while (!todo.empty()) {
        const auto [a, b] = todo.back();
        todo.pop_back();
        const std::optional<std::size_t> k = splitPoint(c, a, b, eps, scratch);
        if (!k) continue;
        keep.push_back(*k);
        todo.push_back({*k, b});
        todo.push_back({a, *k});
    }
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
