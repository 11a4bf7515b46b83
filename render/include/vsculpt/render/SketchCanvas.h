// SPDX-License-Identifier: MIT
/// @file SketchCanvas.h
/// @brief Draws the sketch canvas (issue #8) into a rectangle of the current OpenGL 3.3 core
/// context: paper, a light grid that follows pan and zoom (so the canvas reads as endless),
/// the ink of an InkStroke draw list, and optionally the pen's hover cursor and a lasso.
/// Frames and units as in SketchInk.h.
#pragma once

#include "vsculpt/render/SketchInk.h"

#include <glm/vec2.hpp>

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

namespace vsculpt::render {

/// What is drawn over the ink.
struct CanvasOverlay {
    bool grid = true;
    /// The pen hovering (or touching) here, canvas mm: a ring as wide as the line it would
    /// lay (penWidthMm, canvas mm, full width), filled while touching.
    std::optional<glm::dvec2> penMm;
    double penWidthMm = 1.0;
    bool penTouching = false;
    /// A lasso being drawn, canvas mm: its outline, closed, 1.5 pixels wide. Empty: none.
    std::vector<glm::dvec2> lassoMm;
};

struct CanvasStats {
    size_t strokesDrawn = 0;
    size_t strokesCulled = 0;  ///< wholly outside the viewport, not tessellated
    size_t triangles = 0;
};

/// Owns its GL objects (program, vertex array, buffer). Construct and destroy it with the
/// same GL 3.3 core context current (e.g. a Viewer's window); it is not copyable.
class SketchCanvas {
  public:
    /// Throws RenderError when the shaders cannot be built (no current GL 3.3 context).
    SketchCanvas();
    ~SketchCanvas();
    SketchCanvas(const SketchCanvas&) = delete;
    SketchCanvas& operator=(const SketchCanvas&) = delete;

    /// Draws into the framebuffer rectangle whose lower-left corner is `originPx` (GL
    /// window coordinates) and whose size is view.viewportPx; nothing outside it changes. The
    /// viewport, scissor, depth-test and blend state are restored afterwards (the bound
    /// program and vertex array are not). Strokes are drawn in list order (later ink covers
    /// earlier). Throws
    /// std::invalid_argument for an invalid view or stroke (see tessellateInk), RenderError
    /// on a GL error.
    CanvasStats draw(const std::vector<InkStroke>& ink, const CanvasView& view,
                     glm::ivec2 originPx = {0, 0}, const CanvasOverlay& overlay = {});

  private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

/// The grid's line spacing in canvas mm at a zoom: the power of ten that puts the lines at
/// least 5 view mm apart (every tenth line is drawn darker).
double canvasGridSpacingMm(double zoom);

}  // namespace vsculpt::render
