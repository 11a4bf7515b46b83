// SPDX-License-Identifier: MIT
#include "vsculpt/render/Palette.h"

#include <string>

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

std::vector<OverlayQuad> sevenSegmentNumber(long value, double x, double y, double h) {
    // Segments a..g as bits 0..6: top, top-right, bottom-right, bottom, bottom-left, top-left,
    // middle.
    static const int kDigits[10] = {0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F};
    const std::string text = std::to_string(value < 0 ? 0 : value);
    const double w = 0.5 * h, t = 0.12 * h;  // digit width, stroke thickness
    std::vector<OverlayQuad> quads;
    for (char ch : text) {
        const int m = kDigits[ch - '0'];
        auto seg = [&](int bit, double x0, double y0, double x1, double y1) {
            if (m >> bit & 1) quads.push_back({x + x0, y + y0, x + x1, y + y1, 0.9f, 0.92f, 0.95f});
        };
        seg(0, 0, h - t, w, h);                      // a
        seg(1, w - t, h / 2, w, h);                  // b
        seg(2, w - t, 0, w, h / 2);                  // c
        seg(3, 0, 0, w, t);                          // d
        seg(4, 0, 0, t, h / 2);                      // e
        seg(5, 0, h / 2, t, h);                      // f
        seg(6, 0, h / 2 - t / 2, w, h / 2 + t / 2);  // g
        x += w + 0.4 * w;
    }
    return quads;
}

std::vector<OverlayQuad> statusQuads(const StatusLine& st) {
    const double h = 0.06, y = 0.9;
    double x = -0.95;
    std::vector<OverlayQuad> quads;
    const float tools[3][3] = {{0.45f, 1.0f, 0.5f}, {1.0f, 0.35f, 0.3f}, {0.4f, 0.6f, 1.0f}};
    const int t = st.tool < 0 || st.tool > 2 ? 0 : st.tool;
    quads.push_back({x, y, x + h, y + h, tools[t][0], tools[t][1], tools[t][2]});
    x += h + 0.04;
    for (long v : {long(st.size), long(st.zoom), st.skeletons, long(st.frameMs + 0.5)}) {
        const auto digits = sevenSegmentNumber(v, x, y, h);
        quads.insert(quads.end(), digits.begin(), digits.end());
        x += double(std::to_string(v).size()) * 0.7 * h + 0.06;
    }
    return quads;
}

}  // namespace vsculpt::render
