#include "vsculpt/sketch/FeaturePoints.h"

#include "CleanupGeometry.h"

#include <stdexcept>
#include <utility>
#include <vector>

namespace vsculpt::sketch {

namespace {

// Farthest point of stroke[i0..i1] from its chord (from stroke[i0] when the chord is zero) and
// its distance.
std::pair<std::size_t, double> farthest(const Polyline2& stroke, std::size_t i0, std::size_t i1) {
    const glm::dvec2 a = stroke[i0], chord = stroke[i1] - a;
    const double len = glm::length(chord);
    std::pair<std::size_t, double> best{(i0 + i1) / 2, -1.0};
    for (std::size_t i = i0 + 1; i < i1; ++i) {
        const double d = len > 0.0 ? std::abs(detail::cross(chord, stroke[i] - a)) / len
                                   : glm::distance(stroke[i], a);
        if (d > best.second) best = {i, d};
    }
    return best;
}

void refine(const Polyline2& stroke, std::size_t i0, std::size_t i1, double ratio,
            std::vector<std::size_t>& out) {
    if (i1 - i0 < 2) return;
    const auto [k, d] = farthest(stroke, i0, i1);
    if (!(d > ratio * glm::distance(stroke[i0], stroke[i1]))) return;
    refine(stroke, i0, k, ratio, out);
    out.push_back(k);
    refine(stroke, k, i1, ratio, out);
}

}  // namespace

Polyline2 strokeFeaturePoints(const Polyline2& stroke, double maxChordRatio) {
    detail::requireFinite(stroke, "strokeFeaturePoints");
    if (stroke.size() < 2) throw std::invalid_argument("strokeFeaturePoints: need 2 points");
    if (!(maxChordRatio >= 0.0))
        throw std::invalid_argument("strokeFeaturePoints: maxChordRatio must be >= 0");
    if (maxChordRatio > 0.0 && stroke.size() > 2) {
        const std::size_t mid = farthest(stroke, 0, stroke.size() - 1).first;
        std::vector<std::size_t> idx{0};
        refine(stroke, 0, mid, maxChordRatio, idx);
        idx.push_back(mid);
        refine(stroke, mid, stroke.size() - 1, maxChordRatio, idx);
        idx.push_back(stroke.size() - 1);
        Polyline2 out;
        for (std::size_t i : idx)
            out.push_back(stroke[i]);
        return out;
    }
    const glm::dvec2 a = stroke.front(), b = stroke.back();
    const glm::dvec2 chord = b - a;
    const double len = glm::length(chord);
    std::size_t best = stroke.size() / 2;
    double bestDist = -1.0;
    for (std::size_t i = 1; i + 1 < stroke.size(); ++i) {
        const double d = len > 0.0 ? std::abs(detail::cross(chord, stroke[i] - a)) / len
                                   : glm::distance(stroke[i], a);
        if (d > bestDist) {
            bestDist = d;
            best = i;
        }
    }
    if (stroke.size() == 2) return {a, 0.5 * (a + b), b};
    return {a, stroke[best], b};
}

}  // namespace vsculpt::sketch
