// SPDX-License-Identifier: MIT
/// @file ProjectStroke.h
/// @brief Drawing on the model (issue #8 item 5): a 2D stroke drawn over the 3D view becomes
/// polylines on the sculpture's surface, found with one Embree ray per sample.
///
/// Frames and units: positions are the mesh's object frame, millimetres. Pixels are window
/// pixels of the 3D view: origin at the top-left corner, x right, y down, pixel (i, j)'s centre
/// at (i + 0.5, j + 0.5): continuous, like GLFW cursor positions. (Viewer::pixelRay(x, y)
/// adds the half pixel itself: it equals pixelRayInObject at (x + 0.5, y + 0.5).)
#pragma once

#include "vsculpt/core/Mesh.h"
#include "vsculpt/render/RayTrace.h"
#include "vsculpt/render/StereoCamera.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include <optional>
#include <vector>

namespace vsculpt::render {

/// The camera a stroke was drawn through.
struct ProjectionCamera {
    /// Object to OpenGL clip coordinates: clipFromView * viewFromWorld * worldFromObject.
    glm::dmat4 clipFromObject{1.0};
    glm::ivec2 viewportPx{960, 540};  ///< the 3D view's size in pixels

    /// The camera of one eye (EyeView from stereoEyes(); the mono eye for the window) looking
    /// at a sculpture placed at `worldFromObject`.
    static ProjectionCamera fromEye(const EyeView& eye, const glm::dmat4& worldFromObject,
                                    glm::ivec2 viewportPx);
};

/// The ray through a pixel, object frame: from the near plane towards the far plane; `dir` is
/// unit. Throws std::invalid_argument for a non-finite pixel or a camera that cannot be
/// inverted or has a non-positive viewport.
void pixelRayInObject(const ProjectionCamera& camera, glm::dvec2 pixel, core::Vec3& origin,
                      core::Vec3& dir);

/// The surface point under one pixel, or nullopt where the ray misses the mesh.
std::optional<RayHit> pickSurface(const RayScene& scene, const ProjectionCamera& camera,
                                  glm::dvec2 pixel);

struct StrokeProjectionOptions {
    /// Consecutive points of a surface line are at most this far apart (straight-line
    /// distance, object mm), except across a step finer than minPixelStep (see below).
    double spacingMm = 1.0;
    /// Where two neighbouring hits, less than minPixelStep apart on the screen, are farther
    /// apart than this in 3D, the surface is not continuous there (one part hides another):
    /// the line is split.
    double maxDepthJumpMm = 5.0;
    /// How finely a segment is bisected (pixels) to find where the stroke leaves the surface
    /// or jumps in depth.
    double minPixelStep = 1.0 / 64;
    /// Gaps between input samples are first filled every this many pixels, so a stroke that
    /// passes over a thin part between two samples still finds it.
    double probeStepPx = 2.0;
};

/// A point of a surface line.
struct SurfacePoint {
    core::Vec3 position{0.0};  ///< object mm, on the mesh
    core::Vec3 normal{0.0};    ///< unit, the hit triangle's, facing the camera
    uint32_t triangle = 0;
    glm::dvec2 pixel{0.0};  ///< where on the screen it was found
};

/// Projects a stroke given in pixels onto the surface. Returns the pieces in stroke order:
/// a new piece starts where the stroke comes back onto the surface after leaving it, or after
/// a depth jump. A piece ends within minPixelStep of the place where the stroke leaves the
/// surface. Pieces of a single point are dropped unless the stroke itself is one point.
/// Throws std::invalid_argument naming the field for options that are not finite and
/// positive, maxDepthJumpMm < spacingMm, or non-finite pixels.
std::vector<std::vector<SurfacePoint>> projectStroke(const RayScene& scene,
                                                     const ProjectionCamera& camera,
                                                     const std::vector<glm::dvec2>& strokePx,
                                                     const StrokeProjectionOptions& options = {});

/// The same, building the Embree scene from `mesh` first (for one-off strokes; keep a
/// RayScene when projecting many).
std::vector<std::vector<SurfacePoint>> projectStroke(const core::Mesh& mesh,
                                                     const ProjectionCamera& camera,
                                                     const std::vector<glm::dvec2>& strokePx,
                                                     const StrokeProjectionOptions& options = {});

}  // namespace vsculpt::render
