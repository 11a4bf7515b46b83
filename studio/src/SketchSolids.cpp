// SPDX-License-Identifier: MIT
#include "vsculpt/studio/SketchSolids.h"

#include "vsculpt/sketch/StrokeClosedness.h"

#include <glm/geometric.hpp>

#include <stdexcept>
#include <string>

namespace vsculpt::studio {

namespace {

// A role as scripts write it ("surface-x"): one table both ways.
constexpr std::pair<const char*, studio::Role> kRoleWords[] = {
    {"none", studio::Role::None},
    {"outline", studio::Role::Outline},
    {"surface-x", studio::Role::SurfaceLineX},
    {"surface-y", studio::Role::SurfaceLineY},
    {"surface-z", studio::Role::SurfaceLineZ},
    {"sweep-section", studio::Role::SweepSection},
    {"sweep-path", studio::Role::SweepPath},
    {"cut", studio::Role::Cut},
    {"extrude", studio::Role::Extrude}};

}  // namespace

const char* roleScriptWord(studio::Role role) {
    for (const auto& [word, r] : kRoleWords)
        if (r == role) return word;
    return "none";
}

studio::Role roleFromScriptWord(const std::string& word) {
    for (const auto& [w, r] : kRoleWords)
        if (word == w) return r;
    throw std::invalid_argument("unknown role '" + word + "'");
}

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
                                          const std::optional<sketch::PolyMesh>& previous,
                                          std::vector<PolylineRef>* used) {
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
    const std::string what = sketch::constructionName(construction);
    // The polyline with `role` (and, when given, closedness) on the first page that has one;
    // on a view other than `view`, when one is required, refused.
    auto find = [&](R role, std::optional<bool> closed = std::nullopt,
                    std::optional<sketch::SketchPlane> view =
                        std::nullopt) -> std::optional<Found> {
        for (size_t page : order) {
            std::optional<Found> found;
            std::vector<std::string> names;
            for (const studio::RolePolyline& r : document.page(page).rolePolylines()) {
                if (r.role != role) continue;
                // A raw stroke counts as closed when it ends where it began, as loosely
                // as designers close loops (StrokeClosedness.h). Four points make the
                // smallest loop, a triangle back to its start (found by QA: a square of five
                // script points, docs/playback.md's own example in draft mode, was "not
                // closed" under the six points asked before).
                Found f{{r.points, r.closed}, planeOf(page)};
                if (!r.fromCurve && !r.closed && r.points.size() >= 4 &&
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
                if (closed && f.curve.closed != *closed) continue;
                names.push_back((r.fromCurve ? "curve " : "stroke ") + std::to_string(r.id));
                if (!found) {
                    found = f;
                    if (used) used->push_back({page, r.fromCurve, r.id});
                }
            }
            if (!found) continue;
            const std::string pageName = "page '" + document.page(page).name() + "'";
            if (names.size() > 1) {
                std::string list;
                for (const std::string& n : names)
                    list += (list.empty() ? "" : ", ") + n;
                throw std::invalid_argument(
                    what + ": " + pageName + " has " + std::to_string(names.size()) + " " +
                    roleScriptWord(role) + (closed ? (*closed ? " (closed)" : " (open)") : "") +
                    " lines (" + list + "); give the ones not meant role none");
            }
            if (view && found->plane != *view)
                throw std::invalid_argument(what + ": the " + roleScriptWord(role) +
                                            " line must be drawn on a " +
                                            sketch::sketchPlaneName(*view) + " view; " + pageName +
                                            " is a " + sketch::sketchPlaneName(found->plane) +
                                            " view (a page named side... or top... is one)");
            return found;
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
        case C::ThreeSection: {
            using P = sketch::SketchPlane;
            in.outline = curve(find(R::Outline, std::nullopt, P::Front));
            in.surfaceLineX = curve(find(R::SurfaceLineX, std::nullopt, P::Side));
            in.surfaceLineY = curve(find(R::SurfaceLineY, std::nullopt, P::Front));
            in.surfaceLineZ = curve(find(R::SurfaceLineZ, std::nullopt, P::Top));
            break;
        }
        case C::Sweep:
            in.sweepSection = curve(find(R::SweepSection, std::nullopt, sketch::SketchPlane::Side));
            in.sweepPath = curve(find(R::SweepPath, std::nullopt, sketch::SketchPlane::Top));
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
