// SPDX-License-Identifier: MIT
/// @file XrPanelUi.h
/// @brief The headset's panel (docs/xr.md): the status and the palette, drawn with Dear ImGui
/// into the image of the quad layer beside the sculpture, clicked by pointing the pen at it
/// and pulling its trigger, as VR applications' panels are.
#pragma once

#include "vsculpt/app/WindowUi.h"
#include "vsculpt/app/XrInput.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/devices/XrHeadset.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vsculpt::render {
class UiLayer;
class Viewer;
}  // namespace vsculpt::render

namespace vsculpt::app {

/// The panel's pose in the studio's world (rigid, mm): where the quad layer sits in OpenXR's
/// local space, mapped as the controllers are (handsInWorld). Its face looks along +z, +x is
/// its image's right and +y its image's up.
glm::dmat4 worldFromPanel(const devices::XrPanel& panel, const core::XrConfig& cfg);
/// The panel's width and height in mm (the height follows the image's aspect, as the quad
/// layer's does).
glm::dvec2 panelSizeMm(const devices::XrPanel& panel);

/// Where a ray meets the panel: in the panel image's pixels (top-left origin) and in the
/// world (mm).
struct PanelHit {
    glm::dvec2 pixel{0.0};
    glm::dvec3 world{0.0};
};
/// Where the pen's pointing ray (from its aim pose's origin along its -z) meets the panel's
/// face; nullopt when it misses the panel or meets it from behind.
std::optional<PanelHit> panelHitAt(const glm::dmat4& worldFromPen, const glm::dmat4& worldFromPanel,
                                   const glm::dvec2& sizeMm, int widthPx, int heightPx);

class XrPanelUi {
  public:
    /// Draws with `viewer`'s GL context, which must be current for every call and outlive
    /// this object. `uiScale`: render.ui_scale (the panel's text is 1.5 times the window's).
    /// Throws render::RenderError when the UI renderer cannot start.
    XrPanelUi(render::Viewer& viewer, const devices::XrPanel& panel, const core::XrConfig& cfg,
              float uiScale);
    ~XrPanelUi();
    XrPanelUi(const XrPanelUi&) = delete;
    XrPanelUi& operator=(const XrPanelUi&) = delete;

    /// Once a frame, before XrInput::handle: where the pen points. `penFree`: the pen is not
    /// sculpting and its tool is in the air, so its trigger may click the panel. Returns true
    /// when the panel has the trigger this frame (the caller hands XrInput a trigger of 0):
    /// the pen points at the panel, or a press that began there is still held. The trigger
    /// presses at render.xr.trigger_threshold and releases below 80 % of it, as it engages
    /// the tool.
    bool point(const XrHands& hands, bool penFree);
    /// Where the pen pointed at the last point(), in the image's pixels.
    std::optional<glm::dvec2> pointer() const {
        return mHit ? std::optional<glm::dvec2>(mHit->pixel) : std::nullopt;
    }
    /// The button under the pen ("button:carve", the key of UiState::rects), or empty.
    const std::string& hoveredButton() const { return mHovered; }
    /// The pen came onto a button at the last point() (another one, or from none): the frame
    /// for a haptic tick, as VR panels give.
    bool enteredButton() const { return mEntered; }
    /// The same in the world (mm): where the pen's ray, drawn in the eyes, ends.
    std::optional<glm::dvec3> pointerWorld() const {
        return mHit ? std::optional<glm::dvec3>(mHit->world) : std::nullopt;
    }

    /// Draws the panel's image for this frame (headsetUi) and returns the buttons clicked.
    /// `hands`: what the controllers are doing, for the status line. `dtS`: seconds since
    /// the last frame.
    std::vector<UiAction> draw(const SculptUiView& view, const std::string& hands, double dtS);
    /// The image draw() made (a GL texture of widthPx x heightPx, for the quad layer).
    unsigned texture() const { return mTexture; }
    /// Last frame's panels and buttons (UiState::rects), for tests to aim at.
    const UiState& state() const { return mState; }

  private:
    std::unique_ptr<render::UiLayer> mUi;
    devices::XrPanel mPanel;
    core::XrConfig mCfg;
    glm::dmat4 mWorldFromPanel;
    glm::dvec2 mSizeMm;
    UiState mState;
    std::optional<PanelHit> mHit;
    bool mPressed = false;  // the trigger went down on the panel and is still held
    std::string mHovered;   // the button under the pen, from the last frame's layout
    bool mEntered = false;
    unsigned mTexture = 0;
};

}  // namespace vsculpt::app
