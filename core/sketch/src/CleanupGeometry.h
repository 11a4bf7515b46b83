// Private helpers shared by the stroke and clean-up sources.
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch::detail {

inline bool finite(const glm::dvec2& p) {
    return std::isfinite(p.x) && std::isfinite(p.y);
}

inline void requireFinite(const Polyline2& line, const char* what) {
    for (const glm::dvec2& p : line)
        if (!finite(p)) throw std::invalid_argument(std::string(what) + ": non-finite point");
}

inline double cross(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

/// Closest point on a polyline: arc-length parameter from the start, the point and distance.
struct Projection {
    double s = 0.0;
    glm::dvec2 point{0.0};
    double distance = 0.0;
    bool atStart = false;  // the closest point is the first point of the polyline
    bool atEnd = false;    // ... the last point
};

inline Projection project(const Polyline2& line, const glm::dvec2& p) {
    Projection best;
    best.distance = std::numeric_limits<double>::infinity();
    double s0 = 0.0;
    if (line.size() == 1) {
        best.point = line[0];
        best.distance = glm::distance(p, line[0]);
        best.atStart = best.atEnd = true;
        return best;
    }
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const glm::dvec2 a = line[i], d = line[i + 1] - a;
        const double len2 = glm::dot(d, d);
        const double len = std::sqrt(len2);
        double t = len2 > 0.0 ? glm::dot(p - a, d) / len2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        const glm::dvec2 q = a + t * d;
        const double dist = glm::distance(p, q);
        if (dist < best.distance) {
            best.distance = dist;
            best.point = q;
            best.s = s0 + t * len;
            best.atStart = (i == 0 && t == 0.0);
            best.atEnd = (i + 2 == line.size() && t == 1.0);
        }
        s0 += len;
    }
    return best;
}

}  // namespace vsculpt::sketch::detail
