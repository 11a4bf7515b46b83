// SPDX-License-Identifier: MIT
// The windows' rig finishes a smooth stroke's pen-lift estimate off the frame
// (Session::setAsyncStrokeFinish): the frame's poll makes it a step, and an export or a close
// right after the lift holds it.
#include "vsculpt/app/Rig.h"
#include "vsculpt/studio/Session.h"

#include "../TestFixtures.h"

#include <gtest/gtest.h>

using namespace vsculpt;
using core::Vec3;

namespace {

using test::Weights;
using test::weightsOf;

// A size-3 arm, then size-4 smooth strokes along it (no finer detail: the export below
// meshes at the finest size's spacing).
void sculptArm(studio::Studio& studio) {
    studio.setZoom(3, Vec3(54, 0, 0));
    studio.setSize(3);
    studio.stroke({Vec3(36, 0, 0), Vec3(50, 0, 0), Vec3(72, 0, 0)}, false);
    studio.setZoom(4, Vec3(54, 0, 0));
    studio.setSize(4);
    studio.setTool(studio::ToolKind::Smooth);
}
void smoothAlong(studio::Studio& studio, double y) {
    studio.beginStroke();
    for (double x = 40; x <= 68; x += 2.5)
        studio.strokeSample(Vec3(x, y, 3.4), false);
    studio.endStroke();
}

struct RigStrokeFinish : ::testing::Test {
    test::TempDir temp;
    const std::filesystem::path project = temp.path / "project";
    const core::SculptConfig cfg = test::smallConfig(40);
    app::RigOptions windowOptions() const {
        app::RigOptions o = app::windowRigOptions(project.string(), false, false);
        o.rememberRecent = false;
        return o;
    }
};

}  // namespace

TEST_F(RigStrokeFinish, TheFramesPollMakesItAStepAndACloseRightAfterTheLiftKeepsIt) {
    // The same strokes, each completed at once.
    studio::Studio reference(cfg);
    sculptArm(reference);
    for (double y : {-2.0, 0.0, 2.0})
        smoothAlong(reference, y);
    ASSERT_FALSE(reference.session().strokeFinishing());
    const Weights expected = weightsOf(reference.session().sculpture());
    const size_t steps = reference.session().history().done().size();
    {
        app::Rig rig(cfg, windowOptions());
        ASSERT_TRUE(rig.session().asyncStrokeFinish());  // the windows' rig turns it on
        sculptArm(rig.studio());
        const size_t before = rig.studio().stepCount();
        smoothAlong(rig.studio(), -2.0);
        ASSERT_TRUE(rig.session().strokeFinishing());
        EXPECT_EQ(rig.studio().stepCount(), before);
        rig.pollBackgroundWork(true);  // as a frame would, waiting
        EXPECT_FALSE(rig.session().strokeFinishing());
        EXPECT_EQ(rig.studio().stepCount(), before + 1);
        // An export asked for right after a lift holds that stroke.
        smoothAlong(rig.studio(), 0.0);
        ASSERT_TRUE(rig.session().strokeFinishing());
        rig.exportTo(temp.path / "arm.obj");
        EXPECT_FALSE(rig.session().strokeFinishing());
        EXPECT_EQ(rig.studio().stepCount(), before + 2);
        rig.pollExport(true);
        // Closed right after a lift: the stroke is journaled and in the snapshot.
        smoothAlong(rig.studio(), 2.0);
        ASSERT_TRUE(rig.session().strokeFinishing());
        rig.close();
        EXPECT_FALSE(rig.session().strokeFinishing());
    }
    auto reopened = studio::Session::openProject(project, cfg);
    EXPECT_EQ(reopened->history().done().size(), steps);
    EXPECT_EQ(weightsOf(reopened->sculpture()), expected);
}
