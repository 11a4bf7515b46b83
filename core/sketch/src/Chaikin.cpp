#include "vsculpt/sketch/Chaikin.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

bool finite(const glm::dvec2& p) {
    return std::isfinite(p.x) && std::isfinite(p.y);
}
bool finite(const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

template <class Points>
void checkPolygon(const Points& polygon, const char* what) {
    if (polygon.size() < 3)
        throw std::invalid_argument(std::string(what) +
                                    ": a closed polygon needs at least 3 points, got " +
                                    std::to_string(polygon.size()));
    for (const auto& p : polygon)
        if (!finite(p)) throw std::invalid_argument(std::string(what) + ": non-finite coordinate");
}

template <class Points>
Points chaikinImpl(const Points& polygon, int levels) {
    checkPolygon(polygon, "chaikin");
    // 2^20 times the input is already far beyond any drawable curve; refuse rather than
    // exhaust memory.
    if (levels < 0 || levels > 20)
        throw std::invalid_argument("chaikin: levels must be in [0, 20], got " +
                                    std::to_string(levels));
    Points current = polygon;
    for (int level = 0; level < levels; ++level) {
        const std::size_t n = current.size();
        Points next(2 * n);
        for (std::size_t i = 0; i < n; ++i) {
            const auto& a = current[i];
            const auto& b = current[(i + 1) % n];
            next[2 * i] = 0.75 * a + 0.25 * b;
            next[2 * i + 1] = 0.25 * a + 0.75 * b;
        }
        current = std::move(next);
    }
    return current;
}

}  // namespace

Polyline2 chaikin(const Polyline2& polygon, int levels) {
    return chaikinImpl(polygon, levels);
}
Polyline3 chaikin(const Polyline3& polygon, int levels) {
    return chaikinImpl(polygon, levels);
}

glm::dvec2 chaikinLimitPoint(const Polyline2& polygon, double u) {
    checkPolygon(polygon, "chaikinLimitPoint");
    if (!std::isfinite(u)) throw std::invalid_argument("chaikinLimitPoint: non-finite parameter");
    const int n = static_cast<int>(polygon.size());
    double span = std::floor(u);
    const double t = u - span;
    int i = static_cast<int>(std::fmod(span, double(n)));
    if (i < 0) i += n;
    const auto& p0 = polygon[i];
    const auto& p1 = polygon[(i + 1) % n];
    const auto& p2 = polygon[(i + 2) % n];
    return 0.5 * (1 - t) * (1 - t) * p0 + (0.5 + t - t * t) * p1 + 0.5 * t * t * p2;
}

Polyline2 chaikinLimit(const Polyline2& polygon, int samplesPerEdge) {
    checkPolygon(polygon, "chaikinLimit");
    if (samplesPerEdge < 1)
        throw std::invalid_argument("chaikinLimit: samplesPerEdge must be at least 1");
    const int n = static_cast<int>(polygon.size());
    Polyline2 out;
    out.reserve(std::size_t(n) * samplesPerEdge);
    for (int i = 0; i < n; ++i)
        for (int s = 0; s < samplesPerEdge; ++s)
            out.push_back(chaikinLimitPoint(polygon, i + double(s) / samplesPerEdge));
    return out;
}

}  // namespace vsculpt::sketch
