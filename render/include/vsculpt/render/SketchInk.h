// SPDX-License-Identifier: MIT
/// @file SketchInk.h
/// @brief The sketch canvas's draw list (issue #8): what the renderer needs to know about ink,
/// independent of the sketch document model. The application turns its page into InkStrokes
/// each frame; SketchCanvas draws them and tessellateInk() turns one into triangles.
///
/// Frames and units:
/// - canvas: millimetres, x right, y up, unbounded (the endless sheet the strokes live on);
/// - view: millimetres on the screen/tablet surface, origin at the viewport's lower-left
///   corner, x right, y up; viewMm = (canvasMm - panMm) * zoom;
/// - pixels: the viewport's pixels, origin at its top-left corner, x right, y down (like
///   window cursor positions); pixel (i, j) covers [i, i+1) x [j, j+1), its centre is
///   (i + 0.5, j + 0.5).
/// This matches vsculpt::studio::CanvasView (canvas = scale * view + offset) with
/// zoom = 1 / scale and panMm = offset.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <vector>

namespace vsculpt::render {

/// How a stroke is coloured. The draft and clean classes are grey ink (black at darkness 1);
/// the others are tinted so a designer can tell state and purpose at a glance:
/// - Draft: draft-mode ink, kept as drawn;
/// - Selected: a selected draft stroke (blue);
/// - Pending: a clean-up stroke waiting for its group to end (green-grey);
/// - Consumed: a clean-up stroke already turned into a clean line (faint: 35 % of darkness);
/// - Clean: a clean line or curve (grey ink like Draft);
/// - Outline, SurfaceLine, Sweep, Cut: strokes with a role for the 3D builders (dark red,
///   green, purple, orange), so the user sees which lines will build the solid.
enum class InkClass { Draft, Selected, Pending, Consumed, Clean, Outline, SurfaceLine, Sweep, Cut };

/// One polyline of ink. widthMm and darkness hold one value per point, or a single value for
/// the whole stroke.
struct InkStroke {
    std::vector<glm::dvec2> pointsMm;  ///< canvas mm
    std::vector<float> widthMm;        ///< full line width (not half), canvas mm, >= 0
    std::vector<float> darkness;       ///< 0 = paper ... 1 = full ink colour
    InkClass cls = InkClass::Draft;
    bool closed = false;  ///< joins the last point back to the first (no caps)
};

/// Which part of the endless canvas a viewport shows, and how big the viewport is.
struct CanvasView {
    glm::dvec2 panMm{0.0};  ///< the canvas point at the view origin (viewport's lower-left)
    double zoom = 1.0;      ///< view mm per canvas mm (> 1 magnifies)
    glm::dvec2 viewportMm{200.0, 150.0};  ///< the viewport's size in view mm
    glm::ivec2 viewportPx{800, 600};      ///< and in pixels

    glm::dvec2 viewFromCanvas(glm::dvec2 canvas) const { return (canvas - panMm) * zoom; }
    glm::dvec2 canvasFromView(glm::dvec2 view) const { return view / zoom + panMm; }
    /// Pixels per view mm along x and y.
    glm::dvec2 pixelsPerMm() const { return glm::dvec2(viewportPx) / viewportMm; }
    /// A view point's position in viewport pixels (continuous, y down).
    glm::dvec2 pixelFromView(glm::dvec2 view) const {
        const glm::dvec2 s = pixelsPerMm();
        return {view.x * s.x, double(viewportPx.y) - view.y * s.y};
    }
    glm::dvec2 viewFromPixel(glm::dvec2 pixel) const {
        const glm::dvec2 s = pixelsPerMm();
        return {pixel.x / s.x, (double(viewportPx.y) - pixel.y) / s.y};
    }
    /// The view magnified by `factor` keeping the canvas point under `viewPoint` in place.
    /// Throws std::invalid_argument for a factor that is not finite and positive.
    CanvasView zoomedAbout(glm::dvec2 viewPoint, double factor) const;
};

/// Throws std::invalid_argument naming the field when the view is unusable: zoom not finite
/// and positive, pan not finite, viewport sizes not positive and finite.
void validateCanvasView(const CanvasView& view);

/// The paper colour (RGB, 0..1).
inline constexpr glm::vec3 kPaperRgb{0.976f, 0.969f, 0.941f};
/// The colour ink of a class lays at a darkness (0..1, clamped): paper mixed with the class's
/// full ink colour.
glm::vec3 inkRgb(InkClass cls, float darkness);

/// One triangle corner of tessellated ink.
struct InkVertex {
    glm::dvec2 viewMm{0.0};
    float darkness = 0;
};

/// Turns a stroke into triangles (three InkVertex per triangle, any winding) in view mm: a
/// quad per segment whose width is widthMm * zoom at each end, round joins on the outer side
/// of every turn and round caps at both ends (a disc for a one-point stroke). Arcs are split
/// into chords of about 3 pixels (at least 8 per full circle). Consecutive duplicate points
/// are merged, so any input without NaN gives finite triangles. A stroke with no points or
/// zero width gives none. Throws std::invalid_argument naming the field for non-finite
/// points, negative or non-finite widths, darkness outside [0, 1], or per-point arrays whose
/// size is neither 1 nor the point count; and for an invalid view.
std::vector<InkVertex> tessellateInk(const InkStroke& stroke, const CanvasView& view);

}  // namespace vsculpt::render
