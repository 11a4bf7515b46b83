// SPDX-License-Identifier: MIT
#include "vsculpt/app/ExportDetail.h"

#include "vsculpt/core/History.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/Zoom.h"
#include "vsculpt/studio/Session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vsculpt::app {

using namespace vsculpt::core;
using studio::Session;

ExportDetail exportDetail(const Session& session, double zoom1Mm) {
    ExportDetail out;
    out.keepingMm = zoom1Mm;
    int finest = kLevelCount + 1;
    for (const StrokeRecord& r : session.history().done()) {
        if (!r.solid)
            finest = std::min(finest, r.level);
        else
            for (const SkeletonChange& c : r.changes)
                finest = std::min(finest, c.level);
    }
    const SculptConfig& cfg = session.sculpture().config();
    for (int z = 1; z <= kZoomLevels && finest <= kLevelCount && out.zoom == 0; ++z)
        if (toolAllowedAtZoom(cfg, z, finest)) out.zoom = z;
    if (out.zoom == 0) return out;
    out.finestSize = finest;
    out.detailMm = zoomSpacing(cfg, session.sculpture().levels(), out.zoom);
    const Aabb bounds = session.sculpture().supportBounds();
    double extent = 0;
    for (int a = 0; a < 3; ++a)
        extent = std::max(extent, bounds.max[a] - bounds.min[a]);
    // The finest spacing Session::wholeMesh takes: its grid adds a cell or two each side and
    // rounds its size up to a multiple of 16, so 24 cells are left for those.
    const double finestFit = extent / (Session::kWholeMeshMaxCells - 24);
    out.capped = finestFit > out.detailMm;
    out.keepingMm = std::max(out.detailMm, finestFit);
    return out;
}

double wholeMeshFinestSpacing(const Session& session) {
    const Aabb bounds = session.sculpture().supportBounds();
    if (bounds.empty()) return 0;
    double extent = 0;
    for (int a = 0; a < 3; ++a)
        extent = std::max(extent, bounds.max[a] - bounds.min[a]);
    // As exportDetail: 24 cells are left for the grid's margins and its rounding to 16.
    const double fit = extent / (Session::kWholeMeshMaxCells - 24);
    const double unit = std::pow(10.0, std::floor(std::log10(fit)) - 2);
    return std::ceil(fit / unit) * unit;
}

double wholeMeshSpacing(const Session& session, double spacing, const std::string& option,
                        double maxMm, std::string& warning) {
    const double fit = wholeMeshFinestSpacing(session);
    if (!(fit > spacing)) return spacing;
    const double across = fit * (Session::kWholeMeshMaxCells - 24);
    char text[400];
    if (option.empty()) {
        std::snprintf(text, sizeof text,
                      "the region the sculpture's clay reaches is %.4g mm across (its skeletons' "
                      "reach), more than the whole-sculpture grid's %d "
                      "cells per axis hold at %.3g mm: meshing at %.3g mm",
                      across, Session::kWholeMeshMaxCells, spacing, fit);
        warning = text;
        return fit;
    }
    if (fit > maxMm)
        std::snprintf(text, sizeof text,
                      "%s %.3g: the region the sculpture's clay reaches is %.4g mm across, too "
                      "large to mesh whole at any "
                      "spacing vsculpt offers (the grid holds %d cells per axis, %s at most %.0f "
                      "mm); undo what was placed that far out",
                      option.c_str(), spacing, across, Session::kWholeMeshMaxCells, option.c_str(),
                      maxMm);
    else
        std::snprintf(text, sizeof text,
                      "%s %.3g: the region the sculpture's clay reaches is %.4g mm across, more "
                      "than the whole-sculpture "
                      "grid's %d cells per axis hold at that spacing: give %s %.3g or more",
                      option.c_str(), spacing, across, Session::kWholeMeshMaxCells, option.c_str(),
                      fit);
    throw studio::SessionError(text);
}

std::string exportDetailWarning(const Session& session, double spacing, const std::string& what,
                                const std::string& option) {
    const ExportDetail d = exportDetail(session, spacing);
    if (d.zoom == 0 || spacing <= d.detailMm * (1 + 1e-9)) return {};
    // Three significant digits, rounded so that the printed spacing does what the sentence
    // says: down to keep the detail, up to fit the grid.
    const double unit = std::pow(10.0, std::floor(std::log10(d.keepingMm)) - 2);
    const double suggest =
        d.capped ? std::ceil(d.keepingMm / unit) * unit : std::floor(d.keepingMm / unit) * unit;
    if (spacing <= suggest * (1 + 1e-9)) return {};
    char capNote[80];
    std::snprintf(capNote, sizeof capNote, "as much of it as the grid's %d cells per axis allow",
                  Session::kWholeMeshMaxCells);
    char text[320];
    std::snprintf(text, sizeof text,
                  "%s, %.3g mm, is coarser than the sculpture's finest detail (clay of size %d, "
                  "shown in full from zoom %d at %.3g mm), which it loses: %s %.3g keeps %s",
                  what.c_str(), spacing, d.finestSize, d.zoom, d.detailMm, option.c_str(), suggest,
                  d.capped ? capNote : "it");
    return text;
}

}  // namespace vsculpt::app
