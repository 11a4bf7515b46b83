// SPDX-License-Identifier: MIT
#include "vsculpt/studio/Session.h"

#include "vsculpt/core/Project.h"

#include "../TestFiles.h"
#include "../TestFixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <optional>
#include <random>

using namespace vsculpt;
using namespace vsculpt::studio;
using core::Vec3;

namespace {

using test::readFile;
using test::smallConfig;
using test::TempDir;

using test::viewHash;

void sculptSome(Session& s, int strokes, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-35, 35);
    for (int i = 0; i < strokes; ++i) {
        s.setTool(i % 3 == 2 ? ToolKind::Carve : ToolKind::Add);
        s.setSize(5 + i % 3);
        std::vector<Vec3> pts;
        Vec3 p(U(rng), U(rng), U(rng));
        for (int k = 0; k < 6; ++k)
            pts.push_back(p + Vec3(k * 3.0, 0.5 * k, 0));
        s.stroke(pts, false);
    }
}

/// Zooms in, strokes, undoes and redoes, has a sample refused (the whole stroke is rolled back,
/// on an async mesher's replica too) and zooms out again.
void zoomInStrokeAndUndo(Session& s) {
    s.setZoom(3, Vec3(0, 0, 30));
    s.setSize(4);
    s.stroke({Vec3(-3, 0, 30), Vec3(3, 1, 30)}, false);
    s.undo();
    s.redo();
    s.undo();
    EXPECT_THROW(s.stroke({Vec3(0, 0, 30), Vec3(2, 0, 30), Vec3(1e7, 0, 0)}, false), SessionError);
    s.setZoom(1, Vec3(0.0));
}

TEST(Session, UndoToTheStartAndRedoToTheEnd) {
    Session s(smallConfig());
    const uint64_t start = viewHash(s);
    sculptSome(s, 10, 1);
    const uint64_t end = viewHash(s);
    ASSERT_NE(start, end);
    while (s.undo()) {
    }
    EXPECT_EQ(viewHash(s), start);
    EXPECT_EQ(s.sculpture().store().vertexCount(), 0u);
    while (s.redo()) {
    }
    EXPECT_EQ(viewHash(s), end);
    EXPECT_EQ(s.verifyMesh(), "");
    // A new stroke after an undo drops the redo steps.
    s.undo();
    sculptSome(s, 1, 2);
    EXPECT_FALSE(s.redo());
}

TEST(Session, AsyncMeshingEndsWhereSyncMeshingEnds) {
    Session sync(smallConfig()), async(smallConfig());
    async.setAsyncMeshing(true);
    EXPECT_TRUE(async.asyncMeshing());
    EXPECT_THROW(async.view(), std::logic_error);  // the live polygonizer is the mesher's
    for (Session* s : {&sync, &async}) {
        sculptSome(*s, 6, 3);
        zoomInStrokeAndUndo(*s);
        sculptSome(*s, 2, 4);
    }
    async.waitForMesh();
    const auto shown = async.published();
    EXPECT_TRUE(shown->complete);
    EXPECT_FALSE(shown->preview);
    EXPECT_EQ(shown->region, sync.region());
    EXPECT_EQ(core::canonicalMeshHash(shown->merged()), viewHash(sync));
    EXPECT_EQ(core::canonicalMeshHash(sync.published()->merged()), viewHash(sync));
    EXPECT_EQ(async.verifyMesh(), "");
    EXPECT_FALSE(async.takePublishDelaysMs().empty());
    EXPECT_TRUE(sync.takePublishDelaysMs().empty());
    // Switching back keeps the mesh.
    async.setAsyncMeshing(false);
    EXPECT_EQ(viewHash(async), viewHash(sync));
}

TEST(Session, DeferredMeshingEndsWhereMeshingEveryEditEnds) {
    Session now(smallConfig()), later(smallConfig());
    later.setDeferredMeshing(true);
    EXPECT_TRUE(later.deferredMeshing());
    for (Session* s : {&now, &later}) {
        sculptSome(*s, 6, 3);
        // Looked at midway: brought up to date, then deferred again.
        EXPECT_EQ(s->verifyMesh(), "");
        sculptSome(*s, 3, 5);
        zoomInStrokeAndUndo(*s);
        sculptSome(*s, 2, 4);
        s->undo();
    }
    EXPECT_EQ(later.region(), now.region());
    EXPECT_EQ(core::canonicalMeshHash(later.published()->merged()), viewHash(now));
    EXPECT_EQ(viewHash(later), viewHash(now));
    EXPECT_EQ(later.verifyMesh(), "");
    // Edits after a look, then switched off: the mesh is current before the call returns.
    sculptSome(now, 2, 6);
    sculptSome(later, 2, 6);
    later.setDeferredMeshing(false);
    EXPECT_EQ(viewHash(later), viewHash(now));
    EXPECT_EQ(later.verifyMesh(), "");
}

TEST(Session, SizesFollowTheZoomTable) {
    Session s(smallConfig());
    EXPECT_THROW(s.setSize(3), SessionError);  // zoom 1 offers 7, 6, 5
    s.setSize(5);
    s.setZoom(4, Vec3(0, 0, 30));
    EXPECT_EQ(s.size(), 4);  // 5 is not offered at zoom 4: the nearest offered size
    EXPECT_NO_THROW(s.setSize(2));
    s.setTool(ToolKind::Select);
    EXPECT_THROW(s.stroke({Vec3(0, 0, 30)}, false), SessionError);
}

TEST(Session, AZoomAtAPointTheLatticesCannotHoldIsRefusedChangingNothing) {
    // A device's garbage pose reaches setZoom through the select tool's step: a refusal the
    // input layers report (SessionError), never a std::invalid_argument that ends the program.
    Session s(smallConfig());
    s.setSize(5);
    s.setZoom(3, Vec3(0, 0, 30));
    const core::GridRegion before = s.region();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const Vec3& c : {Vec3(1e300, 0, 0), Vec3(0, -1e6, 0), Vec3(nan, 0, 0)}) {
        EXPECT_THROW(s.setZoom(4, c), SessionError) << c.x << " " << c.y;
        EXPECT_EQ(s.zoom(), 3);
        EXPECT_EQ(s.size(), 5);
        EXPECT_EQ(s.region(), before);
    }
    EXPECT_NO_THROW(s.setZoom(1, Vec3(nan, nan, nan)));  // zoom 1 ignores the centre
    EXPECT_EQ(s.zoom(), 1);
}

TEST(Session, ARefusedSampleCancelsTheWholeStroke) {
    Session s(smallConfig());
    const uint64_t before = viewHash(s);
    s.setSize(5);
    // A refusal is the user's input (SessionError), never an invariant failure (logic_error).
    EXPECT_THROW(s.stroke({Vec3(0, 0, 30), Vec3(5, 0, 30), Vec3(1e7, 0, 0)}, false), SessionError);
    EXPECT_EQ(viewHash(s), before);
    EXPECT_EQ(s.sculpture().store().vertexCount(), 0u);
    EXPECT_FALSE(s.history().canUndo());
}

TEST(Session, WorldSpaceStrokesFollowTheObjectPose) {
    Session a(smallConfig()), b(smallConfig());
    core::RigidTransform pose;
    pose.rotation = glm::angleAxis(glm::radians(90.0), Vec3(1, 0, 0));
    pose.translation = Vec3(5, 6, 7);
    b.setObjectPose(pose);
    std::vector<Vec3> objectPts = {Vec3(0, 0, 30), Vec3(8, 2, 31)}, worldPts;
    for (const Vec3& p : objectPts)
        worldPts.push_back(pose.apply(p));
    a.stroke(objectPts, false);
    b.stroke(worldPts, true);
    EXPECT_EQ(viewHash(a), viewHash(b));
}

TEST(Session, ProjectSaveAndReopenGivesTheSameSculptureAndHistory) {
    TempDir dir;
    uint64_t end = 0, mid = 0;
    {
        auto s = Session::openProject(dir.path, smallConfig());
        sculptSome(*s, 4, 3);
        s->save();
        sculptSome(*s, 3, 4);  // journaled after the snapshot
        s->undo();
        mid = viewHash(*s);
        s->redo();
        end = viewHash(*s);
    }
    auto s = Session::openProject(dir.path, core::SculptConfig{});  // stored config wins
    EXPECT_EQ(s->recoveredEdits(), 5u);                             // 3 strokes, undo, redo
    EXPECT_EQ(viewHash(*s), end);
    EXPECT_EQ(s->sculpture().config().polygonizer.gridN, 64);
    s->undo();
    EXPECT_EQ(viewHash(*s), mid);
    while (s->undo()) {
    }
    Session fresh(smallConfig());
    EXPECT_EQ(viewHash(*s), viewHash(fresh));
}

// What the windows snapshot when they close: edits in the journal that the snapshot lacks.
TEST(Session, JournaledEditsAreThoseTheSnapshotLacks) {
    TempDir dir;
    {
        auto s = Session::openProject(dir.path, smallConfig());
        EXPECT_FALSE(s->hasJournaledEdits());  // a new project starts with its snapshot
        sculptSome(*s, 2, 3);
        EXPECT_TRUE(s->hasJournaledEdits());
        s->save();
        EXPECT_FALSE(s->hasJournaledEdits());
        s->undo();
        EXPECT_TRUE(s->hasJournaledEdits());  // an undo is an edit too
    }
    {
        auto s = Session::openProject(dir.path, core::SculptConfig{});
        EXPECT_EQ(s->recoveredEdits(), 1u);
        EXPECT_TRUE(s->hasJournaledEdits());  // replayed from the journal, not yet snapshotted
        auto r = Session::openProject(dir.path, core::SculptConfig{}, ProjectMode::ReadOnly);
        EXPECT_FALSE(r->hasJournaledEdits());  // read-only: nothing it could save
        s->save();
    }
    auto s = Session::openProject(dir.path, core::SculptConfig{});
    EXPECT_EQ(s->recoveredEdits(), 0u);
    EXPECT_FALSE(s->hasJournaledEdits());
    Session plain(smallConfig());  // no project
    sculptSome(plain, 1, 3);
    EXPECT_FALSE(plain.hasJournaledEdits());
}

// F5 in the windows: the snapshot is written beside further edits. Whenever the thread
// finishes (before, between or after the edits below: the test holds either way), the
// snapshot holds the edits made before the request, the restarted journal exactly the ones
// after it, and reopening gives every edit.
TEST(Session, ABackgroundSaveHoldsTheClayAsAskedAndTheJournalTheEditsSince) {
    TempDir dir;
    uint64_t end = 0, atRequest = 0;
    {
        auto s = Session::openProject(dir.path, smallConfig());
        sculptSome(*s, 3, 5);
        atRequest = viewHash(*s);
        ASSERT_TRUE(s->saveInBackground());
        EXPECT_TRUE(s->saving());
        sculptSome(*s, 2, 6);  // while it may still be writing
        s->undo();
        bool failed = true;
        const std::optional<std::string> outcome = s->pollSave(true, &failed);
        ASSERT_TRUE(outcome);
        EXPECT_EQ(*outcome, "saved " + dir.path.string());
        EXPECT_FALSE(failed);
        EXPECT_FALSE(s->saving());
        EXPECT_FALSE(s->pollSave(true));      // said once
        EXPECT_TRUE(s->hasJournaledEdits());  // the three edits after the request
        const core::SnapshotContents snap = core::readSnapshot(core::snapshotPath(dir.path));
        EXPECT_EQ(snap.lastSequence, 3u);
        EXPECT_EQ(snap.done.size(), 3u);
        std::vector<uint64_t> journaled;
        for (const core::JournalRecord& r : core::readJournal(core::journalPath(dir.path)).records)
            journaled.push_back(r.sequence);
        EXPECT_EQ(journaled, (std::vector<uint64_t>{4, 5, 6}));
        // Destroyed with a save in flight: it is finished, not dropped.
        sculptSome(*s, 1, 7);
        ASSERT_TRUE(s->saveInBackground());
        sculptSome(*s, 1, 8);
        end = viewHash(*s);
    }
    EXPECT_EQ(core::readSnapshot(core::snapshotPath(dir.path)).lastSequence, 7u);
    EXPECT_EQ(core::readJournal(core::journalPath(dir.path)).records.size(), 1u);
    auto s = Session::openProject(dir.path, core::SculptConfig{});
    EXPECT_TRUE(s->recoveryWarning().empty()) << s->recoveryWarning();
    EXPECT_EQ(s->recoveredEdits(), 1u);
    EXPECT_EQ(viewHash(*s), end);
    // The clay as it was at the first request is three undos back (of the four strokes since,
    // one was undone and its redo dropped by the next stroke).
    s->undo();
    s->undo();
    EXPECT_NE(viewHash(*s), atRequest);
    s->undo();
    EXPECT_EQ(viewHash(*s), atRequest);
}

TEST(Session, ABackgroundSaveIsRefusedWhereASaveIs) {
    TempDir dir;
    {
        auto s = Session::openProject(dir.path, smallConfig());
        sculptSome(*s, 1, 5);
    }
    auto r = Session::openProject(dir.path, smallConfig(), ProjectMode::ReadOnly);
    EXPECT_THROW(r->saveInBackground(), SessionError);
    EXPECT_FALSE(r->saving());
    Session plain(smallConfig());
    EXPECT_FALSE(plain.saveInBackground());  // no project: nothing to save
    EXPECT_FALSE(plain.pollSave(true));
}

// Found by fuzzing: `vsculpt render FOLDER` of a folder that is not a project left a lock
// file there before it said so. A reader now refuses first and writes nothing.
TEST(Session, AReaderOfAFolderThatIsNoProjectLeavesItUntouched) {
    TempDir dir;
    std::filesystem::create_directories(dir.path / "photos");
    std::string what;
    try {
        Session::openProject(dir.path / "photos", smallConfig(), ProjectMode::ReadOnly);
    } catch (const core::ProjectError& e) {
        what = e.what();
    }
    EXPECT_EQ(what, (dir.path / "photos").string() + ": not a vsculpt project (no snapshot.vsnap)");
    EXPECT_TRUE(std::filesystem::is_empty(dir.path / "photos"));
}

TEST(Session, AProjectKeepsThePlacementModeItWasMadeWith) {
    // Made in `free` mode (the default before `swept`): reopened with today's default config,
    // its journal replays with the rule that made it, to the same mesh.
    TempDir dir;
    core::SculptConfig made = smallConfig();
    made.placement = core::PlacementMode::Free;
    ASSERT_NE(core::SculptConfig{}.placement, made.placement);
    uint64_t end = 0;
    {
        auto s = Session::openProject(dir.path, made);
        sculptSome(*s, 4, 7);
        end = viewHash(*s);
    }
    auto s = Session::openProject(dir.path, core::SculptConfig{});
    EXPECT_EQ(s->sculpture().config().placement, core::PlacementMode::Free);
    EXPECT_EQ(s->recoveredEdits(), 4u);
    EXPECT_EQ(viewHash(*s), end);
}

TEST(Session, AProjectKeepsTheLatticeItsStrokesWerePlacedOn) {
    // Made with placement.finer_lattice_levels = 2: reopened with the default config (0), its
    // journal replays on the finer lattice to the same mesh, and new strokes go there too.
    TempDir dir;
    core::SculptConfig made = smallConfig();
    made.finerLatticeLevels = 2;
    ASSERT_NE(core::SculptConfig{}.finerLatticeLevels, made.finerLatticeLevels);
    uint64_t end = 0;
    {
        auto s = Session::openProject(dir.path, made);
        sculptSome(*s, 2, 5);
        end = viewHash(*s);
    }
    auto s = Session::openProject(dir.path, core::SculptConfig{});
    EXPECT_EQ(s->sculpture().config().finerLatticeLevels, 2);
    EXPECT_EQ(s->recoveredEdits(), 2u);
    EXPECT_EQ(viewHash(*s), end);
    sculptSome(*s, 3, 6);  // sizes 5, 6 and 7: weights on levels 3, 4 and 5
    int highest = 0;
    s->sculpture().store().forEach(
        [&](const core::SkeletonEntry& e) { highest = std::max(highest, e.level); });
    EXPECT_EQ(highest, 5);
}

TEST(Session, AProjectMadeBeforeTheSpheresCoreKeepsItsOneSkeletonSphere) {
    // A project written before initial_sphere.core_weight existed (its stored config lacks the
    // key; emulated by rewriting the start snapshot without it): reopened with today's default
    // config, it keeps the one-skeleton sphere and its journal replays to the same mesh. A
    // project made today stores the core and keeps it.
    TempDir dir;
    core::SculptConfig made = smallConfig();
    made.sphereCoreWeight = 0;
    ASSERT_GT(core::SculptConfig{}.sphereCoreWeight, 0);
    uint64_t end = 0;
    {
        auto s = Session::openProject(dir.path, made);
        sculptSome(*s, 4, 7);
        end = viewHash(*s);
    }
    nlohmann::json stored = nlohmann::json::parse(core::configToJson(made));
    stored["initial_sphere"].erase("core_weight");
    stored["initial_sphere"].erase("core_support_over_radius");
    core::writeProjectSnapshot(dir.path, stored.dump(), 0, core::Sculpture(made), core::History{});
    {
        auto s = Session::openProject(dir.path, core::SculptConfig{});
        EXPECT_EQ(s->sculpture().config().sphereCoreWeight, 0.0);
        EXPECT_EQ(s->sculpture().counts().point, 1u);
        EXPECT_EQ(s->recoveredEdits(), 4u);
        EXPECT_EQ(viewHash(*s), end);
    }
    TempDir today;
    { Session::openProject(today.path, smallConfig()); }
    auto s = Session::openProject(today.path, made);  // the project's config wins
    EXPECT_EQ(s->sculpture().config().sphereCoreWeight, smallConfig().sphereCoreWeight);
    EXPECT_EQ(s->sculpture().counts().point, 2u);
}

TEST(Session, DamagedJournalTailIsDroppedAndReported) {
    TempDir dir;
    uint64_t afterTwo = 0;
    {
        auto s = Session::openProject(dir.path, smallConfig());
        sculptSome(*s, 2, 5);
        afterTwo = viewHash(*s);
        sculptSome(*s, 1, 6);
    }
    const auto journal = core::journalPath(dir.path);
    const auto size = std::filesystem::file_size(journal);
    std::filesystem::resize_file(journal, size - 7);  // the last record torn
    const std::string torn = readFile(journal);
    {
        auto s = Session::openProject(dir.path, smallConfig());
        EXPECT_EQ(s->recoveredEdits(), 2u);
        EXPECT_NE(s->recoveryWarning().find("is truncated"), std::string::npos)
            << s->recoveryWarning();
        // The journal as it was, torn record and all, is kept before the writer cuts it.
        const auto kept = dir.path / "journal.vjl.damaged";
        EXPECT_NE(s->recoveryWarning().find(journal.string() +
                                            " as it was (with what could not "
                                            "be replayed) is kept in " +
                                            kept.string()),
                  std::string::npos)
            << s->recoveryWarning();
        EXPECT_EQ(readFile(kept), torn);
        EXPECT_EQ(viewHash(*s), afterTwo);
        sculptSome(*s, 1, 6);  // appends after the good prefix
    }
    {
        // Flip a byte inside the second record: the first survives, the rest is dropped.
        std::fstream f(journal, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(0, std::ios::end);
        const auto n = f.tellg();
        f.seekp(n / 2);
        char c;
        f.seekg(n / 2);
        f.read(&c, 1);
        c ^= 0x5A;
        f.seekp(n / 2);
        f.write(&c, 1);
    }
    auto s = Session::openProject(dir.path, smallConfig());
    EXPECT_LT(s->recoveredEdits(), 3u);
    EXPECT_FALSE(s->recoveryWarning().empty());
    EXPECT_EQ(s->verifyMesh(), "");
}

TEST(Session, DamagedSnapshotIsRecoveredFromItsBackup) {
    TempDir dir;
    uint64_t expected = 0;
    {
        auto s = Session::openProject(dir.path, smallConfig());
        sculptSome(*s, 2, 7);
        s->save();  // the first snapshot with edits; the empty one becomes its backup
        sculptSome(*s, 2, 8);
        s->save();             // the previous snapshot and its journal become the backup
        sculptSome(*s, 1, 9);  // journaled only
        expected = viewHash(*s);
    }
    const auto snap = core::snapshotPath(dir.path);
    std::filesystem::resize_file(snap, std::filesystem::file_size(snap) - 10);
    {
        // One damaged snapshot loses nothing: backup + its journal + the journal.
        auto s = Session::openProject(dir.path, smallConfig());
        EXPECT_EQ(viewHash(*s), expected);
        EXPECT_NE(s->recoveryWarning().find("snapshot.vsnap"), std::string::npos)
            << s->recoveryWarning();
        EXPECT_EQ(s->verifyMesh(), "");
    }
    // With the backup damaged too nothing usable is left: a clear error naming the file.
    const std::filesystem::path backup = snap.string() + ".bak";
    std::filesystem::resize_file(backup, std::filesystem::file_size(backup) / 2);
    try {
        Session::openProject(dir.path, smallConfig());
        FAIL() << "no error";
    } catch (const core::ProjectError& e) {
        EXPECT_NE(std::string(e.what()).find("snapshot.vsnap"), std::string::npos) << e.what();
    }
}

TEST(Session, ConfigRoundTripsThroughJson) {
    core::SculptConfig cfg = smallConfig();
    cfg.placement = core::PlacementMode::Thesis;
    cfg.growth = 1.4;
    cfg.zoom.allowedSizes[2] = {5, 4};
    cfg.manualSupport = core::ManualSupport{6, {0.2, 0.4, 0.7, 1, 1.5, 2, 3}};
    const core::SculptConfig back = core::parseConfig(core::configToJson(cfg), "x");
    EXPECT_EQ(core::configToJson(back), core::configToJson(cfg));
    EXPECT_EQ(back.growth, 1.4);
    EXPECT_EQ(back.placement, core::PlacementMode::Thesis);
    EXPECT_EQ(back.zoom.allowedSizes[2], (std::vector<int>{5, 4}));
}

}  // namespace

namespace {

// Key bindings, display and lens, USB tables and tracker calibration belong to the machine:
// a project does not store them, and a reopened project takes them from the config in use.
TEST(Session, AReopenedProjectTakesTheMachineSettingsOfTheConfigInUse) {
    TempDir dir;
    core::SculptConfig first = smallConfig();
    first.render.ipdMm = 61;
    first.interaction.bindings["undo"] = "U";
    first.devices.penStation = 1;
    {
        auto s = Session::openProject(dir.path, first);
        s->stroke({Vec3(0, 0, 30), Vec3(4, 0, 30)}, false);
        s->save();
    }
    core::SculptConfig second = smallConfig();
    second.sphereRadiusMm = 12;  // a sculpture setting: the project's own wins
    second.render.ipdMm = 70;
    second.interaction.bindings["undo"] = "Y";
    second.devices.penStation = 3;
    auto s = Session::openProject(dir.path, second);
    const core::SculptConfig& used = s->sculpture().config();
    EXPECT_EQ(used.sphereRadiusMm, 30);
    EXPECT_EQ(used.render.ipdMm, 70);
    EXPECT_EQ(used.interaction.bindings.at("undo"), "Y");
    EXPECT_EQ(used.devices.penStation, 3);
    // The snapshot holds no machine section at all.
    const core::SnapshotContents snap = core::readSnapshot(core::snapshotPath(dir.path));
    for (const char* section : {"\"render\"", "\"interaction\"", "\"devices\""})
        EXPECT_EQ(snap.configJson.find(section), std::string::npos) << section;
}

}  // namespace
