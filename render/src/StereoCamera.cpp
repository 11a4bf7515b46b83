// SPDX-License-Identifier: MIT
#include "vsculpt/render/StereoCamera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vsculpt::render {

std::array<EyeView, 2> stereoEyes(const glm::dmat4& worldFromHead, const StereoDisplay& d) {
    if (!(d.ipdMm >= 0 && d.focalDistanceMm > 0 && d.verticalFovDeg > 0 && d.verticalFovDeg < 180 &&
          d.aspect > 0 && d.nearMm > 0 && d.farMm > d.nearMm))
        throw std::invalid_argument("stereo display description out of range");
    std::array<EyeView, 2> eyes;
    const double top = d.nearMm * std::tan(glm::radians(d.verticalFovDeg) * 0.5);
    const double halfWidth = top * d.aspect;
    for (int i = 0; i < 2; ++i) {
        // Left eye at -ipd/2 along the head's x axis, right eye at +ipd/2.
        const double offset = (i == 0 ? -0.5 : 0.5) * d.ipdMm;
        const glm::dmat4 worldFromEye =
            worldFromHead * glm::translate(glm::dmat4(1.0), glm::dvec3(offset, 0, 0));
        // Shift each frustum towards the centre so both frame the same window at the focal
        // distance (the zero-parallax plane), instead of toeing the eyes in.
        const double shift = -offset * d.nearMm / d.focalDistanceMm;
        EyeView& e = eyes[size_t(i)];
        e.viewFromWorld = glm::inverse(worldFromEye);
        e.clipFromView =
            glm::frustum(-halfWidth + shift, halfWidth + shift, -top, top, d.nearMm, d.farMm);
        e.worldPosition = glm::dvec3(worldFromEye[3]);
    }
    return eyes;
}

double eyeShiftNdc(const StereoDisplay& d, double depthMm, Eye eye) {
    if (!(depthMm > 0) || d.ipdMm <= 0) return 0;
    // The eye at offset o sees a point on the head's axis at depth Z through the zero-parallax
    // window (half-width F tan(fov/2) aspect at distance F) at o (1 - F / Z).
    const double offset = (eye == Eye::Left ? -0.5 : 0.5) * d.ipdMm;
    const double halfWidth =
        d.focalDistanceMm * std::tan(glm::radians(d.verticalFovDeg) * 0.5) * d.aspect;
    return offset * (1 - d.focalDistanceMm / depthMm) / halfWidth;
}

glm::dmat4 frameFromFront(const glm::dvec3& boxMin, const glm::dvec3& boxMax, double aspect,
                          StereoDisplay& d, FrameFit fit) {
    const bool empty = boxMin.x > boxMax.x;
    const glm::dvec3 center = empty ? glm::dvec3(0) : 0.5 * (boxMin + boxMax);
    const double radius = empty ? 50.0 : std::max(1.0, 0.5 * glm::length(boxMax - boxMin));
    if (!(d.verticalFovDeg > 0 && d.verticalFovDeg < 180)) d.verticalFovDeg = 40;
    d.aspect = aspect;
    double distance;
    if (fit == FrameFit::Box && !empty) {
        // The box's front face is the nearest to the eye, so it spreads widest in the
        // picture: its corners at depth distance - h.y must lie within the picture shrunk by
        // the margin, sideways (tan of the half angle times the aspect) and up and down.
        constexpr double kInside = 0.92;  // 4 % of the picture's size left at each side
        const glm::dvec3 h = 0.5 * (boxMax - boxMin);
        const double tanUp = std::tan(glm::radians(d.verticalFovDeg) * 0.5);
        distance = h.y + std::max({h.x / (kInside * tanUp * aspect), h.z / (kInside * tanUp), 1.0});
    } else {
        const double halfFov = glm::radians(d.verticalFovDeg) * 0.5 * std::min(1.0, aspect);
        distance = 1.1 * radius / std::sin(halfFov);
    }
    d.focalDistanceMm = distance;
    d.nearMm = std::max(1.0, distance - 2 * radius);
    d.farMm = distance + 2 * radius;
    glm::dmat4 worldFromHead(1.0);
    worldFromHead[0] = glm::dvec4(1, 0, 0, 0);   // head x: world x
    worldFromHead[1] = glm::dvec4(0, 0, 1, 0);   // head up: world z
    worldFromHead[2] = glm::dvec4(0, -1, 0, 0);  // head looks down -z: world +y
    worldFromHead[3] = glm::dvec4(center - glm::dvec3(0, distance, 0), 1);
    return worldFromHead;
}

glm::dvec3 projectToNdc(const EyeView& eye, const glm::dvec3& p) {
    const glm::dvec4 clip = eye.clipFromView * eye.viewFromWorld * glm::dvec4(p, 1.0);
    return glm::dvec3(clip) / clip.w;
}

}  // namespace vsculpt::render
