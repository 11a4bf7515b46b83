#include "vsculpt/sketch/ThreeSection.h"

#include "vsculpt/sketch/NaturalSpline.h"
#include "vsculpt/sketch/Prism.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

void requireOpenCurve(const Polyline2& curve, const char* name) {
    if (curve.size() < 2)
        throw std::invalid_argument(std::string("buildSections: curve ") + name +
                                    " needs at least 2 points");
    for (const auto& p : curve)
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument(std::string("buildSections: curve ") + name +
                                        " has a non-finite coordinate");
}

struct Range {
    double lo, hi;
};
Range rangeOf(const Polyline2& curve, int axis) {
    Range r{curve[0][axis], curve[0][axis]};
    for (const auto& p : curve) {
        r.lo = std::min(r.lo, p[axis]);
        r.hi = std::max(r.hi, p[axis]);
    }
    return r;
}

// Maps coordinate `axis` of every point affinely so that range `from` becomes `to`.
void remap(Polyline2& curve, int axis, Range from, Range to, const char* name) {
    if (!(from.hi > from.lo))
        throw std::invalid_argument(std::string("buildSections: curve ") + name +
                                    " has zero extent");
    for (auto& p : curve)
        p[axis] = to.lo + (p[axis] - from.lo) * (to.hi - to.lo) / (from.hi - from.lo);
}

// Appends points, skipping one equal (to 1e-9 of the scale) to the last point so far.
void appendDistinct(Polyline2& out, const glm::dvec2& p, double scale) {
    if (out.empty() || std::abs(out.back().x - p.x) + std::abs(out.back().y - p.y) > 1e-9 * scale)
        out.push_back(p);
}

void closeLoop(Polyline2& polygon, double scale) {
    while (polygon.size() > 1 && std::abs(polygon.back().x - polygon.front().x) +
                                         std::abs(polygon.back().y - polygon.front().y) <=
                                     1e-9 * scale)
        polygon.pop_back();
}

// Exact mirror symmetry of a nearly symmetric control polygon about component c = 0: keeps the
// run of vertices on the positive side and appends their mirror images. The inverse-Chaikin
// polygon of a symmetric section is symmetric only to the resampling accuracy, and the seed's
// solids are exactly mirror-symmetric. Returns the polygon unchanged if the positive vertices
// are not one contiguous run.
Polyline2 mirrorSymmetrize(const Polyline2& polygon, int c) {
    const std::size_t n = polygon.size();
    std::size_t start = n;
    for (std::size_t i = 0; i < n; ++i)
        if (polygon[i][c] > 0 && !(polygon[(i + n - 1) % n][c] > 0)) {
            if (start != n) return polygon;  // two runs
            start = i;
        }
    if (start == n) return polygon;
    Polyline2 run;
    for (std::size_t k = 0; k < n && polygon[(start + k) % n][c] > 0; ++k)
        run.push_back(polygon[(start + k) % n]);
    if (run.size() < 2) return polygon;
    Polyline2 out = run;
    for (auto it = run.rbegin(); it != run.rend(); ++it) {
        glm::dvec2 m = *it;
        m[c] = -m[c];
        out.push_back(m);
    }
    return out;
}

int axisIndex(Axis axis) {
    return axis == Axis::X ? 0 : axis == Axis::Y ? 1 : 2;
}

}  // namespace

HiddenBottom estimateHiddenBottom(double L1, double L2, double L3, double h3) {
    for (double v : {L1, L2, L3, h3})
        if (!std::isfinite(v) || !(v > 0))
            throw std::invalid_argument(
                "estimateHiddenBottom: L1, L2, L3 and h3 must be finite and positive");
    const double L4 = L1 / L2 * L3;
    return {L4, (L3 + L4) / L3 * h3};
}

ThreeSections buildSections(const SurfaceLines& lines) {
    requireOpenCurve(lines.back, "(a) back");
    requireOpenCurve(lines.torso, "(b) torso");
    requireOpenCurve(lines.belly, "(c) belly");
    requireOpenCurve(lines.bottom, "(d) bottom");
    ThreeSections out;
    out.bottom = estimateHiddenBottom(lines.L1, lines.L2, lines.L3, lines.h3);
    const double h4 = out.bottom.h4;

    // Reference extents from (a) and (b).
    const Range length = rangeOf(lines.back, 0);
    const Range height = rangeOf(lines.back, 1);
    if (!(length.hi > length.lo) || !(height.hi > 0))
        throw std::invalid_argument(
            "buildSections: curve (a) back needs a length and a top above z = 0");
    Polyline2 torso = lines.torso;
    remap(torso, 0, rangeOf(torso, 0), length, "(b) torso");
    const double halfWidth = rangeOf(torso, 1).hi;
    if (!(halfWidth > 0))
        throw std::invalid_argument("buildSections: curve (b) torso must reach y > 0");
    const double scale = std::max({length.hi - length.lo, height.hi, halfWidth, h4});

    // z-section: (b) and its mirror image.
    for (const auto& p : torso)
        appendDistinct(out.z, {p.x, std::max(p.y, 0.0)}, scale);
    for (auto it = torso.rbegin(); it != torso.rend(); ++it)
        appendDistinct(out.z, {it->x, -std::max(it->y, 0.0)}, scale);
    closeLoop(out.z, scale);

    // x-section: (c) scaled to the half width and the height, mirrored, closed through
    // (0, −h4) by a natural spline; the spline also passes the two last points of each side so
    // it leaves (c) smoothly.
    Polyline2 belly = lines.belly;
    {
        // Drawn from the bottom up: the same line (found by QA: refused, while the other
        // three lines may be drawn either way).
        if (belly.size() >= 2 && belly.back().y > belly.front().y)
            std::reverse(belly.begin(), belly.end());
        const Range y = rangeOf(belly, 0);
        const double top = belly.front().y;
        if (!(y.hi > 0) || !(top > 0))
            throw std::invalid_argument(
                "buildSections: curve (c) belly must start on top (z > 0) and reach y > 0");
        for (auto& p : belly) {
            p.x *= halfWidth / y.hi;
            p.y *= height.hi / top;
        }
        if (belly.back().y <= -h4)
            throw std::invalid_argument("buildSections: curve (c) belly reaches below −h4");
    }
    for (auto it = belly.rbegin(); it != belly.rend(); ++it)
        appendDistinct(out.x, {-it->x, it->y}, scale);
    for (const auto& p : belly)
        appendDistinct(out.x, p, scale);
    {
        const std::size_t m = belly.size();
        const glm::dvec2 end = belly[m - 1];
        const glm::dvec2 before = m >= 2 ? belly[m - 2] : end;
        const Polyline2 knots{before, end, {0.0, -h4}, {-end.x, end.y}, {-before.x, before.y}};
        const int perSpan = 16;
        const Polyline2 spline = sampleNaturalSpline(knots, false, perSpan);
        // Keep the spans end → (0, −h4) → mirrored end, without their end knots.
        for (int i = perSpan + 1; i < 3 * perSpan; ++i)
            appendDistinct(out.x, spline[i], scale);
    }
    closeLoop(out.x, scale);

    // y-section: (a) over the top, then (d) scaled to the length and down to −h4.
    Polyline2 bottom = lines.bottom;
    remap(bottom, 0, rangeOf(bottom, 0), length, "(d) bottom");
    {
        const double low = rangeOf(bottom, 1).lo;
        if (!(low < 0))
            throw std::invalid_argument("buildSections: curve (d) bottom must reach z < 0");
        for (auto& p : bottom)
            p.y *= h4 / -low;
    }
    // Run (d) from the end where (a) finishes back to where (a) starts.
    const bool sameDirection =
        (lines.back.front().x < lines.back.back().x) == (bottom.front().x < bottom.back().x);
    if (sameDirection) std::reverse(bottom.begin(), bottom.end());
    for (const auto& p : lines.back)
        appendDistinct(out.y, p, scale);
    for (const auto& p : bottom)
        appendDistinct(out.y, p, scale);
    closeLoop(out.y, scale);

    for (const auto* section : {&out.z, &out.x, &out.y})
        requireSimplePolygon(*section, "buildSections: section");
    return out;
}

ThreeSectionSolid reconstructFromSections(const ThreeSections& sections,
                                          const InverseChaikinOptions& options) {
    ThreeSectionSolid solid;
    solid.sections = sections;
    const Axis axes[3] = {Axis::Z, Axis::X, Axis::Y};
    const Polyline2* input[3] = {&sections.z, &sections.x, &sections.y};
    glm::dvec3 lo(1e300), hi(-1e300);
    for (int k = 0; k < 3; ++k) {
        solid.polygons[k] = inverseChaikin(*input[k], options).polygon;
        // The z-section (x, y) and the x-section (y, z) are symmetric about y = 0.
        if (axes[k] == Axis::Z) solid.polygons[k] = mirrorSymmetrize(solid.polygons[k], 1);
        if (axes[k] == Axis::X) solid.polygons[k] = mirrorSymmetrize(solid.polygons[k], 0);
        // Only the in-plane coordinates of a section bound the solid.
        for (const auto& p : solid.polygons[k]) {
            const glm::dvec3 q = sectionToWorld(axes[k], p, 0.0);
            for (int c = 0; c < 3; ++c) {
                if (c == axisIndex(axes[k])) continue;
                lo[c] = std::min(lo[c], q[c]);
                hi[c] = std::max(hi[c], q[c]);
            }
        }
    }
    // Each prism reaches past the others' extent by a different margin so no two caps are
    // coplanar (coplanar caps are legal for the exact Boolean but leave sliver facets).
    const double diagonal = glm::length(hi - lo);
    std::vector<PolyMesh> prisms;
    for (int k = 0; k < 3; ++k) {
        const int c = axisIndex(axes[k]);
        const double margin = (0.1 + 0.05 * k) * diagonal;
        prisms.push_back(sweepPrism(solid.polygons[k], axes[k], lo[c] - margin, hi[c] + margin));
    }
    solid.controlMesh = intersectSolids(prisms);
    return solid;
}

ThreeSectionSolid reconstructThreeSections(const SurfaceLines& lines,
                                           const InverseChaikinOptions& options) {
    return reconstructFromSections(buildSections(lines), options);
}

}  // namespace vsculpt::sketch
