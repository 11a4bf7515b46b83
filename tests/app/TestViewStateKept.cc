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
        o.keepViewState = true;  // as windowRigOptions sets them
        o.restoreViewState = true;
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
    std::string notOffered = studio::viewStateJson(studio::ViewState{});
    notOffered.replace(notOffered.find("\"size\": 7"), 9, "\"size\": 2");
    const std::string path = studio::viewStatePath(project).string();
    struct Case {
        std::string text, says;
    };
    for (const Case& c : std::vector<Case>{
             {"{\"format\": \"vsculpt-view\", \"vers", path + ":1:"},
             // Each value in range, but zoom 1 does not offer size 2: the file and the field
             // are named, not only the session's refusal (found by QA).
             {notOffered, path + ": field 'size': size 2 is not offered at zoom 1"},
             // Not read whole (found by QA: a 6 GB file held the window's start for 14 s).
             {std::string(70000, ' ') + studio::viewStateJson(studio::ViewState{}),
              path + ": 7"}}) {
        {
            std::ofstream out(studio::viewStatePath(project), std::ios::trunc);
            out << c.text;
        }
        app::Rig rig(cfg, windowOptions(project));
        expectDefaults(rig.session());  // nothing half set
        EXPECT_EQ(rig.session().history().done().size(), 1u);
        // Said where the journal's recovery is (the windows' terminal, panel and title).
        const std::string& said = rig.session().recoveryWarning();
        EXPECT_EQ(said.rfind(c.says, 0), 0u) << said;
        EXPECT_NE(said.find("starting at the default tool and view"), std::string::npos) << said;
        rig.close();
        // The next close wrote a good one.
        EXPECT_EQ(studio::readViewState(project), studio::viewStateOf(rig.session()));
    }
}

// A window's --play script and a headset's --record start from the defaults, as `vsculpt play`
// does, so they play (and the recording replays) the same whoever left the project last (found
// by QA: a recording made on a turned project replayed unturned, to another sculpture). The
// session's end is still kept.
TEST_F(ViewStateKept, AScriptedOrRecordedSessionStartsFromTheDefaults) {
    leaveTurnedAndZoomed(true);
    {
        app::Rig rig(cfg, app::windowRigOptions(project.string(), false, false, true));
        expectDefaults(rig.session());
        rig.studio().setSize(5);
        rig.close();
    }
    const auto kept = studio::readViewState(project);
    ASSERT_TRUE(kept.has_value());
    EXPECT_EQ(kept->size, 5);
    app::Rig rig(cfg, app::windowRigOptions(project.string(), false, false));
    EXPECT_EQ(rig.session().size(), 5);
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
