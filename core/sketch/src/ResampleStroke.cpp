#include "vsculpt/sketch/ResampleStroke.h"

#include "CleanupGeometry.h"

#include <cmath>
#include <stdexcept>

namespace vsculpt::sketch {

namespace {

void requireSpacing(double spacing) {
    if (!(std::isfinite(spacing) && spacing > 0.0))
        throw std::invalid_argument("resampleByArcLength: spacing must be positive and finite");
}

StrokeSample lerp(const StrokeSample& a, const StrokeSample& b, double t) {
    return {a.position + t * (b.position - a.position), a.time + t * (b.time - a.time),
            a.pressure + t * (b.pressure - a.pressure)};
}

}  // namespace

Stroke resampleByArcLength(const Stroke& stroke, double spacing) {
    validateStroke(stroke);
    requireSpacing(spacing);
    const auto& in = stroke.samples;
    Stroke out;
    out.hasPressure = stroke.hasPressure;
    out.samples.push_back(in.front());
    // Distance still to travel from the last emitted sample; walking input segments keeps the
    // output exactly `spacing` apart along the input path.
    double next = spacing;
    double travelled = 0.0;
    for (std::size_t i = 0; i + 1 < in.size(); ++i) {
        const double segLen = glm::distance(in[i].position, in[i + 1].position);
        if (segLen <= 0.0) continue;
        while (travelled + segLen >= next) {
            const double t = (next - travelled) / segLen;
            out.samples.push_back(lerp(in[i], in[i + 1], t));
            next += spacing;
        }
        travelled += segLen;
    }
    if (travelled > 0.0) {
        // The last emitted sample may coincide with the end (length a multiple of spacing).
        if (glm::distance(out.samples.back().position, in.back().position) > 1e-9 * spacing)
            out.samples.push_back(in.back());
        else
            out.samples.back() = in.back();
    }
    return out;
}

Polyline2 resampleByArcLength(const Polyline2& line, double spacing) {
    if (line.empty()) throw std::invalid_argument("resampleByArcLength: empty polyline");
    detail::requireFinite(line, "resampleByArcLength");
    return strokePositions(resampleByArcLength(makeStroke(line), spacing));
}

}  // namespace vsculpt::sketch
