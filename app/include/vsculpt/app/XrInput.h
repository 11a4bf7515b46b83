// SPDX-License-Identifier: MIT
/// @file XrInput.h
/// @brief OpenXR controllers -> sculpting, the thesis's two hands (docs/xr.md), mirroring
/// DeviceInput for the libusb devices:
///   - right hand = the pen: its aim pose places the tool (pen_tip_mm ahead), the trigger
///     engages it (add/carve while moving); with trigger_penetration_mm the trigger's value
///     pushes the tool further along the pen;
///   - left hand = the 3D mouse: while the grip is held the sculpture follows the hand (grab,
///     move and turn); its buttons cycle the tool, step the size (zoom with the select tool)
///     and go back to the overview; the pen hand's second button undoes;
///   - direct jumps: the pen hand's thumbstick pushed left / up / right jumps to the smallest /
///     middle / largest size the zoom offers, down redoes; the 3D-mouse hand's thumbstick up
///     zooms in one level at the tool, down zooms out.
/// Pure of OpenXR: it takes poses already in the studio's world (XrHands), so tests drive it
/// without a runtime.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/devices/XrHeadset.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/PickTool.h"
#include "vsculpt/studio/Studio.h"

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace vsculpt::app {

/// The trigger lets go below this fraction of render.xr.trigger_threshold (it engages at
/// the threshold): a trigger held at the threshold does not chatter.
inline constexpr double kTriggerRelease = 0.8;

/// One frame of the controllers in the studio's world: rigid poses in mm (nullopt: not
/// tracked); buttons as XrControllers (true in the frame they went down).
struct XrHands {
    std::optional<glm::dmat4> worldFromPen, worldFromMouse;
    float trigger = 0;
    bool grip = false;
    bool undo = false, cycleTool = false, step = false, overview = false;
    /// Thumbsticks, -1..1: the pen hand's (direct size jumps, redo) and the 3D-mouse hand's y
    /// (zoom in and out at the tool).
    float penStickX = 0, penStickY = 0, mouseStickY = 0;
    /// A button clicked on the headset's panel this frame (SculptAction.h: "tool_carve",
    /// "mirror_x", "size_3", "undo", ...), or empty. While the pen points at the panel its
    /// trigger clicks there: the frame loop hands XrInput a trigger of 0 (XrPanelUi.h).
    std::string panelAction;
};

/// The controllers of one sync mapped from OpenXR's local space into the world (XrBindings.h,
/// worldPoseFromXrLocal with the config's sculpture placement).
XrHands handsInWorld(const devices::XrControllers& c, const core::XrConfig& cfg);

/// One frame of hands as a device report, for recordings (driver "openxr", docs/xr.md):
/// a flags byte (bit 0 pen tracked, 1 3D-mouse hand tracked, 2 grip, 3 undo, 4 cycle tool,
/// 5 step, 6 overview, 7 thumbsticks follow), the trigger as a float, then for each tracked
/// hand its pose's first three rows (12 doubles, column by column), then (bit 7) the three
/// thumbstick floats, then, when a panel button was clicked, a length byte and the action's
/// name; little-endian. Lossless: a replay maps exactly what the live run did.
/// Reports without bit 7 (recorded before the thumbsticks) still parse.
std::vector<uint8_t> xrHandsReport(const XrHands& hands);
/// nullopt for a report of the wrong length or whose panel action is not a sculpting action.
std::optional<XrHands> parseXrHandsReport(std::span<const uint8_t> bytes);

/// The tool centre for a pen pose: pen_tip_mm ahead of it along its -z, and with
/// trigger_penetration_mm, the trigger's value times that further.
core::Vec3 penToolWorld(const glm::dmat4& worldFromPen, float trigger, const core::XrConfig& cfg);

/// The haptic amplitude for a contact: 0 in the air, haptic_touching, haptic_inside.
double hapticAmplitude(studio::ToolContact contact, const core::XrConfig& cfg);

class XrInput {
  public:
    /// `interaction` and `studio` must outlive this object.
    XrInput(const core::XrConfig& cfg, studio::Interaction& interaction, studio::Studio& studio);

    /// Applies one frame. Refused commands (nothing to undo, a sample the lattice cannot
    /// hold) are logged, never thrown.
    void handle(const XrHands& hands);
    /// The last refused command's message ("undo: nothing to undo"), once: the headset's
    /// panel shows it, as the window's status shows its own.
    std::optional<std::string> takeRefusal() { return std::exchange(mRefusal, std::nullopt); }

    /// Where the pen put the tool last (world mm); nullopt before the pen was tracked.
    std::optional<core::Vec3> toolWorld() const { return mTool; }
    bool engaged() const { return mEngaged; }
    bool grabbing() const { return mHandFromObject.has_value(); }
    /// Which way a thumbstick was pushed this frame, as a jump: a direction fires once when
    /// the stick passes 0.8 and re-arms when it comes back under 0.5.
    enum class Push { None, Left, Up, Right, Down };

  private:
    core::XrConfig mCfg;
    studio::Interaction& mInteraction;
    studio::Studio& mStudio;
    std::optional<core::Vec3> mTool;
    bool mEngaged = false;
    // The sculpture's pose in the grabbing hand's frame, fixed when the grip closes (so
    // grabbing does not make the sculpture jump).
    std::optional<core::RigidTransform> mHandFromObject;
    bool mPenStickArmed = true, mMouseStickArmed = true;
    std::optional<std::string> mRefusal;
};

}  // namespace vsculpt::app
