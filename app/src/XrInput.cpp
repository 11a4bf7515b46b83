// SPDX-License-Identifier: MIT
#include "vsculpt/app/XrInput.h"

#include "vsculpt/app/DeviceInput.h"
#include "vsculpt/app/SculptAction.h"

#include "vsculpt/devices/XrBindings.h"
#include "vsculpt/studio/Session.h"

#include <spdlog/spdlog.h>

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

namespace vsculpt::app {

namespace {

// A thumbstick as a push: fires once past 0.8, re-armed under 0.5 (no repeats while held).
XrInput::Push stickPush(float x, float y, bool& armed) {
    const float r = std::hypot(x, y);
    if (r < 0.5f) armed = true;
    if (!armed || r < 0.8f) return XrInput::Push::None;
    armed = false;
    if (std::abs(x) > std::abs(y)) return x < 0 ? XrInput::Push::Left : XrInput::Push::Right;
    return y > 0 ? XrInput::Push::Up : XrInput::Push::Down;
}

core::RigidTransform rigidOf(const glm::dmat4& m) {
    core::RigidTransform t;
    t.rotation = glm::normalize(glm::quat_cast(glm::dmat3(m)));
    t.translation = core::Vec3(m[3]);
    return t;
}

void putU64(std::vector<uint8_t>& out, uint64_t v) {
    for (int i = 0; i < 8; ++i)
        out.push_back(uint8_t(v >> (8 * i)));
}

uint64_t getU64(std::span<const uint8_t> b, size_t at) {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i)
        v |= uint64_t(b[at + size_t(i)]) << (8 * i);
    return v;
}

constexpr size_t kPoseBytes = 12 * 8;

}  // namespace

std::vector<uint8_t> xrHandsReport(const XrHands& h) {
    std::vector<uint8_t> out;
    out.push_back(uint8_t((h.worldFromPen ? 1 : 0) | (h.worldFromMouse ? 2 : 0) | (h.grip ? 4 : 0) |
                          (h.undo ? 8 : 0) | (h.cycleTool ? 16 : 0) | (h.step ? 32 : 0) |
                          (h.overview ? 64 : 0) | 128));
    const auto trigger = std::bit_cast<uint32_t>(h.trigger);
    for (int i = 0; i < 4; ++i)
        out.push_back(uint8_t(trigger >> (8 * i)));
    for (const auto& pose : {h.worldFromPen, h.worldFromMouse})
        if (pose)
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 3; ++r)
                    putU64(out, std::bit_cast<uint64_t>((*pose)[c][r]));
    for (float v : {h.penStickX, h.penStickY, h.mouseStickY}) {
        const auto bits = std::bit_cast<uint32_t>(v);
        for (int i = 0; i < 4; ++i)
            out.push_back(uint8_t(bits >> (8 * i)));
    }
    if (!h.panelAction.empty()) {
        // Names are short ASCII words (SculptAction.h); a longer one is a caller's bug.
        if (h.panelAction.size() > 255)
            throw std::logic_error("xrHandsReport: panel action name of " +
                                   std::to_string(h.panelAction.size()) + " bytes");
        out.push_back(uint8_t(h.panelAction.size()));
        out.insert(out.end(), h.panelAction.begin(), h.panelAction.end());
    }
    return out;
}

std::optional<XrHands> parseXrHandsReport(std::span<const uint8_t> b) {
    if (b.size() < 5) return std::nullopt;
    const uint8_t f = b[0];
    const size_t poses = ((f & 1) ? 1 : 0) + ((f & 2) ? 1 : 0);
    const size_t sticks = (f & 0x80) ? 12 : 0;
    const size_t fixed = 5 + poses * kPoseBytes + sticks;
    // After the thumbsticks, optionally the panel's action: a length byte and its name.
    const size_t action = b.size() > fixed && sticks ? b[fixed] : 0;
    if (b.size() != fixed + (action ? 1 + action : 0)) return std::nullopt;
    XrHands h;
    h.grip = f & 4;
    h.undo = f & 8;
    h.cycleTool = f & 16;
    h.step = f & 32;
    h.overview = f & 64;
    uint32_t trigger = 0;
    for (int i = 0; i < 4; ++i)
        trigger |= uint32_t(b[size_t(1 + i)]) << (8 * i);
    h.trigger = std::bit_cast<float>(trigger);
    size_t at = 5;
    auto pose = [&] {
        glm::dmat4 m(1.0);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 3; ++r, at += 8)
                m[c][r] = std::bit_cast<double>(getU64(b, at));
        return m;
    };
    if (f & 1) h.worldFromPen = pose();
    if (f & 2) h.worldFromMouse = pose();
    if (sticks) {
        auto f32 = [&] {
            uint32_t v = 0;
            for (int i = 0; i < 4; ++i)
                v |= uint32_t(b[at++]) << (8 * i);
            return std::bit_cast<float>(v);
        };
        h.penStickX = f32();
        h.penStickY = f32();
        h.mouseStickY = f32();
    }
    if (action) {
        h.panelAction.assign(b.begin() + std::ptrdiff_t(fixed + 1), b.end());
        if (!isSculptAction(h.panelAction)) return std::nullopt;
    }
    return h;
}

XrHands handsInWorld(const devices::XrControllers& c, const core::XrConfig& cfg) {
    XrHands h;
    if (c.localFromPen)
        h.worldFromPen = devices::worldPoseFromXrLocal(*c.localFromPen, cfg.sculptureInLocalM);
    if (c.localFromMouse)
        h.worldFromMouse = devices::worldPoseFromXrLocal(*c.localFromMouse, cfg.sculptureInLocalM);
    h.trigger = c.trigger;
    h.grip = c.grip;
    h.undo = c.undo;
    h.cycleTool = c.cycleTool;
    h.step = c.step;
    h.overview = c.overview;
    h.penStickX = c.penStickX;
    h.penStickY = c.penStickY;
    h.mouseStickY = c.mouseStickY;
    return h;
}

core::Vec3 penToolWorld(const glm::dmat4& worldFromPen, float trigger, const core::XrConfig& cfg) {
    core::Vec3 p(worldFromPen[3]);
    // Ahead is the pen's -z. Nothing is added when nothing is asked for: the tool is then
    // exactly the pose's position (recordings and scripts compare bit for bit).
    const double ahead = cfg.penTipMm + cfg.triggerPenetrationMm * double(trigger);
    if (ahead != 0) p -= glm::normalize(core::Vec3(worldFromPen[2])) * ahead;
    return p;
}

double hapticAmplitude(studio::ToolContact contact, const core::XrConfig& cfg) {
    switch (contact) {
        case studio::ToolContact::Air:
            return 0;
        case studio::ToolContact::Touching:
            return cfg.hapticTouching;
        case studio::ToolContact::Inside:
            return cfg.hapticInside;
    }
    return 0;
}

XrInput::XrInput(const core::XrConfig& cfg, studio::Interaction& interaction,
                 studio::Studio& studio)
    : mCfg(cfg), mInteraction(interaction), mStudio(studio) {}

void XrInput::handle(const XrHands& h) {
    const studio::Session& session = mStudio.session();
    auto guarded = [this](const char* what, auto&& f) {
        try {
            f();
        } catch (const std::logic_error&) {
            throw;  // a broken invariant, not a refused command
        } catch (const std::exception& e) {
            spdlog::warn("{}: {}", what, e.what());
            mRefusal = std::string(what) + ": " + e.what();
        }
    };
    if (h.undo) guarded("undo", [&] { mStudio.undo(); });
    if (h.cycleTool) guarded("cycle tool", [&] { mInteraction.cycleTool(); });
    if (h.step)
        guarded("step", [&] {
            mInteraction.step(
                session.objectPose().inverse().apply(mTool.value_or(core::Vec3(0.0))));
        });
    if (h.overview) guarded("overview", [&] { mInteraction.overview(); });
    // A button clicked on the headset's panel: what the window's palette does, zooming at the
    // tool as the thumbstick does.
    if (!h.panelAction.empty())
        guarded(h.panelAction.c_str(), [&] {
            const core::Vec3 at =
                session.objectPose().inverse().apply(mTool.value_or(core::Vec3(0.0)));
            if (!applySculptAction(h.panelAction, mStudio, mInteraction, at))
                spdlog::warn("the panel's action '{}' is not a sculpting action", h.panelAction);
        });
    // Direct jumps (docs/xr.md): sizes by the pen hand's stick, zoom steps by the other's.
    const Push penPush = stickPush(h.penStickX, h.penStickY, mPenStickArmed);
    if (penPush == Push::Down) {
        guarded("redo", [&] { mStudio.redo(); });
    } else if (penPush != Push::None) {
        std::vector<int> sizes =
            session.sculpture().config().zoom.allowedSizes[size_t(session.zoom() - 1)];
        std::sort(sizes.begin(), sizes.end());
        const int level = penPush == Push::Left    ? sizes.front()
                          : penPush == Push::Right ? sizes.back()
                                                   : sizes[sizes.size() / 2];
        guarded("size", [&] { mInteraction.jumpToSize(level); });
    }
    const Push mousePush = stickPush(0, h.mouseStickY, mMouseStickArmed);
    if (mousePush == Push::Up || mousePush == Push::Down) {
        const int zoom =
            std::clamp(session.zoom() + (mousePush == Push::Up ? 1 : -1), 1, core::kZoomLevels);
        const core::Vec3 at = session.objectPose().inverse().apply(mTool.value_or(core::Vec3(0.0)));
        if (zoom != session.zoom()) guarded("zoom", [&] { mInteraction.jumpToZoom(zoom, at); });
    }

    // The left hand holds the sculpture while the grip is closed (position control, like the
    // tracker's object station).
    // A pose beyond any room (kTrackerReachMm from the stage's origin) is a glitch: taken as
    // lost tracking, for the hand that holds the sculpture as for the pen.
    auto inReach = [](const std::optional<glm::dmat4>& pose) {
        return pose && glm::length(glm::dvec3((*pose)[3])) <= kTrackerReachMm;
    };
    if (h.grip && inReach(h.worldFromMouse)) {
        const core::RigidTransform worldFromHand = rigidOf(*h.worldFromMouse);
        if (!mHandFromObject) mHandFromObject = worldFromHand.inverse() * session.objectPose();
        mStudio.setObjectPose(worldFromHand * *mHandFromObject);
    } else {
        mHandFromObject.reset();
    }

    if (!inReach(h.worldFromPen)) {
        // Lost tracking ends the stroke: nothing is sculpted from a stale pose.
        if (mEngaged) guarded("pen", [&] { mInteraction.setEngaged(false); });
        mEngaged = false;
        return;
    }
    const core::Vec3 tool = penToolWorld(*h.worldFromPen, h.trigger, mCfg);
    const double t = mCfg.triggerThreshold;
    const bool engaged = mEngaged ? h.trigger >= kTriggerRelease * t : h.trigger >= t;
    const bool changed = engaged != mEngaged;
    if (changed) guarded("pen", [&] { mInteraction.setEngaged(engaged); });
    mEngaged = engaged;
    // A sample per pose that moved (or on engaging): a pen held still adds nothing.
    if (changed || !mTool || *mTool != tool) guarded("pen", [&] { mInteraction.moveTool(tool); });
    mTool = tool;
}

}  // namespace vsculpt::app
