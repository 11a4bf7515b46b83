// SPDX-License-Identifier: MIT
/// @file StereoCamera.h
/// @brief Per-eye view and projection matrices for stereo display (headset or desktop), by
/// the off-axis (asymmetric frustum) method: both eyes share one zero-parallax plane, so
/// objects on it appear at the same place in both images, nearer ones with crossed parallax
/// and farther ones uncrossed. Units: millimetres; frames: head (x right, y up, looking
/// down -z), world. OpenGL clip conventions (right-handed view, NDC z in [-1, 1]).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>

namespace vsculpt::render {

struct StereoDisplay {
    double ipdMm = 63.0;             ///< interpupillary distance
    double focalDistanceMm = 600.0;  ///< distance of the zero-parallax plane from the eyes
    double verticalFovDeg = 45.0;    ///< per-eye vertical field of view
    double aspect = 1.0;             ///< per-eye image width / height
    double nearMm = 10.0, farMm = 10000.0;
};

struct EyeView {
    glm::dmat4 viewFromWorld{1.0};
    glm::dmat4 clipFromView{1.0};
    glm::dvec3 worldPosition{0.0};  ///< the eye's centre in the world
};

enum class Eye { Left = 0, Right = 1 };

/// The two eyes for a head pose. `worldFromHead` places the head (the point between the
/// eyes) in the world. A mono view is the same with ipdMm = 0.
std::array<EyeView, 2> stereoEyes(const glm::dmat4& worldFromHead, const StereoDisplay& display);

/// What frameFromFront fits into the view.
enum class FrameFit {
    /// The box's bounding sphere, with a tenth to spare: the windows, where the sculpture
    /// turns in the view and must stay in it at every angle.
    Sphere,
    /// The box as seen from the front, its outline 4 % inside the picture's nearer edges:
    /// stills, where the sculpture should fill the picture.
    Box,
};

/// The head pose and display that frame a box from the front (-y looking +y, z up), fitted
/// as `fit` says, with the zero-parallax plane through its centre. `display` keeps its IPD
/// and field of view; aspect, focal distance and clip planes are set.
glm::dmat4 frameFromFront(const glm::dvec3& boxMin, const glm::dvec3& boxMax, double aspect,
                          StereoDisplay& display, FrameFit fit = FrameFit::Sphere);

/// How far (in the eye's NDC x, image width = 2) a point straight ahead of the head at
/// `depthMm` from the eyes is drawn away from where a mono camera would draw it, in `eye`'s
/// image: the horizontal disparity of a flat overlay (the on-screen UI) placed at that depth.
/// 0 on the zero-parallax plane (depth = display.focalDistanceMm) or with no IPD; positive
/// (rightwards) in the left eye for depths nearer than the plane (crossed parallax).
double eyeShiftNdc(const StereoDisplay& display, double depthMm, Eye eye);

/// Where a world point lands in an eye's normalised device coordinates (x, y in [-1, 1] on
/// screen, z depth).
glm::dvec3 projectToNdc(const EyeView& eye, const glm::dvec3& worldPoint);

}  // namespace vsculpt::render
