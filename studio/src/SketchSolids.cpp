// SPDX-License-Identifier: MIT
#include "vsculpt/studio/SketchSolids.h"

#include "vsculpt/sketch/StrokeClosedness.h"

#include <glm/geometric.hpp>

#include <stdexcept>

namespace vsculpt::studio {

sketch::SolidConstruction constructionFromName(const std::string& name) {
    using C = sketch::SolidConstruction;
    for (C c : {C::Inflate, C::ThreeSection, C::Sweep, C::Cut, C::Extrude})
        if (name == sketch::constructionName(c)) return c;
    throw std::invalid_argument("unknown solid construction '" + name +
                                "' (use inflate, three-section, sweep, cut or extrude)");
}

sketch::SketchSolidInput sketchSolidInput(sketch::SolidConstruction construction,
                                          const studio::SketchDocument& document,
                                          size_t currentPage,
                                          const std::vector<sketch::SketchPlane>& planes,
                                          const std::optional<sketch::PolyMesh>& previous) {
    using R = studio::Role;
    struct Found {
        sketch::SketchCurve curve;
        sketch::SketchPlane plane;
    };
    std::vector<size_t> order{currentPage};
    for (size_t i = 0; i < document.pageCount(); ++i)
        if (i != currentPage) order.push_back(i);
    auto planeOf = [&](size_t page) {
        return page < planes.size() ? planes[page] : sketch::SketchPlane::Front;
    };
    // The first polyline with `role` (and, when given, closedness).
    auto find = [&](R role, std::optional<bool> closed = std::nullopt) -> std::optional<Found> {
        for (size_t page : order)
            for (const studio::RolePolyline& r : document.page(page).rolePolylines())
                if (r.role == role) {
                    // A raw stroke counts as closed when it ends where it began, as loosely
                    // as designers close loops (StrokeClosedness.h).
                    Found f{{r.points, r.closed}, planeOf(page)};
                    if (!r.fromCurve && !r.closed && r.points.size() >= 6 &&
                        sketch::isClosedStroke(r.points)) {
                        f.curve.closed = true;
                        // Overshoot past the start would fold the outline: end at the point
                        // nearest the start within the last quarter.
                        sketch::Polyline2& p = f.curve.points;
                        size_t best = p.size() - 1;
                        for (size_t i = p.size() * 3 / 4; i < p.size(); ++i)
                            if (glm::distance(p[i], p[0]) < glm::distance(p[best], p[0])) best = i;
                        p.resize(best + 1);
                        if (p.size() > 3 && glm::distance(p.back(), p.front()) < 1e-9) p.pop_back();
                    }
                    if (!closed || f.curve.closed == *closed) return f;
                }
        return std::nullopt;
    };
    auto curve = [](const std::optional<Found>& f) {
        return f ? std::optional<sketch::SketchCurve>(f->curve) : std::nullopt;
    };
    sketch::SketchSolidInput in;
    in.construction = construction;
    in.previous = previous;
    using C = sketch::SolidConstruction;
    switch (construction) {
        case C::Inflate: {
            const auto o = find(R::Outline);
            in.outline = curve(o);
            if (o) in.outlinePlane = o->plane;
            break;
        }
        case C::ThreeSection:
            in.outline = curve(find(R::Outline));
            in.surfaceLineX = curve(find(R::SurfaceLineX));
            in.surfaceLineY = curve(find(R::SurfaceLineY));
            in.surfaceLineZ = curve(find(R::SurfaceLineZ));
            break;
        case C::Sweep:
            in.sweepSection = curve(find(R::SweepSection));
            in.sweepPath = curve(find(R::SweepPath));
            break;
        case C::Cut: {
            const auto c = find(R::Cut);
            in.cutStroke = curve(c);
            if (c) in.cutPlane = c->plane;
            break;
        }
        case C::Extrude: {
            const auto base = find(R::Extrude, true), silhouette = find(R::Extrude, false);
            in.extrudeBase = curve(base);
            in.extrudeSilhouette = curve(silhouette);
            if (base) in.extrudeBasePlane = base->plane;
            if (silhouette) in.extrudeSilhouettePlane = silhouette->plane;
            break;
        }
    }
    return in;
}

core::Mesh toMesh(const sketch::TriangleMesh& triangles) {
    core::Mesh m;
    m.positions.assign(triangles.positions.begin(), triangles.positions.end());
    m.indices = triangles.indices;
    return m;
}

}  // namespace vsculpt::studio
