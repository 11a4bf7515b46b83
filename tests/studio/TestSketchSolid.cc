// SPDX-License-Identifier: MIT
// A sketched solid added to a sculpting session (issue #7 item 7): one undo step, the same
// polygonizer (incremental == full), watertight result, journaled and recovered exactly.
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/studio/Session.h"

#include "../TestFixtures.h"
#include "../TestSolids.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

using namespace vsculpt;
using namespace vsculpt::studio;
using core::Vec3;

namespace {

using test::smallConfig;
using test::TempDir;

using test::viewHash;

// A solid that overlaps the initial sphere (radius 30) and reaches out of it.
core::Mesh armSolid() {
    return core::boxMesh(Vec3(15, -8, -8), Vec3(60, 8, 8));
}

TEST(SketchSolid, JoinsTheClayAsOneUndoStep) {
    Session s(smallConfig());
    const uint64_t start = viewHash(s);
    const double volumeBefore = core::meshVolume(s.wholeMesh());
    const int level = s.addSolid(armSolid());
    EXPECT_GE(level, 1);
    EXPECT_EQ(s.history().done().size(), 1u);
    EXPECT_TRUE(s.history().done().back().solid);
    const uint64_t after = viewHash(s);
    EXPECT_NE(after, start);
    EXPECT_EQ(s.verifyMesh(), "");
    const core::Mesh whole = s.wholeMesh();
    const core::MeshTopology topo = core::analyzeTopology(whole);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.components, 1u);  // joined, not a separate lump
    // The arm outside the sphere: 45 x 16 x 16 minus the part inside the sphere (x < ~28.9 at
    // the arm's axis). The added volume is at least the part clearly outside.
    const double added = core::meshVolume(whole) - volumeBefore;
    EXPECT_GT(added, (60 - 30) * 16 * 16 * 0.8);
    EXPECT_LT(added, (60 - 15) * 16 * 16 * 1.1);

    ASSERT_TRUE(s.undo());
    EXPECT_EQ(viewHash(s), start);
    EXPECT_EQ(s.verifyMesh(), "");
    ASSERT_TRUE(s.redo());
    EXPECT_EQ(viewHash(s), after);
    EXPECT_EQ(s.verifyMesh(), "");
}

TEST(SketchSolid, SculptingOnTheSolidAndUndoingEverythingReturnsToTheStart) {
    Session s(smallConfig());
    const uint64_t start = viewHash(s);
    s.addSolid(armSolid());
    s.setTool(ToolKind::Carve);
    s.setSize(5);
    s.stroke({Vec3(50, -12, 8), Vec3(50, 12, 8)}, false);  // a groove across the arm
    s.setTool(ToolKind::Add);
    s.stroke({Vec3(40, 0, 10), Vec3(55, 0, 10)}, false);
    EXPECT_EQ(s.verifyMesh(), "");
    EXPECT_TRUE(core::analyzeTopology(s.wholeMesh()).watertight());
    while (s.undo()) {
    }
    EXPECT_EQ(viewHash(s), start);
}

TEST(SketchSolid, ProjectKeepsSolidsThroughSnapshotAndJournal) {
    TempDir dir;
    uint64_t expected = 0, expectedAfterUndo = 0;
    {
        auto s = Session::openProject(dir.path, smallConfig());
        s->addSolid(armSolid());
        s->save();  // the first solid goes into the snapshot
        s->addSolid(core::sphereMesh(Vec3(0, 0, 40), 12, 24, 48));  // the second only journaled
        expected = viewHash(*s);
        s->undo();
        expectedAfterUndo = viewHash(*s);
        s->redo();
    }
    auto s = Session::openProject(dir.path, smallConfig());
    EXPECT_EQ(s->recoveryWarning(), "");
    EXPECT_EQ(s->recoveredEdits(), 3u);  // solid, undo, redo
    EXPECT_EQ(viewHash(*s), expected);
    ASSERT_EQ(s->history().done().size(), 2u);
    EXPECT_TRUE(s->history().done()[0].solid);
    EXPECT_TRUE(s->history().done()[1].solid);
    s->undo();
    EXPECT_EQ(viewHash(*s), expectedAfterUndo);
    s->save();
    s.reset();  // closed: a project is open in one place at a time
    auto again = Session::openProject(dir.path, smallConfig());
    EXPECT_EQ(viewHash(*again), expectedAfterUndo);
    again->redo();
    EXPECT_EQ(viewHash(*again), expected);
}

TEST(SketchSolid, BadSolidsAreRefusedWithoutAStep) {
    Session s(smallConfig());
    const uint64_t start = viewHash(s);
    core::Mesh open = armSolid();
    open.indices.resize(open.indices.size() - 3);
    EXPECT_THROW(s.addSolid(open), std::invalid_argument);
    EXPECT_THROW(s.addSolid(armSolid(), 9), std::invalid_argument);
    EXPECT_EQ(viewHash(s), start);
    EXPECT_FALSE(s.history().canUndo());
    // The same solid again, away from other clay: nothing to add, so no empty undo step.
    const core::Mesh lump = core::sphereMesh(Vec3(0, 0, 70), 10, 24, 48);
    s.addSolid(lump);
    const uint64_t once = viewHash(s);
    ASSERT_EQ(s.history().done().size(), 1u);
    s.addSolid(lump);
    EXPECT_EQ(viewHash(s), once);
    EXPECT_EQ(s.history().done().size(), 1u);
}

TEST(SketchSolid, AddingASolidAgainOverClayBarelyMovesTheSurface) {
    // Free mode decides from field values, so over the initial sphere's uneven field a repeat
    // tops up a little (as repeating a stroke does, docs/placement.md), but does not pile up.
    Session s(smallConfig());
    s.addSolid(armSolid());
    const double once = core::meshVolume(s.wholeMesh());
    s.addSolid(armSolid());
    const double twice = core::meshVolume(s.wholeMesh());
    EXPECT_GE(twice, once * (1 - 1e-9));
    EXPECT_LT(twice, once * 1.005) << once << " -> " << twice;
}

}  // namespace
