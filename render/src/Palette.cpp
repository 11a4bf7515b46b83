// SPDX-License-Identifier: MIT
#include "vsculpt/render/Palette.h"

namespace vsculpt::render {

std::vector<PaletteItem> layoutPalette(const std::vector<int>& offeredSizes, int currentSize,
                                       int zoom) {
    std::vector<PaletteItem> items;
    double x = -0.92;
    const double base = -0.94;
    for (int size : offeredSizes) {
        const double edge = 0.05 + 0.012 * size;  // bigger tools, bigger squares
        items.push_back(
            {PaletteItem::Kind::Size, size, size == currentSize, x, base, x + edge, base + edge});
        x += edge + 0.03;
    }
    x += 0.08;
    for (int z = 1; z <= 5; ++z) {
        const double edge = 0.07;
        items.push_back({PaletteItem::Kind::Zoom, z, z == zoom, x, base, x + edge,
                         base + edge * (0.6 + 0.2 * z)});
        x += edge + 0.02;
    }
    return items;
}

const PaletteItem* pickPalette(const std::vector<PaletteItem>& items, double x, double y) {
    for (const PaletteItem& it : items)
        if (x >= it.x0 && x <= it.x1 && y >= it.y0 && y <= it.y1) return &it;
    return nullptr;
}

}  // namespace vsculpt::render
