// SPDX-License-Identifier: MIT
// A smooth stroke's pen-lift volume estimate off the frame thread (Session::setAsyncStrokeFinish):
// the same clay, history and journal as finishing at once; the stroke is never lost or
// reordered, whatever comes next (another stroke, an undo, a save, the session closing).
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/studio/Session.h"
#include "vsculpt/studio/Studio.h"

#include "../TestFixtures.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <unistd.h>

using namespace vsculpt;
using namespace vsculpt::studio;

namespace {

// A size-3 arm off the initial sphere with size-1 bumps on it (examples/smooth-bumpy-arm.vsc,
// shortened), then two size-4 smooth strokes along it with an add between them.
const char* kArm = R"(zoom 3 54 0 0
size 3
stroke 36 0 0 50 0 0 72 0 0
zoom 5 54 0 0
size 1
stroke 44 1.925 2.680
stroke 50 -3.216 -0.738
stroke 56 -3.296 -0.154
stroke 62 2.987 1.402
zoom 4 54 0 0
size 4
)";
const char* kSmooth = "tool smooth\nstroke 40 3.4 0 54 3.4 0 68 3.4 0\n";
const char* kAdd = "tool add\nstroke 60 0 4 64 0 5\n";
const char* kSmoothAgain = "tool smooth\nstroke 40 0 3.4 54 0 3.4 68 0 3.4\n";

core::SculptConfig smallConfig() {
    core::SculptConfig cfg;
    cfg.polygonizer.gridN = 48;
    return cfg;
}

using test::Weights;
using test::weightsOf;

void play(Session& s, const char* text) {
    for (const ScriptCommand& c : parseScript(text, "test.vsc").commands)
        s.apply(c);
}

std::filesystem::path tempProject(const std::string& name) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() /
        ("vsculpt-async-finish-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    return dir;
}

void expectSameChanges(const std::vector<core::SkeletonChange>& a,
                       const std::vector<core::SkeletonChange>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].level, b[i].level) << i;
        EXPECT_EQ(a[i].coord, b[i].coord) << i;
        EXPECT_EQ(a[i].before, b[i].before) << i;
        EXPECT_EQ(a[i].after, b[i].after) << i;
    }
}

// The session ends as the reference did: the same weights, the same steps with the same
// changes, and a mesh that matches a full rebuild.
void expectSameAs(Session& s, const Weights& expected,
                  const std::vector<core::StrokeRecord>& steps) {
    EXPECT_EQ(weightsOf(s.sculpture()), expected);
    ASSERT_EQ(s.history().done().size(), steps.size());
    for (size_t i = 0; i < steps.size(); ++i)
        expectSameChanges(s.history().done()[i].changes, steps[i].changes);
    s.waitForMesh();
    EXPECT_EQ(s.verifyMesh(), "");
}

}  // namespace

TEST(AsyncStrokeFinish, GivesTheSameClayHistoryAndJournalAsFinishingAtOnce) {
    const std::filesystem::path syncDir = tempProject("sync"), asyncDir = tempProject("async");
    Weights expected;
    std::vector<core::StrokeRecord> expectedSteps;
    {
        auto s = Session::openProject(syncDir, smallConfig());
        for (const char* part : {kArm, kSmooth, kAdd, kSmoothAgain})
            play(*s, part);
        expected = weightsOf(s->sculpture());
        for (const core::StrokeRecord& r : s->history().done())
            expectedSteps.push_back(r);
    }
    {
        auto s = Session::openProject(asyncDir, smallConfig());
        s->setAsyncMeshing(true);
        s->setAsyncStrokeFinish(true);
        play(*s, kArm);
        const size_t steps = s->history().done().size();
        play(*s, kSmooth);
        // Ended, not yet a step: the estimate runs on a thread of its own until polled.
        EXPECT_TRUE(s->strokeFinishing());
        EXPECT_FALSE(s->inStroke());
        EXPECT_EQ(s->history().done().size(), steps);
        // The next stroke waits for it: the smooth is a step before the add is one.
        play(*s, kAdd);
        EXPECT_FALSE(s->strokeFinishing());
        ASSERT_EQ(s->history().done().size(), steps + 2);
        EXPECT_EQ(s->history().done()[steps].op, core::ToolOp::Smooth);
        EXPECT_EQ(s->history().done()[steps + 1].op, core::ToolOp::Add);
        play(*s, kSmoothAgain);
        EXPECT_TRUE(s->strokeFinishing());
        EXPECT_TRUE(s->pollStrokeFinish(true));
        EXPECT_FALSE(s->strokeFinishing());
        EXPECT_FALSE(s->pollStrokeFinish(true));  // nothing left
        expectSameAs(*s, expected, expectedSteps);
    }
    // Not saved: each journal alone replays to the same clay.
    for (const auto& dir : {syncDir, asyncDir}) {
        auto s = Session::openProject(dir, smallConfig());
        EXPECT_EQ(s->recoveredEdits(), expectedSteps.size()) << dir;
        EXPECT_EQ(weightsOf(s->sculpture()), expected) << dir;
    }
    std::filesystem::remove_all(syncDir);
    std::filesystem::remove_all(asyncDir);
}

TEST(AsyncStrokeFinish, AnUndoRightAfterThePenLiftUndoesTheWholeStroke) {
    Session s(smallConfig());
    s.setAsyncStrokeFinish(true);
    play(s, kArm);
    const Weights beforeSmooth = weightsOf(s.sculpture());
    play(s, kSmooth);
    ASSERT_TRUE(s.strokeFinishing());
    ASSERT_TRUE(s.undo());  // waits for the stroke, then undoes it, not the stroke before
    EXPECT_FALSE(s.strokeFinishing());
    EXPECT_EQ(weightsOf(s.sculpture()), beforeSmooth);
    ASSERT_TRUE(s.redo());
    Session sync(smallConfig());
    play(sync, kArm);
    play(sync, kSmooth);
    EXPECT_EQ(weightsOf(s.sculpture()), weightsOf(sync.sculpture()));
}

TEST(AsyncStrokeFinish, ASessionClosedBeforeTheStrokeIsCompletedKeepsIt) {
    const std::filesystem::path dir = tempProject("close");
    Weights expected;
    {
        Session sync(smallConfig());
        play(sync, kArm);
        play(sync, kSmooth);
        expected = weightsOf(sync.sculpture());
    }
    size_t steps = 0;
    {
        auto s = Session::openProject(dir, smallConfig());
        s->setAsyncMeshing(true);
        s->setAsyncStrokeFinish(true);
        play(*s, kArm);
        steps = s->history().done().size() + 1;
        play(*s, kSmooth);
        ASSERT_TRUE(s->strokeFinishing());
    }  // closed with the estimate pending: the destructor completes and journals it
    {
        auto s = Session::openProject(dir, smallConfig());
        EXPECT_EQ(s->recoveredEdits(), steps);
        ASSERT_EQ(s->history().done().size(), steps);
        EXPECT_EQ(s->history().done().back().op, core::ToolOp::Smooth);
        EXPECT_EQ(weightsOf(s->sculpture()), expected);
    }
    std::filesystem::remove_all(dir);
}

TEST(AsyncStrokeFinish, ASaveRightAfterThePenLiftHoldsTheStroke) {
    const std::filesystem::path dir = tempProject("save");
    Weights expected;
    {
        auto s = Session::openProject(dir, smallConfig());
        s->setAsyncStrokeFinish(true);
        play(*s, kArm);
        play(*s, kSmooth);
        ASSERT_TRUE(s->strokeFinishing());
        ASSERT_TRUE(s->saveInBackground());  // the snapshot is of the completed stroke
        EXPECT_FALSE(s->strokeFinishing());
        s->pollSave(true);
        expected = weightsOf(s->sculpture());
        EXPECT_FALSE(s->hasJournaledEdits());
    }
    {
        auto s = Session::openProject(dir, smallConfig());
        EXPECT_EQ(s->recoveredEdits(), 0u);  // all of it from the snapshot
        EXPECT_EQ(weightsOf(s->sculpture()), expected);
    }
    std::filesystem::remove_all(dir);
}

TEST(AsyncStrokeFinish, TheStudiosTimelineTakesTheStrokeWhenItIsCompleted) {
    Studio studio(smallConfig());
    studio.setAsyncMeshing(true);
    studio.setAsyncStrokeFinish(true);
    for (const ScriptCommand& c : parseScript(kArm, "arm.vsc").commands)
        studio.apply(c);
    const size_t steps = studio.stepCount();
    studio.setTool(ToolKind::Smooth);
    studio.beginStroke();
    for (const core::Vec3& p :
         {core::Vec3(40, 3.4, 0), core::Vec3(54, 3.4, 0), core::Vec3(68, 3.4, 0)})
        studio.strokeSample(p, false);
    studio.endStroke();
    ASSERT_TRUE(studio.session().strokeFinishing());
    EXPECT_EQ(studio.stepCount(), steps);
    EXPECT_TRUE(studio.pollStrokeFinish(true));
    EXPECT_EQ(studio.stepCount(), steps + 1);
    // One undo of the timeline takes the smooth back.
    Session sync(smallConfig());
    play(sync, kArm);
    studio.undo();
    EXPECT_EQ(weightsOf(studio.session().sculpture()), weightsOf(sync.sculpture()));
}

TEST(AsyncStrokeFinish, StrokesWithNothingToEstimateCompleteAtOnce) {
    Session s(smallConfig());
    s.setAsyncStrokeFinish(true);
    play(s, kArm);
    EXPECT_FALSE(s.strokeFinishing());  // adds have no pen-lift estimate
    // A smooth over the fresh sphere changes no weight: nothing to estimate either.
    play(s, "zoom 1\nsize 5\ntool smooth\nstroke -20 -40 0 20 -40 4\n");
    EXPECT_FALSE(s.strokeFinishing());
    EXPECT_EQ(s.history().done().back().op, core::ToolOp::Smooth);
}

// placement.refine_levels: an add's or carve's refinement is its pen-lift work, run off the
// frame the same way (core: StrokeBuilder::beginFinish). The same clay, steps and journal as
// finishing at once; a project reopened with a config without the setting keeps its own.
TEST(AsyncStrokeFinish, RefinedStrokesCompleteOffTheFrameToTheSameClayAndJournal) {
    const char* kStrokes = R"(zoom 3 28 -20 16
size 4
tool add
stroke 30 -20 20 33 -14 19 36 -8 18
tool carve
stroke 20 -30 18 27 -25 16 34 -18 12
)";
    core::SculptConfig cfg = smallConfig();
    cfg.refineLevels = 2;
    const std::filesystem::path syncDir = tempProject("refine-sync"),
                                asyncDir = tempProject("refine-async");
    Weights start, expected;
    std::vector<core::StrokeRecord> expectedSteps;
    {
        auto s = Session::openProject(syncDir, cfg);
        start = weightsOf(s->sculpture());
        play(*s, kStrokes);
        expected = weightsOf(s->sculpture());
        for (const core::StrokeRecord& r : s->history().done())
            expectedSteps.push_back(r);
    }
    ASSERT_EQ(expectedSteps.size(), 2u);
    for (const core::StrokeRecord& r : expectedSteps) {
        int fine = 0;
        for (const core::SkeletonChange& c : r.changes)
            fine += c.level == r.level - 2;
        EXPECT_GT(fine, 0) << core::toString(r.op) << " not refined";
    }
    {
        auto s = Session::openProject(asyncDir, cfg);
        s->setAsyncMeshing(true);
        s->setAsyncStrokeFinish(true);
        play(*s, "zoom 3 28 -20 16\nsize 4\ntool add\nstroke 30 -20 20 33 -14 19 36 -8 18\n");
        EXPECT_TRUE(s->strokeFinishing());  // the refinement runs on its own thread
        EXPECT_EQ(s->history().done().size(), 0u);
        play(*s, "tool carve\nstroke 20 -30 18 27 -25 16 34 -18 12\n");  // waits for the add
        ASSERT_EQ(s->history().done().size(), 1u);
        EXPECT_TRUE(s->pollStrokeFinish(true));
        expectSameAs(*s, expected, expectedSteps);
        ASSERT_TRUE(s->undo());
        ASSERT_TRUE(s->undo());
        EXPECT_EQ(weightsOf(s->sculpture()), start);
        ASSERT_TRUE(s->redo());
        ASSERT_TRUE(s->redo());
    }
    for (const auto& dir : {syncDir, asyncDir}) {
        auto s = Session::openProject(dir, smallConfig());
        EXPECT_EQ(s->sculpture().config().refineLevels, 2) << dir;
        EXPECT_EQ(weightsOf(s->sculpture()), expected) << dir;
    }
    std::filesystem::remove_all(syncDir);
    std::filesystem::remove_all(asyncDir);
}
