// SPDX-License-Identifier: MIT
/// @file Palette.h
/// @brief The on-screen palette: direct jumps to any size offered at the current zoom and to
/// any zoom level (zoom 1 = the overview). Items are laid out in each eye's normalised device
/// coordinates, identically for both eyes, so in stereo they sit at screen depth (zero
/// parallax) and can be read and clicked in every mode.
#pragma once

#include <vector>

namespace vsculpt::render {

struct PaletteItem {
    enum class Kind { Size, Zoom };
    Kind kind = Kind::Size;
    int value = 0;                          ///< tool level or zoom level
    bool current = false;                   ///< the size or zoom in use
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< rectangle in the eye's NDC ([-1, 1])
};

/// Sizes offered at the current zoom (largest first, squares growing with the size), then
/// zoom levels 1..5, along the bottom edge.
std::vector<PaletteItem> layoutPalette(const std::vector<int>& offeredSizes, int currentSize,
                                       int zoom);

/// The item under a point in the eye's NDC, or nullptr.
const PaletteItem* pickPalette(const std::vector<PaletteItem>& items, double x, double y);

/// A flat coloured rectangle drawn over the scene in each eye's NDC.
struct OverlayQuad {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    float r = 1, g = 1, b = 1;
};

/// The status line along the top edge, readable in a headset where no title bar is: a square
/// in the tool's colour (add green, carve red, select blue), then the size, the zoom level,
/// the skeleton count and the frame time in milliseconds as seven-segment numbers.
struct StatusLine {
    int tool = 0;  ///< 0 add, 1 carve, 2 select
    int size = 0, zoom = 0;
    long skeletons = 0;
    double frameMs = 0;
};
std::vector<OverlayQuad> statusQuads(const StatusLine& status);

/// The quads of a non-negative integer in seven-segment digits, left edge at x, bottom at y,
/// digit height h (NDC). Exposed for tests.
std::vector<OverlayQuad> sevenSegmentNumber(long value, double x, double y, double h);

}  // namespace vsculpt::render
