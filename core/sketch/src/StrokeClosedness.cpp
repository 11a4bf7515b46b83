#include "vsculpt/sketch/StrokeClosedness.h"

#include "CleanupGeometry.h"

#include <stdexcept>

namespace vsculpt::sketch {

namespace {

// Points of `line` whose arc length from the start is at most `upTo` (the prefix as a polyline,
// cut exactly at `upTo`).
Polyline2 prefix(const Polyline2& line, double upTo) {
    Polyline2 out{line.front()};
    double s = 0.0;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const double seg = glm::distance(line[i], line[i + 1]);
        if (s + seg >= upTo) {
            const double t = seg > 0.0 ? (upTo - s) / seg : 0.0;
            out.push_back(line[i] + t * (line[i + 1] - line[i]));
            return out;
        }
        out.push_back(line[i + 1]);
        s += seg;
    }
    return out;
}

}  // namespace

bool isClosedStroke(const Polyline2& line, const ClosednessParams& params) {
    detail::requireFinite(line, "isClosedStroke");
    if (!(params.maxGapRatio > 0.0 && params.maxGapRatio <= 1.0 && params.endRegionRatio > 0.0 &&
          params.endRegionRatio <= 1.0))
        throw std::invalid_argument("isClosedStroke: ratios must lie in (0, 1]");
    if (line.size() < 3) return false;
    const double total = length(line, false);
    if (total <= 0.0) return false;
    const double maxGap = params.maxGapRatio * total;
    if (glm::distance(line.front(), line.back()) <= maxGap) return true;
    const double region = params.endRegionRatio * total;
    if (detail::project(prefix(line, region), line.back()).distance <= maxGap) return true;
    const Polyline2 reversed(line.rbegin(), line.rend());
    return detail::project(prefix(reversed, region), line.front()).distance <= maxGap;
}

bool isClosedStroke(const Stroke& stroke, const ClosednessParams& params) {
    validateStroke(stroke);
    return isClosedStroke(strokePositions(stroke), params);
}

}  // namespace vsculpt::sketch
