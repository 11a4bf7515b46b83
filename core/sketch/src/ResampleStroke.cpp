#include "vsculpt/sketch/ResampleStroke.h"

#include "CleanupGeometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

void requireSpacing(double spacing) {
    if (!(std::isfinite(spacing) && spacing > 0.0))
        throw std::invalid_argument("resampleBySpacing: spacing must be positive and finite");
}

StrokeSample lerp(const StrokeSample& a, const StrokeSample& b, double t) {
    return {a.position + t * (b.position - a.position), a.time + t * (b.time - a.time),
            a.pressure + t * (b.pressure - a.pressure)};
}

[[noreturn]] void tooMany(double length, double spacing, std::size_t maxPoints) {
    throw std::invalid_argument("resampleBySpacing: " + std::to_string(length) + " mm at " +
                                std::to_string(spacing) + " mm spacing gives more than " +
                                std::to_string(maxPoints) + " points");
}

}  // namespace

Stroke resampleBySpacing(const Stroke& stroke, double spacing, std::size_t maxPoints) {
    validateStroke(stroke);
    requireSpacing(spacing);
    const auto& in = stroke.samples;
    // Measured first so that a step far too fine for the stroke is refused before allocating
    // (one sample at 1e6 mm with a 0.5 mm step would ask for gigabytes).
    double total = 0.0;
    for (std::size_t i = 0; i + 1 < in.size(); ++i)
        total += glm::distance(in[i].position, in[i + 1].position);
    // floor(total / spacing) + 1 points at least; the loop below checks the exact count.
    if (!(total / spacing < double(maxPoints))) tooMany(total, spacing, maxPoints);
    Stroke out;
    out.hasPressure = stroke.hasPressure;
    out.samples.reserve(std::min(std::size_t(total / spacing) + 2, maxPoints));
    out.samples.push_back(in.front());
    // Distance still to travel from the last emitted sample; walking input segments keeps the
    // output exactly `spacing` apart along the input path.
    double next = spacing;
    double travelled = 0.0;
    for (std::size_t i = 0; i + 1 < in.size(); ++i) {
        const double segLen = glm::distance(in[i].position, in[i + 1].position);
        if (segLen <= 0.0) continue;
        while (travelled + segLen >= next) {
            // Rounding in the running sums can add a point the estimate above did not count.
            if (out.samples.size() >= maxPoints) tooMany(total, spacing, maxPoints);
            const double t = (next - travelled) / segLen;
            out.samples.push_back(lerp(in[i], in[i + 1], t));
            next += spacing;
        }
        travelled += segLen;
    }
    if (travelled > 0.0) {
        // The last emitted sample may coincide with the end (length a multiple of spacing).
        if (glm::distance(out.samples.back().position, in.back().position) > 1e-9 * spacing) {
            if (out.samples.size() >= maxPoints) tooMany(total, spacing, maxPoints);
            out.samples.push_back(in.back());
        } else {
            out.samples.back() = in.back();
        }
    }
    return out;
}

Polyline2 resampleBySpacing(const Polyline2& line, double spacing, std::size_t maxPoints) {
    if (line.empty()) throw std::invalid_argument("resampleBySpacing: empty polyline");
    detail::requireFinite(line, "resampleBySpacing");
    return strokePositions(resampleBySpacing(makeStroke(line), spacing, maxPoints));
}

double boundedSpacing(double length, double spacing, std::size_t maxPoints) {
    requireSpacing(spacing);
    if (!(std::isfinite(length) && length >= 0.0))
        throw std::invalid_argument("boundedSpacing: length must be finite and >= 0");
    if (maxPoints < 4) throw std::invalid_argument("boundedSpacing: maxPoints must be >= 4");
    // length / spacing steps give at most that many points plus the start and the end; one
    // more step of slack absorbs rounding in the running arc length.
    return std::max(spacing, length / double(maxPoints - 3));
}

}  // namespace vsculpt::sketch
