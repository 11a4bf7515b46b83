#include "vsculpt/sketch/FeaturePoints.h"

#include "CleanupGeometry.h"

#include <algorithm>
#include <queue>
#include <stdexcept>
#include <tuple>
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

// A piece that qualifies for a split: its deviation, then its range (ties go to the earlier
// piece, so the order is deterministic).
struct Piece {
    double deviation;
    std::size_t i0, i1, split;
    bool operator<(const Piece& o) const {
        return std::tie(deviation, o.i0) < std::tie(o.deviation, i0);
    }
};

}  // namespace

Polyline2 strokeFeaturePoints(const Polyline2& stroke, double maxChordRatio,
                              std::size_t maxPoints) {
    detail::requireFinite(stroke, "strokeFeaturePoints");
    if (stroke.size() < 2) throw std::invalid_argument("strokeFeaturePoints: need 2 points");
    if (!(maxChordRatio >= 0.0))
        throw std::invalid_argument("strokeFeaturePoints: maxChordRatio must be >= 0");
    if (maxPoints < 3) throw std::invalid_argument("strokeFeaturePoints: maxPoints must be >= 3");
    if (maxChordRatio > 0.0 && stroke.size() > 2) {
        const std::size_t mid = farthest(stroke, 0, stroke.size() - 1).first;
        std::vector<std::size_t> idx{0, mid, stroke.size() - 1};
        // Whether a piece is split depends only on the piece, so splitting the most deviant
        // first yields the same points as depth-first recursion whenever the cap is not hit,
        // and keeps the most visible shape when it is.
        std::priority_queue<Piece> queue;
        const auto consider = [&](std::size_t i0, std::size_t i1) {
            if (i1 - i0 < 2) return;
            const auto [k, d] = farthest(stroke, i0, i1);
            if (d > maxChordRatio * glm::distance(stroke[i0], stroke[i1]))
                queue.push({d, i0, i1, k});
        };
        consider(0, mid);
        consider(mid, stroke.size() - 1);
        while (!queue.empty() && idx.size() < maxPoints) {
            const Piece p = queue.top();
            queue.pop();
            idx.push_back(p.split);
            consider(p.i0, p.split);
            consider(p.split, p.i1);
        }
        std::sort(idx.begin(), idx.end());
        Polyline2 out;
        out.reserve(idx.size());
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
