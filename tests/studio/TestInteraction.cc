// SPDX-License-Identifier: MIT
// The interaction state machine driven by synthetic events.
#include "vsculpt/studio/Interaction.h"

#include <gtest/gtest.h>

using namespace vsculpt;
using namespace vsculpt::studio;
using core::Vec3;

namespace {

core::SculptConfig config() {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = 32;
    return cfg;
}

TEST(Interaction, RightButtonCyclesAddCarveSmoothSelect) {
    Studio studio(config());
    const Session& s = studio.session();
    Interaction ui(studio);
    EXPECT_EQ(s.tool(), ToolKind::Add);
    ui.cycleTool();
    EXPECT_EQ(s.tool(), ToolKind::Carve);
    ui.cycleTool();
    EXPECT_EQ(s.tool(), ToolKind::Smooth);  // the smooth tool (issue #13) comes before select
    ui.cycleTool();
    EXPECT_EQ(s.tool(), ToolKind::Select);
    ui.cycleTool();
    EXPECT_EQ(s.tool(), ToolKind::Add);
}

TEST(Interaction, LeftButtonStepsThroughOfferedSizesAndWraps) {
    Studio studio(config());
    const Session& s = studio.session();
    Interaction ui(studio);
    EXPECT_EQ(ui.offeredSizes(), (std::vector<int>{7, 6, 5}));
    EXPECT_EQ(s.size(), 7);
    std::vector<int> seen;
    for (int i = 0; i < 4; ++i) {
        ui.step(Vec3(0));
        seen.push_back(s.size());
    }
    EXPECT_EQ(seen, (std::vector<int>{6, 5, 7, 6}));
}

TEST(Interaction, SelectToolZoomsIntoTheRegionUnderIt) {
    Studio studio(config());
    const Session& s = studio.session();
    Interaction ui(studio);
    studio.setTool(ToolKind::Select);
    const Vec3 under(5, -3, 30);
    for (int z = 2; z <= 5; ++z) {
        ui.step(under);
        EXPECT_EQ(s.zoom(), z);
        // Only sizes offered at this zoom; the current one among them.
        const auto sizes = ui.offeredSizes();
        EXPECT_EQ(sizes, (std::vector<int>{8 - z, 7 - z, 6 - z}));
        EXPECT_NE(std::find(sizes.begin(), sizes.end(), s.size()), sizes.end());
        const core::Aabb box = s.view().region().box();
        EXPECT_NEAR(0.5 * (box.min.x + box.max.x), under.x, s.view().region().spacingMm);
    }
    ui.step(under);  // deepest zoom: stays
    EXPECT_EQ(s.zoom(), 5);
    ui.overview();
    EXPECT_EQ(s.zoom(), 1);
}

TEST(Interaction, DirectJumpsOnlyToOfferedSizes) {
    Studio studio(config());
    const Session& s = studio.session();
    Interaction ui(studio);
    EXPECT_FALSE(ui.jumpToSize(3));  // not at zoom 1
    EXPECT_EQ(s.size(), 7);
    EXPECT_TRUE(ui.jumpToSize(5));
    EXPECT_EQ(s.size(), 5);
    EXPECT_TRUE(ui.jumpToZoom(5, Vec3(0, 0, 30)));
    EXPECT_TRUE(ui.jumpToSize(1));
    EXPECT_FALSE(ui.jumpToSize(5));
    EXPECT_FALSE(ui.jumpToZoom(6, Vec3(0)));
    EXPECT_EQ(s.zoom(), 5);
}

TEST(Interaction, EngagedMovesMakeOneUndoStepPerEngagement) {
    Studio studio(config());
    const Session& s = studio.session();
    Interaction ui(studio);
    ui.jumpToSize(5);
    ui.moveTool(Vec3(0, 0, 30));  // not engaged: nothing
    EXPECT_FALSE(s.history().canUndo());
    ui.setEngaged(true);
    for (int i = 0; i < 10; ++i)
        ui.moveTool(Vec3(i * 2.0, 0, 30));
    ui.setEngaged(false);
    ui.setEngaged(true);
    for (int i = 0; i < 5; ++i)
        ui.moveTool(Vec3(0, i * 2.0, 31));
    ui.setEngaged(false);
    EXPECT_EQ(s.history().done().size(), 2u);
    EXPECT_EQ(s.history().done()[0].samples.size(), 10u);
    studio.setTool(ToolKind::Select);  // select: moving never edits
    ui.setEngaged(true);
    ui.moveTool(Vec3(0, 0, 30));
    ui.setEngaged(false);
    EXPECT_EQ(s.history().done().size(), 2u);
}

TEST(Interaction, ThesisModeIsAlwaysEngagedAndToolChangesEndTheStroke) {
    Studio studio(config());
    const Session& s = studio.session();
    Interaction ui(studio, /*alwaysEngaged=*/true);
    ui.jumpToSize(6);
    ui.moveTool(Vec3(0, 0, 30));
    ui.moveTool(Vec3(4, 0, 30));
    ui.step(Vec3(0));  // size change ends the stroke
    ui.moveTool(Vec3(8, 0, 30));
    ui.cycleTool();  // carve: another stroke
    ui.moveTool(Vec3(8, 0, 31));
    // Every stroke ended by a tool change is on the one timeline at once, not when polled.
    EXPECT_EQ(studio.stepCount(), 2u);
    studio.endStroke();
    EXPECT_EQ(studio.stepCount(), 3u);
    EXPECT_EQ(s.history().done().size(), 3u);
    EXPECT_EQ(s.history().done()[0].level, 6);
    EXPECT_EQ(s.history().done()[1].level, 5);
    EXPECT_EQ(s.history().done()[2].op, core::ToolOp::Carve);
    EXPECT_EQ(s.verifyMesh(), "");
}

}  // namespace
