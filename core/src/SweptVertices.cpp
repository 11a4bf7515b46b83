// SPDX-License-Identifier: MIT
#include "vsculpt/core/SweptVertices.h"

#include <algorithm>
#include <cmath>

namespace vsculpt::core {

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    double t = len2 > 0 ? glm::dot(p - a, ab) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return glm::length(p - (a + t * ab));
}

std::vector<SweptVertex> sweptVertices(double spacing, const Vec3& a, const Vec3& b,
                                       double radius) {
    std::vector<SweptVertex> out;
    const double reach = radius * (1 + 1e-9);
    // Pieces no longer than the radius keep each bounding box close to the capsule's volume.
    const double len = glm::length(b - a);
    const int pieces = std::max(1, int(std::ceil(len / std::max(radius, 1e-12))));
    for (int p = 0; p < pieces; ++p) {
        const Vec3 pa = a + (b - a) * (double(p) / pieces);
        const Vec3 pb = a + (b - a) * (double(p + 1) / pieces);
        const Vec3 lo = (glm::min(pa, pb) - Vec3(reach)) / spacing;
        const Vec3 hi = (glm::max(pa, pb) + Vec3(reach)) / spacing;
        for (int i = int(std::ceil(lo.x)); i <= int(std::floor(hi.x)); ++i)
            for (int j = int(std::ceil(lo.y)); j <= int(std::floor(hi.y)); ++j)
                for (int k = int(std::ceil(lo.z)); k <= int(std::floor(hi.z)); ++k) {
                    const Vec3 pos = Vec3(i, j, k) * spacing;
                    // Distance to the whole segment, so every piece reports the same value.
                    const double d = distanceToSegment(pos, a, b);
                    if (d <= reach) out.push_back({LatticeCoord{i, j, k}, std::min(d, radius)});
                }
    }
    // One box is walked in coordinate order, each vertex once; overlapping pieces need the
    // sort and the merge.
    if (pieces == 1) return out;
    std::sort(out.begin(), out.end(),
              [](const SweptVertex& l, const SweptVertex& r) { return l.coord < r.coord; });
    out.erase(
        std::unique(out.begin(), out.end(),
                    [](const SweptVertex& l, const SweptVertex& r) { return l.coord == r.coord; }),
        out.end());
    return out;
}

}  // namespace vsculpt::core
