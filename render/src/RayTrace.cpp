// SPDX-License-Identifier: MIT
#include "vsculpt/render/RayTrace.h"

#include "vsculpt/render/StereoCamera.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <random>

namespace vsculpt::render {

using core::Vec3;

struct RayScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<Vec3> normals;  // per triangle, unit, outward by winding
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

RayScene::RayScene(const core::Mesh& mesh) : mImpl(std::make_unique<Impl>()) {
    mImpl->device = rtcNewDevice(nullptr);
    if (!mImpl->device) throw RenderError("Embree: cannot create a device");
    mImpl->scene = rtcNewScene(mImpl->device);
    // Robust traversal and intersection: without it a primary ray slips through the shared
    // edge of two triangles now and then (Embree's fast path is not watertight), sees the
    // inside of the far wall or the background, and the still gets isolated dark speckles
    // along the polygonizer's sliver triangles. Measured: docs/benchmarks.md (render).
    rtcSetSceneFlags(mImpl->scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(mImpl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          mesh.positions.size()));
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        for (int a = 0; a < 3; ++a)
            v[3 * i + a] = float(mesh.positions[i][a]);
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangleCount()));
    std::copy(mesh.indices.begin(), mesh.indices.end(), idx);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(mImpl->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(mImpl->scene);
    if (rtcGetDeviceError(mImpl->device) != RTC_ERROR_NONE)
        throw RenderError("Embree: scene build failed");
    mImpl->normals.resize(mesh.triangleCount());
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3 a = mesh.positions[mesh.indices[3 * t]],
                   b = mesh.positions[mesh.indices[3 * t + 1]],
                   c = mesh.positions[mesh.indices[3 * t + 2]];
        const Vec3 n = glm::cross(b - a, c - a);
        const double l = glm::length(n);
        mImpl->normals[t] = l > 0 ? n / l : Vec3(0, 0, 1);
    }
}

RayScene::~RayScene() = default;

std::optional<RayHit> RayScene::intersect(const Vec3& o, const Vec3& dirIn, double tNear,
                                          double tFar) const {
    const Vec3 dir = glm::normalize(dirIn);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray.org_x = float(o.x);
    rh.ray.org_y = float(o.y);
    rh.ray.org_z = float(o.z);
    rh.ray.dir_x = float(dir.x);
    rh.ray.dir_y = float(dir.y);
    rh.ray.dir_z = float(dir.z);
    rh.ray.tnear = float(tNear);
    rh.ray.tfar = float(std::min(tFar, double(std::numeric_limits<float>::max())));
    rh.ray.mask = 0xFFFFFFFF;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(mImpl->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    RayHit hit;
    hit.t = rh.ray.tfar;
    hit.triangle = rh.hit.primID;
    hit.position = o + dir * hit.t;
    const Vec3 n = mImpl->normals[hit.triangle];
    hit.normal = glm::dot(n, dir) < 0 ? n : -n;
    return hit;
}

bool RayScene::occluded(const Vec3& o, const Vec3& dirIn, double tNear, double tFar) const {
    const Vec3 dir = glm::normalize(dirIn);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray{};
    ray.org_x = float(o.x);
    ray.org_y = float(o.y);
    ray.org_z = float(o.z);
    ray.dir_x = float(dir.x);
    ray.dir_y = float(dir.y);
    ray.dir_z = float(dir.z);
    ray.tnear = float(tNear);
    ray.tfar = float(tFar);
    ray.mask = 0xFFFFFFFF;
    rtcOccluded1(mImpl->scene, &ctx, &ray);
    return ray.tfar < 0;  // Embree sets tfar = -inf on a hit
}

Image rayTrace(const core::Mesh& mesh, const RayTraceOptions& o) {
    if (o.width < kMinImageSide || o.height < kMinImageSide || o.width > kMaxImageSide ||
        o.height > kMaxImageSide)
        throw RenderError("image size must be between " + std::to_string(kMinImageSide) + " and " +
                          std::to_string(kMaxImageSide) + " pixels per side");
    const RayScene scene(mesh);
    const core::Aabb box = o.frameBox ? *o.frameBox : core::meshBounds(mesh);
    StereoDisplay d;
    d.ipdMm = 0;
    const glm::dmat4 worldFromHead =
        frameFromFront(box.min, box.max, double(o.width) / o.height, d, o.fit);
    const EyeView eye = stereoEyes(worldFromHead, d)[0];
    const glm::dmat4 worldFromClip = glm::inverse(eye.clipFromView * eye.viewFromWorld);
    const double radius = box.empty() ? 50 : 0.5 * glm::length(box.max - box.min);
    const double aoReach = 0.3 * radius;
    // An area light above, left and in front of the sculpture.
    const Vec3 center = box.empty() ? Vec3(0) : 0.5 * (box.min + box.max);
    const Vec3 lightCenter = center + Vec3(-2.0, -1.2, 1.6) * radius;
    const double lightRadius = 0.35 * radius;

    Image img;
    img.width = o.width;
    img.height = o.height;
    img.rgba.resize(size_t(o.width) * o.height * 4);
    std::atomic<int> rowsDone{0};
    std::mutex progressMutex;
    int rowsReported = 0;  // guarded by progressMutex: reports only ever go up
    tbb::parallel_for(0, o.height, [&](int y) {
        std::mt19937 rng(o.seed * 2654435761u + unsigned(y));
        std::uniform_real_distribution<double> U(0, 1);
        // Each pixel is the mean of a 2x2 stratified grid of jittered primary rays, the AO and
        // shadow rays shared out among them: silhouettes and thin shadow bands are
        // antialiased instead of one ray deciding the whole pixel, at about the same cost.
        const int aoPer = o.aoSamples > 0 ? std::max(1, (o.aoSamples + 3) / 4) : 0;
        const int shadowPer = std::max(1, (o.shadowSamples + 3) / 4);
        for (int x = 0; x < o.width; ++x) {
            uint8_t* px = &img.rgba[(size_t(y) * o.width + x) * 4];
            double sum[3] = {0, 0, 0};  // linear colour
            for (int sub = 0; sub < 4; ++sub) {
                const double sx = x + (0.5 * (sub & 1) + 0.5 * U(rng)),
                             sy = y + (0.5 * (sub >> 1) + 0.5 * U(rng));
                // Through the same projection as the raster shot.
                const double nx = sx / o.width * 2 - 1, ny = 1 - sy / o.height * 2;
                const glm::dvec4 pn = worldFromClip * glm::dvec4(nx, ny, -1, 1);
                const glm::dvec4 pf = worldFromClip * glm::dvec4(nx, ny, 1, 1);
                const Vec3 origin = Vec3(pn) / pn.w, dir = glm::normalize(Vec3(pf) / pf.w - origin);
                const auto hit = scene.intersect(origin, dir);
                if (!hit) {
                    for (int c = 0; c < 3; ++c)
                        sum[c] += std::pow(kBackground[c] / 255.0, 2.2);
                    continue;
                }
                const Vec3 n = hit->normal;
                const Vec3 p = hit->position + n * (1e-3 * radius);
                // Ambient occlusion: cosine-weighted hemisphere rays.
                const Vec3 t1 = glm::normalize(
                    glm::cross(n, std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
                const Vec3 t2 = glm::cross(n, t1);
                int open = 0;
                for (int s = 0; s < aoPer; ++s) {
                    const double r = std::sqrt(U(rng)), phi = 2 * std::numbers::pi * U(rng);
                    const Vec3 w = t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) +
                                   n * std::sqrt(std::max(0.0, 1 - r * r));
                    open += !scene.occluded(p, w, 0, aoReach);
                }
                const double ao = aoPer > 0 ? double(open) / aoPer : 1.0;
                // Soft shadow: rays to random points of the light's disc.
                double lit = 0;
                const Vec3 toLight = glm::normalize(lightCenter - p);
                const double lambert = std::max(0.0, glm::dot(n, toLight));
                if (lambert > 0) {
                    const Vec3 l1 =
                        glm::normalize(glm::cross(toLight, Vec3(0, 0, 1) + Vec3(1e-6, 0, 0)));
                    const Vec3 l2 = glm::cross(toLight, l1);
                    int visible = 0;
                    for (int s = 0; s < shadowPer; ++s) {
                        const double r = lightRadius * std::sqrt(U(rng)),
                                     phi = 2 * std::numbers::pi * U(rng);
                        const Vec3 q =
                            lightCenter + l1 * (r * std::cos(phi)) + l2 * (r * std::sin(phi));
                        visible += !scene.occluded(p, q - p, 0, glm::length(q - p));
                    }
                    lit = lambert * double(visible) / shadowPer;
                }
                const double headlight = std::max(0.0, -glm::dot(n, dir));
                const double g =
                    std::clamp(0.02 + 0.22 * ao + 0.45 * lit + 0.06 * headlight, 0.0, 1.0);
                for (double& c : sum)
                    c += g;
            }
            for (int c = 0; c < 3; ++c)
                px[c] = uint8_t(std::lround(255 * std::pow(sum[c] / 4, 1 / 2.2)));
            px[3] = 255;
        }
        const int done = ++rowsDone;
        if (o.progress) {
            // A busy reporter skips this row's report, except the last one: never wait here.
            std::unique_lock lock(progressMutex, std::defer_lock);
            if (done == o.height)
                lock.lock();
            else if (!lock.try_lock())
                return;
            const int now = rowsDone.load();
            if (now > rowsReported) {
                rowsReported = now;
                o.progress(now);
            }
        }
    });
    return img;
}

}  // namespace vsculpt::render
