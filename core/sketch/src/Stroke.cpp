#include "vsculpt/sketch/Stroke.h"

#include "CleanupGeometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

void validateStroke(const Stroke& stroke) {
    if (stroke.samples.empty()) throw std::invalid_argument("stroke has no samples");
    for (std::size_t i = 0; i < stroke.samples.size(); ++i) {
        const StrokeSample& s = stroke.samples[i];
        const std::string at = " at sample " + std::to_string(i);
        if (!detail::finite(s.position))
            throw std::invalid_argument("stroke: non-finite position" + at);
        if (std::abs(s.position.x) > kMaxStrokeCoordinate ||
            std::abs(s.position.y) > kMaxStrokeCoordinate)
            throw std::invalid_argument("stroke: position outside [-1e6, 1e6] mm" + at);
        if (!std::isfinite(s.time)) throw std::invalid_argument("stroke: non-finite time" + at);
        if (std::abs(s.time) > kMaxStrokeTime)
            throw std::invalid_argument("stroke: time outside [-1e10, 1e10] s" + at);
        if (i > 0 && s.time < stroke.samples[i - 1].time)
            throw std::invalid_argument("stroke: time goes backwards" + at);
        if (stroke.hasPressure && !(s.pressure >= 0.0 && s.pressure <= 1.0))
            throw std::invalid_argument("stroke: pressure outside [0, 1]" + at);
    }
}

Polyline2 strokePositions(const Stroke& stroke) {
    Polyline2 out;
    out.reserve(stroke.samples.size());
    for (const StrokeSample& s : stroke.samples)
        out.push_back(s.position);
    return out;
}

double strokeLength(const Stroke& stroke) {
    return length(strokePositions(stroke), false);
}

double peakPressure(const Stroke& stroke) {
    if (!stroke.hasPressure) return 0.0;
    double peak = 0.0;
    for (const StrokeSample& s : stroke.samples)
        peak = std::max(peak, s.pressure);
    return peak;
}

Stroke makeStroke(const Polyline2& points, double startTime, double dt) {
    Stroke stroke;
    stroke.samples.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        stroke.samples.push_back({points[i], startTime + dt * double(i), 1.0});
    return stroke;
}

}  // namespace vsculpt::sketch
