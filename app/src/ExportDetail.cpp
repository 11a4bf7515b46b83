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

std::string exportDetailWarning(const Session& session, double spacing) {
    int finest = kLevelCount + 1;
    for (const StrokeRecord& r : session.history().done()) {
        if (!r.solid)
            finest = std::min(finest, r.level);
        else
            for (const SkeletonChange& c : r.changes)
                finest = std::min(finest, c.level);
    }
    const SculptConfig& cfg = session.sculpture().config();
    int zoom = 0;
    for (int z = 1; z <= kZoomLevels && finest <= kLevelCount && zoom == 0; ++z)
        if (toolAllowedAtZoom(cfg, z, finest)) zoom = z;
    if (zoom == 0) return {};
    const double detail = zoomSpacing(cfg, session.sculpture().levels(), zoom);
    if (spacing <= detail * (1 + 1e-9)) return {};
    const Aabb bounds = session.sculpture().supportBounds();
    double extent = 0;
    for (int a = 0; a < 3; ++a)
        extent = std::max(extent, bounds.max[a] - bounds.min[a]);
    // The finest spacing Session::wholeMesh takes: its grid adds a cell or two each side and
    // rounds its size up to a multiple of 16, so 24 cells are left for those.
    const double finestFit = extent / (Session::kWholeMeshMaxCells - 24);
    const bool capped = finestFit > detail;
    // Three significant digits, rounded so that the printed spacing does what the sentence
    // says: down to keep the detail, up to fit the grid.
    const double unit = std::pow(10.0, std::floor(std::log10(capped ? finestFit : detail)) - 2);
    const double suggest =
        capped ? std::ceil(finestFit / unit) * unit : std::floor(detail / unit) * unit;
    if (spacing <= suggest * (1 + 1e-9)) return {};
    char capNote[80];
    std::snprintf(capNote, sizeof capNote, "as much of it as the grid's %d cells per axis allow",
                  Session::kWholeMeshMaxCells);
    char text[320];
    std::snprintf(text, sizeof text,
                  "the export's grid spacing, %.3g mm, is coarser than the sculpture's finest "
                  "detail (size %d, drawn at zoom %d at %.3g mm), which it loses: "
                  "--export-spacing %.3g keeps %s",
                  spacing, finest, zoom, detail, suggest, capped ? capNote : "it");
    return text;
}

}  // namespace vsculpt::app
