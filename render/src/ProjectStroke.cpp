// SPDX-License-Identifier: MIT
#include "vsculpt/render/ProjectStroke.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::render {

namespace {

bool finite(glm::dvec2 v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
}

/// Unprojects pixels through one precomputed inverse.
class PixelRays {
  public:
    explicit PixelRays(const ProjectionCamera& c) : mViewport(c.viewportPx) {
        if (c.viewportPx.x <= 0 || c.viewportPx.y <= 0)
            throw std::invalid_argument("ProjectionCamera.viewportPx must be > 0");
        const double det = glm::determinant(c.clipFromObject);
        if (!std::isfinite(det) || det == 0)
            throw std::invalid_argument("ProjectionCamera.clipFromObject is not invertible");
        mObjectFromClip = glm::inverse(c.clipFromObject);
    }

    void ray(glm::dvec2 px, core::Vec3& origin, core::Vec3& dir) const {
        if (!finite(px)) throw std::invalid_argument("pixel is not finite");
        const double nx = px.x / mViewport.x * 2 - 1, ny = 1 - px.y / mViewport.y * 2;
        const glm::dvec4 pn = mObjectFromClip * glm::dvec4(nx, ny, -1, 1);
        const glm::dvec4 pf = mObjectFromClip * glm::dvec4(nx, ny, 1, 1);
        origin = core::Vec3(pn) / pn.w;
        dir = glm::normalize(core::Vec3(pf) / pf.w - origin);
    }

  private:
    glm::ivec2 mViewport;
    glm::dmat4 mObjectFromClip{1.0};
};

using Hit = std::optional<SurfacePoint>;
using Piece = std::vector<SurfacePoint>;

class Projector {
  public:
    Projector(const RayScene& scene, const ProjectionCamera& camera,
              const StrokeProjectionOptions& o)
        : mScene(scene), mRays(camera), mO(o) {}

    Hit cast(glm::dvec2 px) const {
        core::Vec3 origin, dir;
        mRays.ray(px, origin, dir);
        const auto h = mScene.intersect(origin, dir);
        if (!h) return std::nullopt;
        return SurfacePoint{h->position, h->normal, h->triangle, px};
    }

    /// Appends what lies after `a` up to and including `b` along the segment a-b.
    void walk(const Hit& a, glm::dvec2 pa, const Hit& b, glm::dvec2 pb, int depth) {
        if (!a && !b) return;  // the probe step already bounds what can hide between misses
        const bool finest = glm::length(pb - pa) < mO.minPixelStep || depth > 60;
        if (a && b) {
            const double gap = glm::length(b->position - a->position);
            if (gap <= mO.spacingMm) {
                emit(*b);
                return;
            }
            if (finest) {
                // Still apart below the bisection limit: a steep but continuous surface when
                // the gap is small, one part hiding another when it is large.
                if (gap > mO.maxDepthJumpMm) endPiece();
                emit(*b);
                return;
            }
        } else if (finest) {
            // The stroke leaves (b misses) or enters (a misses) the surface here.
            endPiece();
            if (b) emit(*b);
            return;
        }
        const glm::dvec2 pm = 0.5 * (pa + pb);
        const Hit m = cast(pm);
        walk(a, pa, m, pm, depth + 1);
        walk(m, pm, b, pb, depth + 1);
    }

    void emit(const SurfacePoint& p) { mCurrent.push_back(p); }
    void endPiece() {
        if (mCurrent.size() >= 2) mPieces.push_back(std::move(mCurrent));
        mCurrent.clear();
    }
    std::vector<Piece> finish() {
        endPiece();
        return std::move(mPieces);
    }

  private:
    const RayScene& mScene;
    PixelRays mRays;
    StrokeProjectionOptions mO;
    Piece mCurrent;
    std::vector<Piece> mPieces;
};

void checkOptions(const StrokeProjectionOptions& o) {
    auto positive = [](double v, const char* name) {
        if (!std::isfinite(v) || v <= 0)
            throw std::invalid_argument(std::string("StrokeProjectionOptions.") + name +
                                        " must be finite and > 0");
    };
    positive(o.spacingMm, "spacingMm");
    positive(o.maxDepthJumpMm, "maxDepthJumpMm");
    positive(o.minPixelStep, "minPixelStep");
    positive(o.probeStepPx, "probeStepPx");
    if (o.maxDepthJumpMm < o.spacingMm)
        throw std::invalid_argument(
            "StrokeProjectionOptions.maxDepthJumpMm must be >= spacingMm (a jump smaller than "
            "the spacing could not be told from the next sample)");
}

}  // namespace

ProjectionCamera ProjectionCamera::fromEye(const EyeView& eye, const glm::dmat4& worldFromObject,
                                           glm::ivec2 viewportPx) {
    return {eye.clipFromView * eye.viewFromWorld * worldFromObject, viewportPx};
}

void pixelRayInObject(const ProjectionCamera& camera, glm::dvec2 pixel, core::Vec3& origin,
                      core::Vec3& dir) {
    PixelRays(camera).ray(pixel, origin, dir);
}

std::optional<RayHit> pickSurface(const RayScene& scene, const ProjectionCamera& camera,
                                  glm::dvec2 pixel) {
    core::Vec3 origin, dir;
    pixelRayInObject(camera, pixel, origin, dir);
    return scene.intersect(origin, dir);
}

std::vector<std::vector<SurfacePoint>> projectStroke(const RayScene& scene,
                                                     const ProjectionCamera& camera,
                                                     const std::vector<glm::dvec2>& strokePx,
                                                     const StrokeProjectionOptions& options) {
    checkOptions(options);
    for (size_t i = 0; i < strokePx.size(); ++i)
        if (!finite(strokePx[i]))
            throw std::invalid_argument("strokePx[" + std::to_string(i) + "] is not finite");
    Projector p(scene, camera, options);
    if (strokePx.empty()) return {};
    if (strokePx.size() == 1) {
        if (const Hit h = p.cast(strokePx[0])) return {{*h}};
        return {};
    }
    glm::dvec2 prevPx = strokePx[0];
    Hit prev = p.cast(prevPx);
    if (prev) p.emit(*prev);
    for (size_t i = 1; i < strokePx.size(); ++i) {
        const glm::dvec2 target = strokePx[i];
        const double len = glm::length(target - prevPx);
        if (len == 0) continue;
        const int steps = std::max(1, int(std::ceil(len / options.probeStepPx)));
        const glm::dvec2 start = prevPx;
        for (int k = 1; k <= steps; ++k) {
            const glm::dvec2 px =
                k == steps ? target : start + (target - start) * (double(k) / steps);
            const Hit h = p.cast(px);
            p.walk(prev, prevPx, h, px, 0);
            prev = h;
            prevPx = px;
        }
    }
    return p.finish();
}

std::vector<std::vector<SurfacePoint>> projectStroke(const core::Mesh& mesh,
                                                     const ProjectionCamera& camera,
                                                     const std::vector<glm::dvec2>& strokePx,
                                                     const StrokeProjectionOptions& options) {
    checkOptions(options);
    const RayScene scene(mesh);
    return projectStroke(scene, camera, strokePx, options);
}

}  // namespace vsculpt::render
