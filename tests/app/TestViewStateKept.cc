// SPDX-License-Identifier: MIT
// A window's project reopens with the tool, size, zoom, mirror and pose the sculptor left it
// with (found by QA: a sculptor who turned the piece in the headset found it turned back, at
// size 7 and zoom 1). `vsculpt play` keeps starting from the defaults; a damaged view.json
// costs the view, never the clay.
#include "vsculpt/app/Rig.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/studio/ViewState.h"

#include "../TestFixtures.h"

#include <gtest/gtest.h>

#include <fstream>

using namespace vsculpt;
using core::Vec3;

namespace {

struct ViewStateKept : ::testing::Test {
    test::TempDir temp;
    const std::filesystem::path project = temp.path / "project";
    const core::SculptConfig cfg = test::smallConfig(25);

    app::RigOptions windowOptions(const std::filesystem::path& dir) const {
        app::RigOptions o;
        o.project = app::ProjectChoice::Given;
        o.projectDir = dir;
        o.keepViewState = true;  // as windowRigOptions sets it
        return o;
    }
    static core::RigidTransform turned() {
        core::RigidTransform t;
        t.rotation = glm::angleAxis(1.234, glm::normalize(Vec3(0.2, 0.9, -0.4)));
        t.translation = Vec3(3.5, -20.25, 7);
        return t;
    }
    /// A project left at zoom 2 with a carve of size 4 mirrored in x, the piece turned.
    void leaveTurnedAndZoomed(bool sculpt) {
        app::Rig rig(cfg, windowOptions(project));
        if (sculpt) rig.studio().stroke({Vec3(-20, 0, 20), Vec3(20, 0, 20)}, false);
        rig.studio().setObjectPose(turned());
        rig.studio().setZoom(2, Vec3(0, 5, 22));
        rig.studio().setSize(4);
        rig.studio().setTool(studio::ToolKind::Carve);
        rig.studio().setMirror(core::MirrorAxis::X);
        rig.close();
    }
};

void expectDefaults(const studio::Session& s) {
    EXPECT_EQ(studio::viewStateOf(s), studio::viewStateOf(studio::Session(s.sculpture().config())));
}

}  // namespace

TEST_F(ViewStateKept, AWindowsProjectReopensAsItWasLeft) {
    for (bool sculpt : {true, false}) {  // closing without an edit keeps the view too
        std::filesystem::remove_all(project);
        leaveTurnedAndZoomed(sculpt);
        ASSERT_TRUE(std::filesystem::exists(studio::viewStatePath(project)));
        app::Rig rig(cfg, windowOptions(project));
        const studio::Session& s = rig.session();
        EXPECT_EQ(s.tool(), studio::ToolKind::Carve) << sculpt;
        EXPECT_EQ(s.mirror(), core::MirrorAxis::X);
        EXPECT_EQ(s.size(), 4);
        EXPECT_EQ(s.zoom(), 2);
        EXPECT_EQ(s.zoomCentre(), Vec3(0, 5, 22));
        EXPECT_EQ(s.objectPose().rotation, turned().rotation);
        EXPECT_EQ(s.objectPose().translation, turned().translation);
        EXPECT_EQ(s.history().done().size(), sculpt ? 1u : 0u);
    }
}

TEST_F(ViewStateKept, PlaybackStartsFromTheDefaults) {
    leaveTurnedAndZoomed(true);
    app::RigOptions play;  // what `vsculpt play --project` builds
    play.project = app::ProjectChoice::Given;
    play.projectDir = project;
    const std::string kept = [&] {
        std::ifstream in(studio::viewStatePath(project));
        return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    {
        app::Rig rig(cfg, play);
        expectDefaults(rig.session());
        EXPECT_EQ(rig.session().history().done().size(), 1u);
        rig.studio().setSize(5);
        rig.close();
    }
    // ...and leaves the windows' file alone.
    std::ifstream in(studio::viewStatePath(project));
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), kept);
}

TEST_F(ViewStateKept, ADamagedViewFileCostsTheViewNotTheClay) {
    leaveTurnedAndZoomed(true);
    for (const std::string bad :
         {std::string("{\"format\": \"vsculpt-view\", \"vers"),
          studio::viewStateJson(studio::ViewState{})
              .replace(studio::viewStateJson(studio::ViewState{}).find("\"size\": 7"), 9,
                       "\"size\": 2")}) {
        {
            std::ofstream out(studio::viewStatePath(project), std::ios::trunc);
            out << bad;
        }
        app::Rig rig(cfg, windowOptions(project));
        expectDefaults(rig.session());  // size 2 at zoom 1 is not offered: nothing half set
        EXPECT_EQ(rig.session().history().done().size(), 1u);
        rig.close();
        // The next close wrote a good one.
        EXPECT_EQ(studio::readViewState(project), studio::viewStateOf(rig.session()));
    }
}

TEST_F(ViewStateKept, SaveAsAndSwitchingProjectsKeepEachProjectsView) {
    leaveTurnedAndZoomed(false);
    app::Rig rig(cfg, windowOptions(project));
    rig.saveAs(temp.path / "copy");  // continues in the copy, with the view as it was
    EXPECT_EQ(studio::readViewState(temp.path / "copy"), studio::readViewState(project));
    rig.studio().setZoom(1, Vec3(0));
    rig.studio().setTool(studio::ToolKind::Add);
    // Opening another project keeps the copy's view as it is now and brings the other's back.
    rig.openProject(project);
    EXPECT_EQ(rig.session().zoom(), 2);
    EXPECT_EQ(rig.session().tool(), studio::ToolKind::Carve);
    const auto copy = studio::readViewState(temp.path / "copy");
    ASSERT_TRUE(copy.has_value());
    EXPECT_EQ(copy->zoom, 1);
    EXPECT_EQ(copy->tool, studio::ToolKind::Add);
}
