// SPDX-License-Identifier: MIT
#include "vsculpt/core/Zoom.h"

#include "vsculpt/core/ToolLevels.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vsculpt::core {

namespace {
void checkZoom(int zoom) {
    if (zoom < 1 || zoom > kZoomLevels)
        throw std::out_of_range("zoom level " + std::to_string(zoom) + " outside 1..5");
}
}  // namespace

double zoomSpacing(const SculptConfig& cfg, const ToolLevels& levels, int zoom) {
    checkZoom(zoom);
    return cfg.zoom.baseSpacingOverD6 * levels.level(6).diameterMm / double(1 << (zoom - 1));
}

GridRegion zoomRegion(const SculptConfig& cfg, const ToolLevels& levels, int zoom,
                      const Vec3& centerMm) {
    checkZoom(zoom);
    GridRegion r;
    r.spacingMm = zoomSpacing(cfg, levels, zoom);
    r.n = cfg.polygonizer.gridN;
    const Vec3 c = zoom == 1 ? cfg.sphereCenterMm : centerMm;
    if (!isUsablePoint(c)) throw std::invalid_argument("zoom centre is not a usable point");
    for (int a = 0; a < 3; ++a)
        r.originCell[a] = std::llround(c[a] / r.spacingMm) - r.n / 2;
    return r;
}

bool toolAllowedAtZoom(const SculptConfig& cfg, int zoom, int level) {
    checkZoom(zoom);
    const auto& allowed = cfg.zoom.allowedSizes[zoom - 1];
    return std::find(allowed.begin(), allowed.end(), level) != allowed.end();
}

}  // namespace vsculpt::core
