// SPDX-License-Identifier: MIT
/// @file XrBindings.h
/// @brief The pure side of the OpenXR path (docs/xr.md): which controller input drives which
/// of the thesis's two hands, per interaction profile (the suggested bindings), and the math
/// from OpenXR's poses and fields of view to glm. No OpenXR calls here: unit-testable
/// without a runtime. OpenXR is metres, y up; the caller maps that into the studio's world.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

#include <string>
#include <vector>

namespace vsculpt::devices {

/// The actions vsculpt creates. Right hand = the pen, left hand = the 3D mouse.
enum class XrActionId {
    PenPose,     ///< pose: the right hand's aim pose (the pen tip lies along its -z)
    PenTrigger,  ///< float: engages the tool; its value may scale the penetration
    PenHaptic,   ///< vibration: contact feedback on the pen hand
    Undo,        ///< boolean, right hand
    MousePose,   ///< pose: the left hand's grip pose (what grabs the sculpture)
    MouseGrip,   ///< boolean: held, the sculpture follows the left hand (grab and turn)
    CycleTool,   ///< boolean: the thesis's right 3D-mouse button (add -> carve -> ...)
    Step,        ///< boolean: the thesis's left 3D-mouse button (size step / zoom step)
    Overview,    ///< boolean: back to zoom 1
    /// float: the pen hand's thumbstick x and y, and the 3D-mouse hand's thumbstick y (direct
    /// jumps: size by direction, zoom in and out; docs/xr.md)
    PenStickX,
    PenStickY,
    MouseStickY,
};
inline constexpr int kXrActionCount = 12;

/// The action's OpenXR name (lower case, as xrCreateAction wants) and its kind.
const char* xrActionName(XrActionId id);
enum class XrActionKind { Pose, Float, Boolean, Vibration };
XrActionKind xrActionKind(XrActionId id);

struct XrSuggestedBinding {
    XrActionId action;
    std::string path;  ///< e.g. "/user/hand/right/input/trigger/value"
};

struct XrProfileBindings {
    std::string profile;  ///< e.g. "/interaction_profiles/valve/index_controller"
    std::vector<XrSuggestedBinding> bindings;
};

/// The suggested bindings for Valve Index, Oculus Touch, HTC Vive wands and the Khronos
/// simple controller (docs/xr.md has the same table for people).
const std::vector<XrProfileBindings>& xrSuggestedBindings();

/// A rigid transform (metres) from an OpenXR pose: position and orientation (x, y, z, w).
glm::dmat4 matrixFromXrPose(const glm::dvec3& position, const glm::dquat& orientation);

/// An OpenGL projection (clip z in [-1, 1]) from an OpenXR field of view (radians; left and
/// down are negative for a symmetric view), looking down -z.
glm::dmat4 projectionFromXrFov(double angleLeft, double angleRight, double angleUp,
                               double angleDown, double nearZ, double farZ);

/// OpenXR's local space (metres, y up, -z ahead) into the studio's world (mm, z up, the user
/// at -y looking +y), with the sculpture's origin at `sculptureInLocalM`: rotation +90 degrees
/// about x, scale 1000, the sculpture's point to the world origin.
glm::dmat4 worldFromXrLocal(const glm::dvec3& sculptureInLocalM);

/// The same without the scale, for poses: a rigid local pose (metres) into a rigid world pose
/// in mm (rotation mapped, translation scaled), so lighting and picking see a rigid transform.
glm::dmat4 worldPoseFromXrLocal(const glm::dmat4& localFromX, const glm::dvec3& sculptureInLocalM);

}  // namespace vsculpt::devices
