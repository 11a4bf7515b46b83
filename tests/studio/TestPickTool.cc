// SPDX-License-Identifier: MIT
// Tool picking against the initial sphere, whose surface is known analytically.
#include "vsculpt/core/EvalField.h"
#include "vsculpt/studio/PickTool.h"
#include "vsculpt/studio/Studio.h"

#include "../TestFixtures.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

namespace vsculpt::studio {
namespace {

using core::Vec3;

TEST(PickTool, ThePointerToolRestsOnTheSphereAndTouchesIt) {
    const core::SculptConfig cfg = test::smallConfig(30);
    Studio studio(cfg);
    const Session& s = studio.session();
    const double step = 0.5 * s.view().region().spacingMm;
    const double radius = 3;
    // A ray from the front (-y) at height z = 10: the sphere's surface is at
    // y = -sqrt(30^2 - 10^2).
    const Vec3 origin(0, -200, 10), dir(0, 1, 0), down(0, 0, -1);
    const ToolPick pick = pickTool(s, origin, dir, radius, 0, down);
    ASSERT_TRUE(pick.surfaceHit);
    const double surfaceY = -std::sqrt(30.0 * 30.0 - 10.0 * 10.0);
    EXPECT_NEAR(pick.surfaceHit->y, surfaceY, step + 0.5);
    EXPECT_NEAR(pick.toolCentre.y, pick.surfaceHit->y - radius, 1e-9);
    EXPECT_EQ(pick.contact, ToolContact::Touching);
    EXPECT_FALSE(pick.shadow);  // straight below the tool, outside the sphere: no clay
    // From above: the tool rests on the top (z = 30) and its shadow is on the sphere below.
    const ToolPick top = pickTool(s, Vec3(1, 2, 200), Vec3(0, 0, -1), radius, 0, down);
    ASSERT_TRUE(top.surfaceHit);
    EXPECT_NEAR(top.toolCentre.z, top.surfaceHit->z + radius, 1e-9);
    ASSERT_TRUE(top.shadow);
    EXPECT_NEAR(glm::length(*top.shadow), 30, step + 0.5);
    EXPECT_LT(top.shadow->z, top.toolCentre.z);
    // Pushed in by twice the radius, the centre is inside.
    EXPECT_EQ(pickTool(s, origin, dir, radius, 2 * radius, down).contact, ToolContact::Inside);
    // Pulled back, it hangs in the air.
    EXPECT_EQ(pickTool(s, origin, dir, radius, -3 * radius, down).contact, ToolContact::Air);
}

TEST(PickTool, ARayThatMissesLeavesTheToolAtTheRegionsDepth) {
    Studio studio(test::smallConfig(30));
    const Session& s = studio.session();
    const Vec3 origin(200, -200, 200), dir = glm::normalize(Vec3(0, 1, 0));
    const ToolPick pick = pickTool(s, origin, dir, 3, 0, Vec3(0, 0, -1));
    EXPECT_FALSE(pick.surfaceHit);
    EXPECT_EQ(pick.contact, ToolContact::Air);
    EXPECT_FALSE(pick.shadow);  // nothing below (200, *, 200) either
    // Cues for a tool placed by a pen inside the clay.
    EXPECT_EQ(toolCues(s, Vec3(0, 0, 0), 3, Vec3(0, 0, -1)).contact, ToolContact::Inside);
}

TEST(PickTool, MarchingStopsAtTheFirstClay) {
    Studio studio(test::smallConfig(30));
    core::FieldProbe probe(studio.session().sculpture());
    const auto t = marchToSurface(probe, Vec3(-100, 0, 0), Vec3(1, 0, 0), 0.25, 300);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 70, 0.5);
    EXPECT_FALSE(marchToSurface(probe, Vec3(-100, 0, 0), Vec3(-1, 0, 0), 0.25, 300));
    EXPECT_FALSE(marchToSurface(probe, Vec3(-100, 0, 0), Vec3(1, 0, 0), 0, 300));
}

// The pointer's tool held still with the button down, a sample a frame as the window sends
// them: it rests on the clay as it was before the stroke, so an add makes one dab of the
// tool's size and a carve pushed in by its radius one pit, however long it is held. On the
// live clay the add climbed its own clay toward the eye (a pillar 300 mm long in a second).
TEST(PickTool, AToolHeldStillDuringAStrokeMakesOneDab) {
    for (ToolKind op : {ToolKind::Add, ToolKind::Carve}) {
        Session s(test::smallConfig(30));
        s.setTool(op);
        s.setSize(6);
        const double radius = 0.5 * s.sculpture().levels().level(6).diameterMm;
        const Vec3 origin(0, -200, 0), dir(0, 1, 0), down(0, 0, -1);
        const double depth = op == ToolKind::Add ? 0 : radius;  // the scroll wheel's push
        s.beginStroke();
        for (int frame = 0; frame < 60; ++frame)
            s.strokeSample(pickTool(s, origin, dir, radius, depth, down).toolCentre, false);
        s.endStroke();
        core::FieldProbe probe(s.sculpture());
        const auto t = marchToSurface(probe, origin, dir, 0.02, 400);
        ASSERT_TRUE(t);
        const double surfaceY = origin.y + *t;
        // Add: a ball touching the sphere's front (y = -30), its far side 2 radii out. Carve:
        // the tool centred on the front, the pit's bottom a radius in.
        const double expected = op == ToolKind::Add ? -30 - 2 * radius : -30 + radius;
        EXPECT_NEAR(surfaceY, expected, 0.08 * radius) << int(op);
    }
}

}  // namespace
}  // namespace vsculpt::studio
