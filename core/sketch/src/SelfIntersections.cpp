#include "vsculpt/sketch/SelfIntersections.h"

#include "CleanupGeometry.h"

#include <algorithm>
#include <optional>

namespace vsculpt::sketch {

namespace {

struct Hit {
    double tA, tB;
};

// Segment-segment intersection of a0-a1 with b0-b1 (both non-degenerate).
std::optional<Hit> intersect(const glm::dvec2& a0, const glm::dvec2& a1, const glm::dvec2& b0,
                             const glm::dvec2& b1) {
    const glm::dvec2 r = a1 - a0, s = b1 - b0, q = b0 - a0;
    const double denom = detail::cross(r, s);
    const double scale = glm::length(r) * glm::length(s);
    if (std::abs(denom) <= 1e-12 * scale) {
        // Parallel: intersect only when collinear and overlapping.
        if (std::abs(detail::cross(q, r)) > 1e-12 * glm::dot(r, r)) return std::nullopt;
        const double rr = glm::dot(r, r);
        const double t0 = glm::dot(q, r) / rr, t1 = glm::dot(b1 - a0, r) / rr;
        const double lo = std::max(0.0, std::min(t0, t1)), hi = std::min(1.0, std::max(t0, t1));
        if (lo > hi) return std::nullopt;
        const glm::dvec2 p = a0 + lo * r;
        const double tb = glm::dot(p - b0, s) / glm::dot(s, s);
        return Hit{lo, std::clamp(tb, 0.0, 1.0)};
    }
    const double t = detail::cross(q, s) / denom;
    const double u = detail::cross(q, r) / denom;
    if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return std::nullopt;
    return Hit{t, u};
}

}  // namespace

std::vector<SelfIntersection> findSelfIntersections(const Polyline2& line, bool closed,
                                                    std::size_t maxCount) {
    detail::requireFinite(line, "findSelfIntersections");
    std::vector<SelfIntersection> out;
    const std::size_t n = line.size();
    if (n < 3 || maxCount == 0) return out;
    const std::size_t segs = closed ? n : n - 1;
    auto endA = [&](std::size_t i) { return line[i]; };
    auto endB = [&](std::size_t i) { return line[(i + 1) % n]; };
    std::vector<glm::dvec2> lo(segs), hi(segs);
    for (std::size_t i = 0; i < segs; ++i) {
        lo[i] = glm::min(endA(i), endB(i));
        hi[i] = glm::max(endA(i), endB(i));
    }
    for (std::size_t i = 0; i < segs; ++i) {
        if (endA(i) == endB(i)) continue;
        for (std::size_t j = i + 2; j < segs; ++j) {
            if (closed && i == 0 && j == segs - 1) continue;  // adjacent through the closure
            if (endA(j) == endB(j)) continue;
            if (hi[i].x < lo[j].x || hi[j].x < lo[i].x || hi[i].y < lo[j].y || hi[j].y < lo[i].y)
                continue;
            if (const auto hit = intersect(endA(i), endB(i), endA(j), endB(j))) {
                const glm::dvec2 p = endA(i) + hit->tA * (endB(i) - endA(i));
                out.push_back({i, j, hit->tA, hit->tB, p});
                if (out.size() >= maxCount) return out;
            }
        }
    }
    return out;
}

bool hasSelfIntersection(const Polyline2& line, bool closed) {
    return !findSelfIntersections(line, closed, 1).empty();
}

}  // namespace vsculpt::sketch
