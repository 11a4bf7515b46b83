#include "vsculpt/sketch/Polyline.h"

#include <glm/geometric.hpp>

namespace vsculpt::sketch {

double signedArea(const Polyline2& polygon) {
    double twiceArea = 0.0;
    const std::size_t n = polygon.size();
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2& a = polygon[i];
        const glm::dvec2& b = polygon[(i + 1) % n];
        twiceArea += a.x * b.y - b.x * a.y;
    }
    return 0.5 * twiceArea;
}

glm::dvec2 areaCentroid(const Polyline2& polygon) {
    glm::dvec2 sum(0.0);
    double twiceArea = 0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const glm::dvec2 p = polygon[i], q = polygon[(i + 1) % polygon.size()];
        const double c = p.x * q.y - q.x * p.y;
        twiceArea += c;
        sum += (p + q) * c;
    }
    return sum / (3.0 * twiceArea);
}

namespace {
template <typename Points>
double polylineLength(const Points& line, bool closed) {
    double sum = 0.0;
    for (std::size_t i = 1; i < line.size(); ++i)
        sum += glm::distance(line[i - 1], line[i]);
    if (closed && line.size() > 1) sum += glm::distance(line.back(), line.front());
    return sum;
}
}  // namespace

double length(const Polyline2& line, bool closed) {
    return polylineLength(line, closed);
}
double length(const Polyline3& line, bool closed) {
    return polylineLength(line, closed);
}

}  // namespace vsculpt::sketch
