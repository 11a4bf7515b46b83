#include "vsculpt/sketch/Prism.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

double cross(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

// Closed-segment intersection test with exact orientation signs of double inputs (good enough
// for sketch input; collinear overlaps count as touching).
bool segmentsTouch(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                   const glm::dvec2& d) {
    auto orient = [](const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r) {
        const double v = cross(q - p, r - p);
        return (v > 0) - (v < 0);
    };
    auto onSegment = [](const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r) {
        return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) &&
               std::min(p.y, q.y) <= r.y && r.y <= std::max(p.y, q.y);
    };
    const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
              o4 = orient(c, d, b);
    if (o1 != o2 && o3 != o4) return true;
    if (o1 == 0 && onSegment(a, b, c)) return true;
    if (o2 == 0 && onSegment(a, b, d)) return true;
    if (o3 == 0 && onSegment(c, d, a)) return true;
    if (o4 == 0 && onSegment(c, d, b)) return true;
    return false;
}

// True when (u, v, w) → world is a reflection, so outward faces built in (u, v, w) must be
// reversed.
bool mirrored(Axis axis) {
    return axis == Axis::Y;
}

}  // namespace

glm::dvec3 sectionToWorld(Axis axis, const glm::dvec2& uv, double w) {
    switch (axis) {
        case Axis::X:
            return {w, uv.x, uv.y};
        case Axis::Y:
            return {uv.x, w, uv.y};
        case Axis::Z:
            return {uv.x, uv.y, w};
    }
    return {};
}

glm::dvec2 worldToSection(Axis axis, const glm::dvec3& p) {
    switch (axis) {
        case Axis::X:
            return {p.y, p.z};
        case Axis::Y:
            return {p.x, p.z};
        case Axis::Z:
            return {p.x, p.y};
    }
    return {};
}

void requireSimplePolygon(const Polyline2& polygon, const char* what) {
    const std::size_t n = polygon.size();
    if (n < 3)
        throw std::invalid_argument(
            std::string(what) + ": a polygon needs at least 3 points, got " + std::to_string(n));
    for (const auto& p : polygon)
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument(std::string(what) + ": non-finite coordinate");
    if (signedArea(polygon) == 0.0)
        throw std::invalid_argument(std::string(what) + ": the polygon has zero area");
    for (std::size_t i = 0; i < n; ++i) {
        if (polygon[i] == polygon[(i + 1) % n])
            throw std::invalid_argument(std::string(what) + ": repeated point " +
                                        std::to_string(i));
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
            if (segmentsTouch(polygon[i], polygon[i + 1], polygon[j], polygon[(j + 1) % n]))
                throw std::invalid_argument(std::string(what) + ": edges " + std::to_string(i) +
                                            " and " + std::to_string(j) + " intersect");
        }
    }
}

PolyMesh sweepPrism(const Polyline2& section, Axis axis, double from, double to) {
    requireSimplePolygon(section, "sweepPrism");
    if (!std::isfinite(from) || !std::isfinite(to) || !(from < to))
        throw std::invalid_argument("sweepPrism: need finite from < to");
    Polyline2 ring = section;
    if (signedArea(ring) < 0) std::reverse(ring.begin(), ring.end());
    const int n = static_cast<int>(ring.size());

    PolyMesh prism;
    for (double w : {from, to})
        for (const auto& p : ring)
            prism.vertices.push_back(sectionToWorld(axis, p, w));
    // In (u, v, w): the bottom cap looks down −w, so it runs clockwise in (u, v).
    std::vector<int> bottom, top;
    for (int i = 0; i < n; ++i) {
        bottom.push_back(n - 1 - i);
        top.push_back(n + i);
    }
    prism.faces.push_back(bottom);
    prism.faces.push_back(top);
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        prism.faces.push_back({i, j, n + j, n + i});
    }
    if (mirrored(axis))
        for (auto& face : prism.faces)
            std::reverse(face.begin(), face.end());
    return prism;
}

}  // namespace vsculpt::sketch
