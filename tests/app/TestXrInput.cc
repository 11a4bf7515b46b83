// SPDX-License-Identifier: MIT
// The OpenXR path's pure parts, without a runtime: the suggested bindings, OpenXR poses and
// fields of view into glm and the studio's world, the haptic and pen mappings, and XrInput
// driving a studio the thesis's two-handed way. The runtime end to end: tests/xr/TestXr.cc.
#include "vsculpt/app/XrInput.h"
#include "vsculpt/app/XrPanelUi.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/devices/XrBindings.h"
#include "vsculpt/studio/Session.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <set>

using namespace vsculpt;
using namespace vsculpt::app;
using namespace vsculpt::devices;
using namespace vsculpt::studio;

namespace {

constexpr double kPi = 3.14159265358979323846;

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-9) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

glm::dmat4 at(const glm::dvec3& p, const glm::dquat& q = glm::dquat(1, 0, 0, 0)) {
    return matrixFromXrPose(p, q);
}

core::SculptConfig config() {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 32;
    return cfg;
}

/// A studio that XrInput drives, wired as the headset session wires it.
struct XrRig {
    core::SculptConfig cfg = config();
    Studio studio{cfg};
    Interaction ui{studio};
    XrInput input{cfg.render.xr, ui, studio};
};

TEST(XrBindings, EveryProfileDrivesBothHands) {
    const auto& table = xrSuggestedBindings();
    std::set<std::string> profiles;
    for (const XrProfileBindings& p : table) {
        profiles.insert(p.profile);
        std::set<XrActionId> bound;
        for (const XrSuggestedBinding& b : p.bindings) {
            EXPECT_TRUE(bound.insert(b.action).second)
                << p.profile << ": " << xrActionName(b.action);
            // The pen is the right hand, the 3D mouse the left (the thesis's hands).
            const bool right = b.path.rfind("/user/hand/right/", 0) == 0;
            const bool left = b.path.rfind("/user/hand/left/", 0) == 0;
            EXPECT_TRUE(right || left) << b.path;
            const bool penAction =
                b.action == XrActionId::PenPose || b.action == XrActionId::PenTrigger ||
                b.action == XrActionId::PenHaptic || b.action == XrActionId::Undo ||
                b.action == XrActionId::PenStickX || b.action == XrActionId::PenStickY;
            EXPECT_EQ(right, penAction) << p.profile << " " << b.path;
        }
        for (XrActionId must :
             {XrActionId::PenPose, XrActionId::PenTrigger, XrActionId::PenHaptic,
              XrActionId::MousePose, XrActionId::MouseGrip, XrActionId::CycleTool})
            EXPECT_TRUE(bound.count(must)) << p.profile << " lacks " << xrActionName(must);
    }
    EXPECT_EQ(profiles, (std::set<std::string>{"/interaction_profiles/valve/index_controller",
                                               "/interaction_profiles/oculus/touch_controller",
                                               "/interaction_profiles/htc/vive_controller",
                                               "/interaction_profiles/khr/simple_controller"}));
    // Action names: unique, and what xrCreateAction accepts (lower case, digits, - _ .).
    std::set<std::string> names;
    for (int i = 0; i < kXrActionCount; ++i) {
        const std::string n = xrActionName(XrActionId(i));
        EXPECT_TRUE(names.insert(n).second) << n;
        for (char c : n)
            EXPECT_TRUE((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                        c == '.')
                << n;
    }
}

TEST(XrBindings, PosesAndFieldsOfView) {
    // A quarter turn about +y takes x to -z (right-handed, y up).
    const glm::dmat4 m = at({1, 2, 3}, glm::angleAxis(kPi / 2, glm::dvec3(0, 1, 0)));
    expectNear(glm::dvec3(m * glm::dvec4(1, 0, 0, 0)), {0, 0, -1});
    expectNear(glm::dvec3(m * glm::dvec4(0, 0, 0, 1)), {1, 2, 3});
    // A symmetric 90-degree field of view is glm's perspective.
    const glm::dmat4 p = projectionFromXrFov(-kPi / 4, kPi / 4, kPi / 4, -kPi / 4, 10, 1000);
    const glm::dmat4 q = glm::perspective(kPi / 2, 1.0, 10.0, 1000.0);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(p[c][r], q[c][r], 1e-12) << c << "," << r;
    // An asymmetric one keeps its edges: the left edge's direction lands on NDC x = -1.
    const glm::dmat4 a = projectionFromXrFov(-0.9, 0.6, 0.7, -0.8, 10, 1000);
    const glm::dvec4 left = a * glm::dvec4(-std::tan(0.9), 0, -1, 1);
    EXPECT_NEAR(left.x / left.w, -1, 1e-12);
    const glm::dvec4 up = a * glm::dvec4(0, std::tan(0.7), -1, 1);
    EXPECT_NEAR(up.y / up.w, 1, 1e-12);
}

TEST(XrBindings, LocalSpaceIntoTheStudiosWorld) {
    const glm::dvec3 sculpture(0, -0.25, -0.5);
    const glm::dmat4 w = worldFromXrLocal(sculpture);
    expectNear(glm::dvec3(w * glm::dvec4(sculpture, 1)), {0, 0, 0});
    // Metres to mm; up (local +y) is the world's +z; ahead (local -z) the world's +y (the
    // user looks at the sculpture from -y, like the window's camera).
    expectNear(glm::dvec3(w * glm::dvec4(0, 1, 0, 0)), {0, 0, 1000});
    expectNear(glm::dvec3(w * glm::dvec4(0, 0, -1, 0)), {0, 1000, 0});
    expectNear(glm::dvec3(w * glm::dvec4(1, 0, 0, 0)), {1000, 0, 0});
    // Poses stay rigid: rotation mapped, position scaled.
    const glm::dmat4 hand =
        at({0.1, -0.2, -0.4}, glm::angleAxis(0.3, glm::normalize(glm::dvec3(1, 2, 3))));
    const glm::dmat4 pose = worldPoseFromXrLocal(hand, sculpture);
    expectNear(glm::dvec3(pose[3]), glm::dvec3(w * hand[3]), 1e-9);
    const glm::dmat3 r(pose);
    const glm::dmat3 rtR = glm::transpose(r) * r;
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(rtR[c][k], c == k ? 1 : 0, 1e-12);
    EXPECT_NEAR(glm::determinant(r), 1, 1e-12);
}

TEST(XrInput, HapticsAndThePenTip) {
    core::XrConfig x;
    EXPECT_EQ(hapticAmplitude(ToolContact::Air, x), 0);
    EXPECT_EQ(hapticAmplitude(ToolContact::Touching, x), 0.3);
    EXPECT_EQ(hapticAmplitude(ToolContact::Inside, x), 0.8);
    // No offsets: exactly the pose's position (a recording compares bit for bit).
    const glm::dmat4 pen = glm::translate(glm::dmat4(1.0), glm::dvec3(1.5, -2.25, 3.125)) *
                           glm::mat4_cast(glm::angleAxis(kPi / 2, glm::dvec3(1, 0, 0)));
    EXPECT_EQ(penToolWorld(pen, 0.7f, x), core::Vec3(1.5, -2.25, 3.125));
    // The tip ahead along the pen's -z (here world +y after the quarter turn about x), and
    // the trigger's value pushing it further when configured.
    x.penTipMm = 20;
    expectNear(penToolWorld(pen, 0.7f, x), glm::dvec3(1.5, -2.25 + 20, 3.125), 1e-9);
    x.triggerPenetrationMm = 10;
    expectNear(penToolWorld(pen, 0.5f, x), glm::dvec3(1.5, -2.25 + 25, 3.125), 1e-9);
}

TEST(XrInput, TriggerStrokeIsTheScriptedStroke) {
    const core::SculptConfig cfg = config();
    const std::vector<core::Vec3> path = {
        {-10, 0, 28}, {-5, 0, 29}, {0, 0, 29.5}, {5, 0, 29}, {10, 0, 28}};
    Studio a(cfg);
    Interaction ui(a);
    XrInput input(cfg.render.xr, ui, a);
    XrHands h;
    h.worldFromPen = glm::translate(glm::dmat4(1.0), glm::dvec3(-10, 0, 60));
    input.handle(h);  // in the air, trigger up: nothing
    EXPECT_EQ(a.stepCount(), 0u);
    for (const core::Vec3& p : path) {
        h.worldFromPen = glm::translate(glm::dmat4(1.0), p);
        h.trigger = 1;
        input.handle(h);
        input.handle(h);  // held still: no second sample
    }
    EXPECT_TRUE(input.engaged());
    h.trigger = 0.45f;  // above 0.8 x threshold: still engaged (hysteresis)
    input.handle(h);
    EXPECT_TRUE(input.engaged());
    h.trigger = 0.3f;
    input.handle(h);
    EXPECT_FALSE(input.engaged());
    EXPECT_EQ(a.stepCount(), 1u);

    Studio b(cfg);
    b.stroke(path, /*world=*/true);
    EXPECT_EQ(core::canonicalMeshHash(a.session().wholeMesh()),
              core::canonicalMeshHash(b.session().wholeMesh()));
}

TEST(XrInput, GripHoldsTheSculptureAndButtonsFollowTheThesis) {
    XrRig rig;
    auto& [cfg, studio, ui, input] = rig;
    const Session& s = studio.session();
    XrHands h;
    h.worldFromMouse = glm::translate(glm::dmat4(1.0), glm::dvec3(-100, 0, 0));
    h.grip = true;
    input.handle(h);  // grabbed where it is: no jump
    expectNear(s.objectPose().translation, {0, 0, 0}, 1e-9);
    EXPECT_TRUE(input.grabbing());
    // The hand turns a quarter about +z and rises: the sculpture swings with it.
    h.worldFromMouse = glm::translate(glm::dmat4(1.0), glm::dvec3(-100, 0, 50)) *
                       glm::mat4_cast(glm::angleAxis(kPi / 2, glm::dvec3(0, 0, 1)));
    input.handle(h);
    expectNear(s.objectPose().translation, {-100, 100, 50}, 1e-9);
    EXPECT_NEAR(std::abs(s.objectPose().rotation.w), std::sqrt(0.5), 1e-12);
    // Let go and move the hand: the sculpture stays.
    h.grip = false;
    h.worldFromMouse = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 0));
    input.handle(h);
    expectNear(s.objectPose().translation, {-100, 100, 50}, 1e-9);
    EXPECT_FALSE(input.grabbing());

    // Left buttons: cycle the tool, step the size; one press each.
    XrHands b;
    b.cycleTool = true;
    input.handle(b);
    EXPECT_EQ(s.tool(), ToolKind::Carve);
    b = {};
    b.step = true;
    input.handle(b);
    EXPECT_EQ(s.size(), 6);
    b = {};
    b.undo = true;  // nothing to undo: logged, not thrown
    EXPECT_NO_THROW(input.handle(b));
}

TEST(XrInput, RecordedReportsAreLossless) {
    XrHands h;
    h.worldFromPen = glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, -2.0 / 3.0, 1e-300)) *
                     glm::mat4_cast(glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, -2, 3))));
    h.trigger = 0.123456f;
    h.grip = true;
    h.step = true;
    h.penStickX = -0.8125f;
    h.mouseStickY = 1.0f / 3.0f;
    const std::vector<uint8_t> bytes = xrHandsReport(h);
    EXPECT_EQ(bytes.size(), 5u + 96u + 12u);
    const std::optional<XrHands> back = parseXrHandsReport(bytes);
    ASSERT_TRUE(back);
    ASSERT_TRUE(back->worldFromPen);
    EXPECT_EQ(*back->worldFromPen, *h.worldFromPen);  // bit for bit
    EXPECT_FALSE(back->worldFromMouse);
    EXPECT_EQ(back->trigger, h.trigger);
    EXPECT_TRUE(back->grip && back->step);
    EXPECT_FALSE(back->undo || back->cycleTool || back->overview);
    EXPECT_EQ(back->penStickX, h.penStickX);
    EXPECT_EQ(back->penStickY, 0.0f);
    EXPECT_EQ(back->mouseStickY, h.mouseStickY);
    // A report recorded before the thumbsticks (no bit 7, no stick floats) still parses.
    std::vector<uint8_t> old(bytes.begin(), bytes.end() - 12);
    old[0] &= 0x7F;
    const std::optional<XrHands> oldBack = parseXrHandsReport(old);
    ASSERT_TRUE(oldBack);
    EXPECT_EQ(*oldBack->worldFromPen, *h.worldFromPen);
    EXPECT_EQ(oldBack->penStickX, 0.0f);
    // A truncated report, or one claiming a hand it does not carry, is refused.
    EXPECT_FALSE(parseXrHandsReport(std::span(bytes).first(50)));
    std::vector<uint8_t> lying = bytes;
    lying[0] |= 2;
    EXPECT_FALSE(parseXrHandsReport(lying));
    EXPECT_TRUE(parseXrHandsReport(xrHandsReport(XrHands{})));

    // A button clicked on the headset's panel travels with the hands: a length byte and the
    // action's name after the thumbsticks.
    h.panelAction = "mirror_z";
    const std::vector<uint8_t> clicked = xrHandsReport(h);
    EXPECT_EQ(clicked.size(), bytes.size() + 1 + 8);
    const std::optional<XrHands> clickedBack = parseXrHandsReport(clicked);
    ASSERT_TRUE(clickedBack);
    EXPECT_EQ(clickedBack->panelAction, "mirror_z");
    EXPECT_EQ(*clickedBack->worldFromPen, *h.worldFromPen);
    EXPECT_EQ(parseXrHandsReport(bytes)->panelAction, "");
    // A name that is not a sculpting action, or a length past the report's end, is refused.
    std::vector<uint8_t> notAnAction(bytes);
    for (uint8_t c : std::string("\4save"))
        notAnAction.push_back(c);
    EXPECT_FALSE(parseXrHandsReport(notAnAction));
    std::vector<uint8_t> cut(clicked.begin(), clicked.end() - 1);
    EXPECT_FALSE(parseXrHandsReport(cut));
}

/// A pen pose at `origin` pointing (its -z) at `target`, world mm.
glm::dmat4 penPointingAt(const glm::dvec3& origin, const glm::dvec3& target) {
    // lookAt's eye looks along its -z, as the aim pose points.
    return glm::inverse(glm::lookAt(origin, target, glm::dvec3(0, 0, 1)));
}

TEST(XrPanel, ThePensRayMeetsThePanelWhereItPoints) {
    const core::SculptConfig cfg = config();
    const XrPanel panel;
    const glm::dmat4 worldFromP = worldFromPanel(panel, cfg.render.xr);
    const glm::dvec2 size = panelSizeMm(panel);
    EXPECT_NEAR(size.x, panel.widthM * 1000, 1e-9);
    EXPECT_NEAR(size.y, size.x * panel.heightPx / panel.widthPx, 1e-9);
    // Placed as the controllers are: its centre where a hand at the same local point would be.
    glm::dmat4 localFromHand(1.0);
    localFromHand[3] = glm::dvec4(panel.positionM, 1);
    expectNear(glm::dvec3(worldFromP[3]),
               glm::dvec3(worldPoseFromXrLocal(localFromHand, cfg.render.xr.sculptureInLocalM)[3]));
    const glm::dvec3 centre(worldFromP[3]), right(worldFromP[0]), up(worldFromP[1]),
        face(worldFromP[2]);
    EXPECT_NEAR(glm::length(right), 1, 1e-12);
    EXPECT_NEAR(glm::dot(right, face), 0, 1e-12);
    // It faces where the head was at the start (the local origin), 0.1 m below the eyes.
    const glm::dvec3 head(
        worldPoseFromXrLocal(glm::dmat4(1.0), cfg.render.xr.sculptureInLocalM)[3]);
    EXPECT_GT(glm::dot(glm::normalize(head - centre), face), 0.985);

    const int w = panel.widthPx, h = panel.heightPx;
    auto pointOf = [&](double px, double py) {
        return centre + (px / w - 0.5) * size.x * right + (0.5 - py / h) * size.y * up;
    };
    const glm::dvec3 pen = centre + 350.0 * face + glm::dvec3(60, -40, 25);
    for (const glm::dvec2 px : {glm::dvec2(w / 2.0, h / 2.0), glm::dvec2(100.25, 37.5),
                                glm::dvec2(0.5, 0.5), glm::dvec2(w - 0.5, h - 0.5)}) {
        const auto hit =
            panelHitAt(penPointingAt(pen, pointOf(px.x, px.y)), worldFromP, size, w, h);
        ASSERT_TRUE(hit) << px.x << " " << px.y;
        EXPECT_NEAR(hit->pixel.x, px.x, 1e-6);
        EXPECT_NEAR(hit->pixel.y, px.y, 1e-6);
        expectNear(hit->world, pointOf(px.x, px.y), 1e-9);
    }
    // Past an edge, pointing away, from behind, or along the panel: no hit.
    EXPECT_FALSE(panelHitAt(penPointingAt(pen, pointOf(-2, h / 2.0)), worldFromP, size, w, h));
    EXPECT_FALSE(panelHitAt(penPointingAt(pen, pointOf(w / 2.0, h + 2)), worldFromP, size, w, h));
    EXPECT_FALSE(panelHitAt(penPointingAt(pen, 2.0 * pen - pointOf(w / 2.0, h / 2.0)), worldFromP,
                            size, w, h));
    const glm::dvec3 behind = centre - 350.0 * face;
    EXPECT_FALSE(
        panelHitAt(penPointingAt(behind, pointOf(w / 2.0, h / 2.0)), worldFromP, size, w, h));
    EXPECT_FALSE(panelHitAt(penPointingAt(centre + 100.0 * right, centre - 100.0 * right),
                            worldFromP, size, w, h));
}

TEST(XrInput, PanelButtonsDoWhatThePalettesButtonsDo) {
    XrRig rig;
    auto& [cfg, studio, ui, input] = rig;
    const Session& s = studio.session();
    auto click = [&](const std::string& action) {
        XrHands h;
        h.panelAction = action;
        input.handle(h);
    };
    click("tool_carve");
    EXPECT_EQ(s.tool(), ToolKind::Carve);
    click("tool_smooth");
    EXPECT_EQ(s.tool(), ToolKind::Smooth);
    click("mirror_x");
    EXPECT_EQ(s.mirror(), core::MirrorAxis::X);
    click("mirror_off");
    EXPECT_EQ(s.mirror(), core::MirrorAxis::None);
    const std::vector<int> offered = ui.offeredSizes();
    ASSERT_GE(offered.size(), 2u);
    click("size_" + std::to_string(offered.back()));
    EXPECT_EQ(s.size(), offered.back());
    click("zoom_2");
    EXPECT_EQ(s.zoom(), 2);
    click("overview");
    EXPECT_EQ(s.zoom(), 1);

    // A stroke with the trigger, then undo and redo from the panel.
    click("tool_add");
    XrHands pen;
    pen.worldFromPen = glm::translate(glm::dmat4(1.0), glm::dvec3(-10, 0, 30));
    pen.trigger = 1;
    input.handle(pen);
    pen.worldFromPen = glm::translate(glm::dmat4(1.0), glm::dvec3(10, 0, 30));
    input.handle(pen);
    pen.trigger = 0;
    input.handle(pen);
    const size_t sculpted = s.sculpture().counts().total();
    click("undo");
    const size_t undone = s.sculpture().counts().total();
    EXPECT_LT(undone, sculpted);
    click("redo");
    EXPECT_EQ(s.sculpture().counts().total(), sculpted);
    // What is not a sculpting action is logged and changes nothing.
    EXPECT_NO_THROW(click("save"));
    EXPECT_EQ(s.sculpture().counts().total(), sculpted);
    EXPECT_EQ(s.tool(), ToolKind::Add);
}

// What the studio refuses is said once, for the headset's panel to show (the window's status
// shows its own): in thesis placement the smooth tool has nothing to relax.
TEST(XrInput, ARefusedCommandIsSaidOnceForThePanel) {
    core::SculptConfig cfg = config();
    cfg.placement = core::PlacementMode::Thesis;
    Studio studio(cfg);
    Interaction ui(studio);
    XrInput input(cfg.render.xr, ui, studio);
    XrHands h;
    h.panelAction = "tool_smooth";
    input.handle(h);
    EXPECT_FALSE(input.takeRefusal()) << "choosing the tool is not refused";
    h.panelAction.clear();
    h.worldFromPen = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 30));
    h.trigger = 1;
    input.handle(h);
    const std::optional<std::string> refused = input.takeRefusal();
    ASSERT_TRUE(refused);
    EXPECT_NE(refused->find("smooth"), std::string::npos) << *refused;
    EXPECT_FALSE(input.takeRefusal()) << "said once";
    EXPECT_EQ(studio.session().sculpture().counts().lattice, 0u) << "nothing sculpted";
}

TEST(XrInput, ThumbsticksJumpToSizesAndZoomOncePerPush) {
    XrRig rig;
    auto& [cfg, studio, ui, input] = rig;
    const Session& s = studio.session();
    std::vector<int> offered = cfg.zoom.allowedSizes[0];
    std::sort(offered.begin(), offered.end());
    auto push = [&](float px, float py, float my) {
        XrHands h;
        h.penStickX = px;
        h.penStickY = py;
        h.mouseStickY = my;
        input.handle(h);
    };
    push(-1, 0, 0);  // left: the smallest size offered at zoom 1
    EXPECT_EQ(s.size(), offered.front());
    push(0, 0, 0);
    push(0.95f, 0.1f, 0);  // right: the largest
    EXPECT_EQ(s.size(), offered.back());
    push(0, 0, 0);
    push(0, 0.9f, 0);  // up: the middle one
    EXPECT_EQ(s.size(), offered[offered.size() / 2]);
    // Held: no repeat; half way back is not yet a release.
    push(0, 0, 0);
    push(-1, 0, 0);
    push(-0.6f, 0, 0);
    push(-1, 0, 0);
    EXPECT_EQ(s.size(), offered.front());
    // The other hand's stick zooms in and out, one level per push.
    push(0, 0, 0);
    push(0, 0, 1);
    EXPECT_EQ(s.zoom(), 2);
    push(0, 0, 1);  // still held
    EXPECT_EQ(s.zoom(), 2);
    push(0, 0, 0);
    push(0, 0, 1);
    EXPECT_EQ(s.zoom(), 3);
    push(0, 0, 0);
    push(0, 0, -1);
    EXPECT_EQ(s.zoom(), 2);
    push(0, 0, 0);
    push(0, 0, -1);
    push(0, 0, 0);
    push(0, 0, -1);  // already at zoom 1: nothing
    EXPECT_EQ(s.zoom(), 1);
    // Down on the pen hand's stick redoes.
    studio.stroke({core::Vec3(0, 0, 40), core::Vec3(5, 0, 40)}, false);
    ASSERT_TRUE(studio.undo());
    EXPECT_EQ(studio.redoCount(), 1u);
    push(0, -1, 0);
    EXPECT_EQ(studio.redoCount(), 0u);
}

TEST(XrInput, LosingThePenEndsTheStroke) {
    XrRig rig;
    auto& [cfg, studio, ui, input] = rig;
    XrHands h;
    h.trigger = 1;
    h.worldFromPen = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 29));
    input.handle(h);
    h.worldFromPen = glm::translate(glm::dmat4(1.0), glm::dvec3(3, 0, 29));
    input.handle(h);
    EXPECT_TRUE(studio.session().inStroke());
    h.worldFromPen.reset();
    input.handle(h);
    EXPECT_FALSE(studio.session().inStroke());
    EXPECT_FALSE(input.engaged());
    EXPECT_EQ(studio.stepCount(), 1u);
}

}  // namespace
