#include "vsculpt/sketch/LineMixing.h"

#include "CleanupGeometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vsculpt::sketch {

namespace {

glm::dvec2 direction(const Segment2& s, const char* what) {
    const glm::dvec2 d = s.b - s.a;
    const double len = glm::length(d);
    if (!(len > 0.0) || !detail::finite(s.a) || !detail::finite(s.b))
        throw std::invalid_argument(std::string(what) + ": degenerate or non-finite segment");
    return d / len;
}

glm::dvec2 midpoint(const Segment2& s) {
    return 0.5 * (s.a + s.b);
}

}  // namespace

Segment2 fitSegment(const Polyline2& points) {
    detail::requireFinite(points, "fitSegment");
    if (points.size() < 2) throw std::invalid_argument("fitSegment: need at least 2 points");
    glm::dvec2 c{0.0};
    for (const glm::dvec2& p : points)
        c += p;
    c /= double(points.size());
    double sxx = 0.0, syy = 0.0, sxy = 0.0;
    for (const glm::dvec2& p : points) {
        const glm::dvec2 d = p - c;
        sxx += d.x * d.x;
        syy += d.y * d.y;
        sxy += d.x * d.y;
    }
    if (sxx + syy <= 0.0) throw std::invalid_argument("fitSegment: all points coincide");
    // Principal axis of the 2x2 scatter matrix in closed form.
    const double theta = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    glm::dvec2 dir{std::cos(theta), std::sin(theta)};
    if (glm::dot(points.back() - points.front(), dir) < 0.0) dir = -dir;
    double lo = 0.0, hi = 0.0;
    for (const glm::dvec2& p : points) {
        const double t = glm::dot(p - c, dir);
        lo = std::min(lo, t);
        hi = std::max(hi, t);
    }
    return {c + lo * dir, c + hi * dir};
}

double angleBetween(const Segment2& s, const Segment2& t) {
    const double c = std::abs(glm::dot(direction(s, "angleBetween"), direction(t, "angleBetween")));
    return std::acos(std::min(1.0, c));
}

bool isSameLine(const Segment2& s, const Segment2& t, const LineMixParams& params) {
    if (angleBetween(s, t) >= params.maxAngle) return false;
    const double d1 = detail::project({s.a, s.b}, midpoint(t)).distance;
    const double d2 = detail::project({t.a, t.b}, midpoint(s)).distance;
    return std::min(d1, d2) <= params.maxDistance;
}

Segment2 mixSegments(const Segment2& older, const Segment2& newer, const LineMixParams& params) {
    if (!(params.angleWeight >= 0.0 && params.angleWeight <= 1.0 && params.offsetWeight >= 0.0 &&
          params.offsetWeight <= 1.0))
        throw std::invalid_argument("mixSegments: weights must lie in [0, 1]");
    const glm::dvec2 u = direction(older, "mixSegments");
    glm::dvec2 v = direction(newer, "mixSegments");
    if (glm::dot(u, v) < 0.0) v = -v;  // drawing direction carries no meaning for a line
    const double delta = std::atan2(detail::cross(u, v), glm::dot(u, v));  // in [-pi/2, pi/2]
    const double theta = std::atan2(u.y, u.x) + params.angleWeight * delta;
    const glm::dvec2 dir{std::cos(theta), std::sin(theta)};

    const glm::dvec2 m = midpoint(newer);
    const glm::dvec2 onOlder = older.a + glm::dot(m - older.a, u) * u;
    const glm::dvec2 anchor = onOlder + params.offsetWeight * (m - onOlder);
    double lo = INFINITY, hi = -INFINITY;
    for (const glm::dvec2& p : {older.a, older.b, newer.a, newer.b}) {
        const double t = glm::dot(p - anchor, dir);
        lo = std::min(lo, t);
        hi = std::max(hi, t);
    }
    return {anchor + lo * dir, anchor + hi * dir};
}

}  // namespace vsculpt::sketch
