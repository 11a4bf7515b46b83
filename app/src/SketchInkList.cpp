// SPDX-License-Identifier: MIT
#include "vsculpt/app/SketchInkList.h"

#include <glm/geometric.hpp>

namespace vsculpt::app {

using namespace vsculpt::studio;

render::InkClass inkClass(const studio::DrawItem& d) {
    using R = studio::Role;
    switch (d.role) {
        case R::Outline:
            return render::InkClass::Outline;
        case R::SurfaceLineX:
        case R::SurfaceLineY:
        case R::SurfaceLineZ:
            return render::InkClass::SurfaceLine;
        case R::SweepSection:
        case R::SweepPath:
            return render::InkClass::Sweep;
        case R::Cut:
        case R::Extrude:
            return render::InkClass::Cut;
        case R::None:
            break;
    }
    switch (d.ink) {
        case studio::InkClass::Draft:
            return render::InkClass::Draft;
        case studio::InkClass::Selected:
            return render::InkClass::Selected;
        case studio::InkClass::Pending:
            return render::InkClass::Pending;
        case studio::InkClass::Consumed:
            return render::InkClass::Consumed;
        case studio::InkClass::Clean:
            break;
    }
    return render::InkClass::Clean;
}

std::vector<render::InkStroke> inkOf(const studio::SketchPage& page) {
    std::vector<render::InkStroke> out;
    for (const studio::DrawItem& d : page.drawList()) {
        if (d.points.empty()) continue;
        render::InkStroke s;
        s.pointsMm = d.points;
        s.widthMm.assign(d.width.begin(), d.width.end());
        s.darkness.assign(d.darkness.begin(), d.darkness.end());
        s.cls = inkClass(d);
        s.closed = d.closed;
        out.push_back(std::move(s));
    }
    return out;
}

// Strokes ever drawn that are not on the page now (undone or deleted), as drawn, faint.
std::vector<render::InkStroke> historyInk(const studio::SketchPage& page) {
    std::vector<render::InkStroke> out;
    for (const studio::ArchivedStroke& a : page.history()) {
        if (page.strokeStatus(a.id) == studio::StrokeStatus::Live || a.stroke.samples.empty())
            continue;
        render::InkStroke s;
        for (const sketch::StrokeSample& q : a.stroke.samples)
            s.pointsMm.push_back(q.position);
        s.widthMm.assign(s.pointsMm.size(), float(0.5 * a.inkScale));
        s.darkness.assign(s.pointsMm.size(), 0.35f);
        s.cls = render::InkClass::Consumed;
        out.push_back(std::move(s));
    }
    return out;
}

// The undone or deleted stroke nearest to `p` (canvas mm) within `tolerance`.
std::optional<int> nearestHistoryStroke(const studio::SketchPage& page, glm::dvec2 p,
                                        double tolerance) {
    std::optional<int> best;
    double bestD = tolerance;
    for (const studio::ArchivedStroke& a : page.history()) {
        if (page.strokeStatus(a.id) == studio::StrokeStatus::Live) continue;
        for (const sketch::StrokeSample& q : a.stroke.samples) {
            const double d = glm::distance(q.position, p);
            if (d <= bestD) {
                bestD = d;
                best = a.id;
            }
        }
    }
    return best;
}

}  // namespace vsculpt::app
