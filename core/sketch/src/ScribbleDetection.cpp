#include "vsculpt/sketch/ScribbleDetection.h"

#include "CleanupGeometry.h"
#include "vsculpt/sketch/ResampleStroke.h"

#include <cmath>
#include <deque>
#include <stdexcept>

namespace vsculpt::sketch {

namespace {

void requireParams(const ScribbleParams& p) {
    if (!(p.spacing > 0.0 && p.reversalAngle > 0.0 && p.reversalWindow > 0.0 &&
          p.minReversals > 0 && p.minInkRatio > 0.0))
        throw std::invalid_argument("isScribble: parameters must be positive");
    if (p.maxPoints < 4) throw std::invalid_argument("isScribble: maxPoints must be >= 4");
}

}  // namespace

int countReversals(const Polyline2& line, const ScribbleParams& params) {
    detail::requireFinite(line, "countReversals");
    requireParams(params);
    if (line.size() < 3) return 0;
    const double spacing = boundedSpacing(length(line, false), params.spacing, params.maxPoints);
    const Polyline2 pts = resampleBySpacing(line, spacing, params.maxPoints);
    // Signed turns at each resampled vertex; a reversal is a same-signed turn total of at least
    // reversalAngle within the window (then the window restarts so one hairpin counts once).
    // At least two vertices: a sharp corner between samples splits its turn over two.
    const std::size_t window =
        std::max<std::size_t>(2, std::size_t(params.reversalWindow / spacing));
    std::deque<double> recent;
    double sum = 0.0;
    int reversals = 0;
    for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
        const glm::dvec2 d0 = pts[i] - pts[i - 1], d1 = pts[i + 1] - pts[i];
        const double turn = std::atan2(detail::cross(d0, d1), glm::dot(d0, d1));
        recent.push_back(turn);
        sum += turn;
        if (recent.size() > window) {
            sum -= recent.front();
            recent.pop_front();
        }
        if (std::abs(sum) >= params.reversalAngle) {
            ++reversals;
            recent.clear();
            sum = 0.0;
        }
    }
    return reversals;
}

bool isScribble(const Polyline2& line, const ScribbleParams& params) {
    const int reversals = countReversals(line, params);
    if (reversals < params.minReversals) return false;
    glm::dvec2 lo = line.front(), hi = line.front();
    for (const glm::dvec2& p : line) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double diagonal = glm::distance(lo, hi);
    return length(line, false) >= params.minInkRatio * diagonal;
}

bool isScribble(const Stroke& stroke, const ScribbleParams& params) {
    validateStroke(stroke);
    return isScribble(strokePositions(stroke), params);
}

}  // namespace vsculpt::sketch
