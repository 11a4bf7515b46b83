// SPDX-License-Identifier: MIT
#include "vsculpt/app/XrPanelUi.h"

#include "vsculpt/devices/XrBindings.h"
#include "vsculpt/render/UiLayer.h"
#include "vsculpt/render/Viewer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // mouse button codes only

#include <glm/gtc/quaternion.hpp>

#include <algorithm>

namespace vsculpt::app {

glm::dmat4 worldFromPanel(const devices::XrPanel& panel, const core::XrConfig& cfg) {
    glm::dmat4 localFromPanel = glm::mat4_cast(glm::normalize(panel.orientation));
    localFromPanel[3] = glm::dvec4(panel.positionM, 1.0);
    return devices::worldPoseFromXrLocal(localFromPanel, cfg.sculptureInLocalM);
}

glm::dvec2 panelSizeMm(const devices::XrPanel& panel) {
    const double w = panel.widthM * 1000.0;
    return {w, w * panel.heightPx / std::max(1, panel.widthPx)};
}

std::optional<PanelHit> panelHitAt(const glm::dmat4& worldFromPen, const glm::dmat4& worldFromPanel,
                                   const glm::dvec2& sizeMm, int widthPx, int heightPx) {
    const glm::dvec3 origin(worldFromPen[3]);
    const glm::dvec3 dir = -glm::normalize(glm::dvec3(worldFromPen[2]));
    const glm::dvec3 centre(worldFromPanel[3]);
    const glm::dvec3 right = glm::normalize(glm::dvec3(worldFromPanel[0]));
    const glm::dvec3 up = glm::normalize(glm::dvec3(worldFromPanel[1]));
    const glm::dvec3 face = glm::normalize(glm::dvec3(worldFromPanel[2]));
    // Only towards the face: a ray parallel to the panel, or meeting it from behind, misses.
    const double towards = glm::dot(dir, face);
    if (towards >= -1e-9) return std::nullopt;
    const double t = glm::dot(centre - origin, face) / towards;
    if (t <= 0) return std::nullopt;
    const glm::dvec3 world = origin + t * dir, onPanel = world - centre;
    const double u = glm::dot(onPanel, right) / sizeMm.x + 0.5,
                 v = 0.5 - glm::dot(onPanel, up) / sizeMm.y;
    if (u < 0 || u >= 1 || v < 0 || v >= 1) return std::nullopt;
    return PanelHit{glm::dvec2(u * widthPx, v * heightPx), world};
}

XrPanelUi::XrPanelUi(render::Viewer& viewer, const devices::XrPanel& panel,
                     const core::XrConfig& cfg, float uiScale)
    : mUi(std::make_unique<render::UiLayer>(viewer)),
      mPanel(panel),
      mCfg(cfg),
      mWorldFromPanel(worldFromPanel(panel, cfg)),
      mSizeMm(panelSizeMm(panel)) {
    mUi->setScale(1.5f * uiScale);
}

XrPanelUi::~XrPanelUi() = default;

bool XrPanelUi::point(const XrHands& hands, bool penFree) {
    mHit.reset();
    if (hands.worldFromPen && (penFree || mPressed))
        mHit = panelHitAt(*hands.worldFromPen, mWorldFromPanel, mSizeMm, mPanel.widthPx,
                          mPanel.heightPx);
    mUi->setPointer(mHit ? mHit->pixel.x : -1, mHit ? mHit->pixel.y : -1);
    std::string hovered;
    if (mHit)
        for (const auto& [name, r] : mState.rects)
            if (name.rfind("button:", 0) == 0 && r.contains(mHit->pixel.x, mHit->pixel.y))
                hovered = name;
    mEntered = !hovered.empty() && hovered != mHovered;
    mHovered = std::move(hovered);
    const double t = mCfg.triggerThreshold;
    render::InputEvent button{render::InputEvent::Kind::MouseButton, GLFW_MOUSE_BUTTON_LEFT};
    if (mPressed) {
        // Held since it went down on the panel: the panel's until released, even when the
        // pen has wandered off it meanwhile (ImGui then clicks nothing).
        if (hands.trigger < kTriggerRelease * t || !hands.worldFromPen) {
            button.pressed = false;
            mUi->feed(button);
            mPressed = false;
        }
        return true;
    }
    if (!mHit) return false;
    if (hands.trigger >= t) {
        button.pressed = true;
        mUi->feed(button);
        mPressed = true;
    }
    return true;
}

std::vector<UiAction> XrPanelUi::draw(const SculptUiView& view, const std::string& hands,
                                      double dtS) {
    mUi->beginFrame(mPanel.widthPx, mPanel.heightPx, std::max(1e-3, dtS));
    std::vector<UiAction> actions = headsetUi(mState, view, hands, mPanel.widthPx, mPanel.heightPx);
    mTexture = mUi->endFrame().texture;
    return actions;
}

}  // namespace vsculpt::app
