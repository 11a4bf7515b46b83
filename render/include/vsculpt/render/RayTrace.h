// SPDX-License-Identifier: MIT
/// @file RayTrace.h
/// @brief Ray-traced stills with Embree (the high-definition images the thesis left as
/// future work): ambient occlusion and soft shadows from an area light, and ray picking.
/// Same framing as renderShot(), so a still and a screenshot line up pixel for pixel.
#pragma once

#include "vsculpt/core/Mesh.h"
#include "vsculpt/render/Shot.h"

#include <functional>
#include <memory>
#include <optional>

namespace vsculpt::render {

struct RayHit {
    double t = 0;           ///< distance along the (unit) ray, mm
    uint32_t triangle = 0;  ///< index into the mesh's triangles
    core::Vec3 position{0.0};
    core::Vec3 normal{0.0};  ///< geometric, unit, facing the ray's origin side
};

/// A mesh in an Embree scene (RAII over the device and scene). Thread-safe queries.
class RayScene {
  public:
    explicit RayScene(const core::Mesh& mesh);
    ~RayScene();
    RayScene(const RayScene&) = delete;
    RayScene& operator=(const RayScene&) = delete;

    /// Nearest hit of the ray origin + t dir, t in (tNear, tFar); dir need not be unit.
    std::optional<RayHit> intersect(const core::Vec3& origin, const core::Vec3& dir,
                                    double tNear = 0, double tFar = 1e30) const;
    /// Whether anything lies on the segment (tNear, tFar) of the ray.
    bool occluded(const core::Vec3& origin, const core::Vec3& dir, double tNear, double tFar) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

struct RayTraceOptions {
    int width = 960, height = 540;
    int aoSamples = 16;     ///< hemisphere rays per pixel for ambient occlusion
    int shadowSamples = 8;  ///< rays per pixel towards the area light
    unsigned seed = 1;      ///< same seed, same image
    /// Frame this box (object mm) instead of the mesh's bounds: a turntable keeps one framing
    /// for every frame, so the sculpture turns in place instead of jumping.
    std::optional<core::Aabb> frameBox;
    /// Stills fill the picture with the box (renderShot's default is the window's sphere).
    FrameFit fit = FrameFit::Box;
    /// Told the number of finished rows now and then (from worker threads, one call at a
    /// time; the last call reports every row). For progress bars.
    std::function<void(int rowsDone)> progress;
};

/// Renders the mesh from the front through renderShot(mono)'s projection for the same fit.
/// Pixels where no surface is hit have the background colour.
Image rayTrace(const core::Mesh& mesh, const RayTraceOptions& options);

}  // namespace vsculpt::render
