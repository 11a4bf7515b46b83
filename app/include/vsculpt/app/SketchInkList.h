// SPDX-License-Identifier: MIT
/// @file SketchInkList.h
/// @brief What the sketch window draws on its canvas: a page's draw list as the renderer's
/// ink (roles tinted), and the strokes of its history that are no longer on the page (undone
/// or deleted), faint, for reuse (seed F-04). Canvas millimetres throughout.
#pragma once

#include "vsculpt/render/SketchInk.h"
#include "vsculpt/studio/SketchDocument.h"

#include <optional>
#include <vector>

namespace vsculpt::app {

/// The renderer's class of a draw item: its role's tint when it has a role, else its ink.
render::InkClass inkClass(const studio::DrawItem& item);

/// The page's draw list (live strokes, clean curves, the stroke being drawn) as ink.
std::vector<render::InkStroke> inkOf(const studio::SketchPage& page);

/// Strokes ever drawn that are not on the page now, as drawn (before any move or scale),
/// thin and faint.
std::vector<render::InkStroke> historyInk(const studio::SketchPage& page);

/// The undone or deleted stroke with a sample nearest to `point`, within `tolerance` mm.
std::optional<int> nearestHistoryStroke(const studio::SketchPage& page, glm::dvec2 point,
                                        double tolerance);

}  // namespace vsculpt::app
