// SPDX-License-Identifier: MIT
#include "vsculpt/devices/XrBindings.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace vsculpt::devices {

const char* xrActionName(XrActionId id) {
    switch (id) {
        case XrActionId::PenPose:
            return "pen_pose";
        case XrActionId::PenTrigger:
            return "pen_trigger";
        case XrActionId::PenHaptic:
            return "pen_haptic";
        case XrActionId::Undo:
            return "undo";
        case XrActionId::MousePose:
            return "mouse_pose";
        case XrActionId::MouseGrip:
            return "mouse_grip";
        case XrActionId::CycleTool:
            return "cycle_tool";
        case XrActionId::Step:
            return "step";
        case XrActionId::Overview:
            return "overview";
        case XrActionId::PenStickX:
            return "pen_stick_x";
        case XrActionId::PenStickY:
            return "pen_stick_y";
        case XrActionId::MouseStickY:
            return "mouse_stick_y";
    }
    return "?";
}

XrActionKind xrActionKind(XrActionId id) {
    switch (id) {
        case XrActionId::PenPose:
        case XrActionId::MousePose:
            return XrActionKind::Pose;
        case XrActionId::PenTrigger:
        case XrActionId::PenStickX:
        case XrActionId::PenStickY:
        case XrActionId::MouseStickY:
            return XrActionKind::Float;
        case XrActionId::PenHaptic:
            return XrActionKind::Vibration;
        default:
            return XrActionKind::Boolean;
    }
}

const std::vector<XrProfileBindings>& xrSuggestedBindings() {
    using A = XrActionId;
    // Every profile gets the poses and the haptic output; buttons differ. A runtime binds a
    // float input (squeeze/value) to a boolean action with its own threshold, and a click to
    // the float trigger as 0 or 1 (simple controller).
    static const std::vector<XrProfileBindings> table = [] {
        const std::string r = "/user/hand/right/", l = "/user/hand/left/";
        auto common = [&](std::vector<XrSuggestedBinding> extra) {
            std::vector<XrSuggestedBinding> b = {{A::PenPose, r + "input/aim/pose"},
                                                 {A::PenHaptic, r + "output/haptic"},
                                                 {A::MousePose, l + "input/grip/pose"}};
            b.insert(b.end(), extra.begin(), extra.end());
            return b;
        };
        return std::vector<XrProfileBindings>{
            {"/interaction_profiles/valve/index_controller",
             common({{A::PenTrigger, r + "input/trigger/value"},
                     {A::Undo, r + "input/b/click"},
                     {A::MouseGrip, l + "input/squeeze/value"},
                     {A::CycleTool, l + "input/a/click"},
                     {A::Step, l + "input/b/click"},
                     {A::Overview, l + "input/thumbstick/click"},
                     {A::PenStickX, r + "input/thumbstick/x"},
                     {A::PenStickY, r + "input/thumbstick/y"},
                     {A::MouseStickY, l + "input/thumbstick/y"}})},
            {"/interaction_profiles/oculus/touch_controller",
             common({{A::PenTrigger, r + "input/trigger/value"},
                     {A::Undo, r + "input/b/click"},
                     {A::MouseGrip, l + "input/squeeze/value"},
                     {A::CycleTool, l + "input/x/click"},
                     {A::Step, l + "input/y/click"},
                     {A::Overview, l + "input/thumbstick/click"},
                     {A::PenStickX, r + "input/thumbstick/x"},
                     {A::PenStickY, r + "input/thumbstick/y"},
                     {A::MouseStickY, l + "input/thumbstick/y"}})},
            {"/interaction_profiles/htc/vive_controller",
             common({{A::PenTrigger, r + "input/trigger/value"},
                     {A::Undo, r + "input/menu/click"},
                     {A::MouseGrip, l + "input/squeeze/click"},
                     {A::CycleTool, l + "input/menu/click"},
                     {A::Step, l + "input/trackpad/click"}})},
            // Two buttons a hand: select is the trigger and the grip, menu cycles the tool.
            {"/interaction_profiles/khr/simple_controller",
             common({{A::PenTrigger, r + "input/select/click"},
                     {A::Undo, r + "input/menu/click"},
                     {A::MouseGrip, l + "input/select/click"},
                     {A::CycleTool, l + "input/menu/click"}})},
        };
    }();
    return table;
}

glm::dmat4 matrixFromXrPose(const glm::dvec3& position, const glm::dquat& orientation) {
    glm::dmat4 m = glm::mat4_cast(glm::normalize(orientation));
    m[3] = glm::dvec4(position, 1.0);
    return m;
}

glm::dmat4 projectionFromXrFov(double angleLeft, double angleRight, double angleUp,
                               double angleDown, double nearZ, double farZ) {
    const double l = std::tan(angleLeft), r = std::tan(angleRight);
    const double u = std::tan(angleUp), d = std::tan(angleDown);
    return glm::frustum(l * nearZ, r * nearZ, d * nearZ, u * nearZ, nearZ, farZ);
}

namespace {
// Local (y up, -z ahead) to world (z up, +y ahead): +90 degrees about x.
const glm::dmat4 kWorldAxesFromLocal(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, 1, 0),
                                     glm::dvec4(0, -1, 0, 0), glm::dvec4(0, 0, 0, 1));
}  // namespace

glm::dmat4 worldFromXrLocal(const glm::dvec3& sculptureInLocalM) {
    return glm::scale(glm::dmat4(1.0), glm::dvec3(1000.0)) * kWorldAxesFromLocal *
           glm::translate(glm::dmat4(1.0), -sculptureInLocalM);
}

glm::dmat4 worldPoseFromXrLocal(const glm::dmat4& localFromX, const glm::dvec3& sculptureInLocalM) {
    glm::dmat4 m = kWorldAxesFromLocal * localFromX;
    m[3] = glm::dvec4(glm::dvec3(worldFromXrLocal(sculptureInLocalM) * localFromX[3]), 1.0);
    return m;
}

}  // namespace vsculpt::devices
