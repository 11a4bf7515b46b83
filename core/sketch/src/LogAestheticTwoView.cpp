#include "vsculpt/sketch/LogAestheticTwoView.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

// A function value(key) sampled at strictly increasing keys.
struct MonotoneTable {
    std::vector<double> key, value;
};

MonotoneTable tableOf(const Polyline2& stroke, bool keyIsX, const char* name) {
    if (stroke.size() < 3)
        throw std::invalid_argument(std::string("combineTwoViews: ") + name +
                                    " stroke needs at least 3 points");
    MonotoneTable t;
    for (const glm::dvec2& p : stroke) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument(std::string("combineTwoViews: ") + name +
                                        " stroke has a non-finite coordinate");
        t.key.push_back(keyIsX ? p.x : p.y);
        t.value.push_back(keyIsX ? p.y : p.x);
    }
    const bool increasing = t.key[1] > t.key[0];
    for (std::size_t i = 1; i < t.key.size(); ++i) {
        if (increasing ? !(t.key[i] > t.key[i - 1]) : !(t.key[i] < t.key[i - 1]))
            throw std::invalid_argument(std::string("combineTwoViews: ") + name +
                                        " stroke is not strictly monotone in Y at point " +
                                        std::to_string(i));
    }
    if (!increasing) {
        std::reverse(t.key.begin(), t.key.end());
        std::reverse(t.value.begin(), t.value.end());
    }
    return t;
}

// Derivative at sample i from the parabola through i−1, i, i+1 (one-sided at the ends).
double slopeAt(const MonotoneTable& t, std::size_t i) {
    const std::size_t n = t.key.size();
    const std::size_t a = i == 0 ? 0 : (i + 1 == n ? n - 3 : i - 1);
    const double x0 = t.key[a], x1 = t.key[a + 1], x2 = t.key[a + 2];
    const double y0 = t.value[a], y1 = t.value[a + 1], y2 = t.value[a + 2];
    const double x = t.key[i];
    return y0 * (2 * x - x1 - x2) / ((x0 - x1) * (x0 - x2)) +
           y1 * (2 * x - x0 - x2) / ((x1 - x0) * (x1 - x2)) +
           y2 * (2 * x - x0 - x1) / ((x2 - x0) * (x2 - x1));
}

double interpolate(const MonotoneTable& t, double key) {
    const auto it = std::upper_bound(t.key.begin(), t.key.end(), key);
    std::size_t i = std::size_t(
        std::clamp<std::ptrdiff_t>(it - t.key.begin(), 1, std::ptrdiff_t(t.key.size()) - 1));
    const double x0 = t.key[i - 1], x1 = t.key[i], h = x1 - x0;
    const double u = (key - x0) / h;
    const double h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u);
    const double h01 = u * u * (3 - 2 * u), h11 = u * u * (u - 1);
    return h00 * t.value[i - 1] + h10 * h * slopeAt(t, i - 1) + h01 * t.value[i] +
           h11 * h * slopeAt(t, i);
}

}  // namespace

Polyline3 combineTwoViews(const Polyline2& top, const Polyline2& side) {
    const MonotoneTable topTable = tableOf(top, false, "top");    // key Y = .y, value X
    const MonotoneTable sideTable = tableOf(side, true, "side");  // key Y = .x, value Z
    const double lo = std::max(topTable.key.front(), sideTable.key.front());
    const double hi = std::min(topTable.key.back(), sideTable.key.back());
    if (!(hi > lo))
        throw std::invalid_argument("combineTwoViews: the Y ranges of the strokes do not overlap");
    Polyline3 out;
    auto add = [&](double x, double y) { out.push_back({x, y, interpolate(sideTable, y)}); };
    const bool increasing = top[1].y > top[0].y;
    const double first = increasing ? lo : hi, last = increasing ? hi : lo;
    auto inside = [&](double y) { return y > lo && y < hi; };
    add(interpolate(topTable, first), first);
    for (const glm::dvec2& p : top)
        if (inside(p.y)) add(p.x, p.y);
    add(interpolate(topTable, last), last);
    return out;
}

Polyline2 projectTopView(const Polyline3& curve) {
    Polyline2 out;
    for (const glm::dvec3& p : curve)
        out.push_back({p.x, p.y});
    return out;
}

Polyline2 projectSideView(const Polyline3& curve) {
    Polyline2 out;
    for (const glm::dvec3& p : curve)
        out.push_back({p.y, p.z});
    return out;
}

double maxDeviation(const Polyline2& stroke, const Polyline2& reference) {
    if (stroke.empty() || reference.size() < 2)
        throw std::invalid_argument(
            "maxDeviation: need a non-empty stroke and at least 2 reference points");
    double worst = 0.0;
    for (const glm::dvec2& p : stroke) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i = 1; i < reference.size(); ++i) {
            const glm::dvec2 a = reference[i - 1], d = reference[i] - a;
            const double len2 = glm::dot(d, d);
            const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
            best = std::min(best, glm::distance(p, a + t * d));
        }
        worst = std::max(worst, best);
    }
    if (!std::isfinite(worst)) throw std::invalid_argument("maxDeviation: non-finite coordinates");
    return worst;
}

}  // namespace vsculpt::sketch
