// SPDX-License-Identifier: MIT
// Importing a mesh in the background (the windows; ImportInBackground.h): the frame never
// waits for the file or the placement, and what lands is exactly what the waiting import
// (Studio::importMesh) makes at the moment it lands, with sculpting going on meanwhile,
// cancelled, failed or reopened from the project's journal.
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/studio/Studio.h"

#include "../TestFixtures.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

using namespace vsculpt;
using core::Vec3;
using studio::Studio;
using test::TempDir;

namespace {

/// Every skeleton, bit for bit: two sculptures are the same clay exactly when these are equal.
std::map<std::tuple<int, int, int, int>, uint32_t> skeletons(const Studio& s) {
    std::map<std::tuple<int, int, int, int>, uint32_t> all;
    s.session().sculpture().store().forEach([&](const core::SkeletonEntry& e) {
        uint32_t bits;
        std::memcpy(&bits, &e.weight, sizeof bits);
        all[{e.level, e.coord.x, e.coord.y, e.coord.z}] = bits;
    });
    return all;
}

/// A lopsided little sculpture exported as a mesh file to import.
std::filesystem::path meshFile(const TempDir& dir) {
    studio::Session s(test::smallConfig(0));
    s.setSize(5);
    s.stroke({Vec3(0, 0, 0), Vec3(0, 0, 30)}, false);
    s.stroke({Vec3(0, 0, 0), Vec3(25, 0, 0)}, false);
    const auto path = dir.path / "part.stl";
    core::exportMesh(s.wholeMesh(1.5), path);
    return path;
}

/// The stroke the sculptor makes while the import runs (size 5): over the initial sphere and
/// into where the imported part lands, so a placement against the clay as it was would differ.
const std::vector<Vec3> kMeanwhile{Vec3(-20, 0, 15), Vec3(0, 0, 20), Vec3(20, 0, 15)};

/// What the sculptor asked for, in the order it landed: that stroke, then the waiting import.
std::map<std::tuple<int, int, int, int>, uint32_t> strokeThenImport(
    const std::filesystem::path& file) {
    Studio waited(test::smallConfig(20));
    waited.setSize(5);
    waited.stroke(kMeanwhile, false);
    waited.importMesh(file);
    return skeletons(waited);
}

}  // namespace

TEST(ImportInBackground, LandsAsTheClayTheWaitingImportMakesAndUndoesToTheStart) {
    TempDir dir;
    const auto file = meshFile(dir);
    Studio waited(test::smallConfig(20));
    const int level = waited.importMesh(file);

    Studio background(test::smallConfig(20));
    const auto start = skeletons(background);
    background.importMeshInBackground(file);
    ASSERT_TRUE(background.importStatus());
    EXPECT_NE(background.importStatus()->find(file.string()), std::string::npos);
    bool failed = true;
    const std::optional<std::string> said = background.pollImport(true, &failed);
    ASSERT_TRUE(said);
    EXPECT_FALSE(failed) << *said;
    EXPECT_NE(said->find("level " + std::to_string(level)), std::string::npos) << *said;
    EXPECT_FALSE(background.importStatus());
    EXPECT_EQ(background.stepCount(), 1u);
    EXPECT_EQ(skeletons(background), skeletons(waited));
    EXPECT_EQ(test::viewHash(background.session()), test::viewHash(waited.session()));
    EXPECT_FALSE(background.pollImport(true)) << "one import, one outcome";
    ASSERT_TRUE(background.undo());
    EXPECT_EQ(skeletons(background), start);
}

TEST(ImportInBackground, SculptingMeanwhilePlacesItAgainOnTheClayAsItIsThen) {
    TempDir dir;
    const auto file = meshFile(dir);
    Studio background(test::smallConfig(20));
    const auto start = skeletons(background);
    background.importMeshInBackground(file);
    background.setSize(5);
    background.stroke(kMeanwhile, false);  // does not wait: the import's copy is not this clay
    ASSERT_TRUE(background.pollImport(true));
    EXPECT_EQ(background.stepCount(), 2u);
    EXPECT_EQ(skeletons(background), strokeThenImport(file));
    ASSERT_TRUE(background.undo());
    ASSERT_TRUE(background.undo());
    EXPECT_EQ(skeletons(background), start);
}

TEST(ImportInBackground, AStrokeInProgressIsFinishedBeforeTheImportLands) {
    TempDir dir;
    const auto file = meshFile(dir);
    Studio background(test::smallConfig(20));
    background.importMeshInBackground(file);
    background.setSize(5);
    background.beginStroke();
    background.strokeSample(kMeanwhile[0], false);
    background.strokeSample(kMeanwhile[1], false);
    // However long the import takes, it does not land inside the stroke.
    for (int i = 0; i < 50; ++i)
        EXPECT_FALSE(background.pollImport(false));
    background.strokeSample(kMeanwhile[2], false);
    background.endStroke();
    ASSERT_TRUE(background.pollImport(true));
    EXPECT_EQ(skeletons(background), strokeThenImport(file));
}

TEST(ImportInBackground, ACancelledImportAddsNothingAndAFailedOneSaysWhy) {
    TempDir dir;
    const auto file = meshFile(dir);
    Studio s(test::smallConfig(20));
    const auto start = skeletons(s);
    s.importMeshInBackground(file);
    EXPECT_THROW(s.importMeshInBackground(file), studio::SessionError) << "one at a time";
    EXPECT_TRUE(s.cancelImport());
    EXPECT_FALSE(s.cancelImport());
    EXPECT_FALSE(s.importStatus());
    EXPECT_FALSE(s.pollImport(true));
    EXPECT_EQ(s.stepCount(), 0u);
    EXPECT_EQ(skeletons(s), start);

    // A file that is not a mesh: refused by the thread, said by the poll, nothing added.
    const auto bad = dir.path / "bad.stl";
    std::ofstream(bad) << "solid nothing\nthis is not STL\n";
    s.importMeshInBackground(bad);
    bool failed = false;
    const std::optional<std::string> said = s.pollImport(true, &failed);
    ASSERT_TRUE(said);
    EXPECT_TRUE(failed);
    EXPECT_NE(said->find(bad.string()), std::string::npos) << *said;
    EXPECT_EQ(s.stepCount(), 0u);
    EXPECT_EQ(skeletons(s), start);

    // A new import works after both, and a cancelled one still running when the studio goes
    // is waited for by its destructor (the sanitizer job checks nothing outlives it).
    s.importMeshInBackground(file);
    ASSERT_TRUE(s.pollImport(true));
    EXPECT_EQ(s.stepCount(), 1u);
    s.importMeshInBackground(file);
    s.cancelImport();
}

TEST(ImportInBackground, AProjectReopensWithTheImportFromItsJournal) {
    TempDir dir;
    const auto file = meshFile(dir);
    const auto project = dir.path / "p";
    std::map<std::tuple<int, int, int, int>, uint32_t> landed;
    {
        auto s = Studio::openProject(project, test::smallConfig(20));
        s->importMeshInBackground(file);
        ASSERT_TRUE(s->pollImport(true));
        landed = skeletons(*s);
        // No save: the journal alone must hold it.
    }
    std::filesystem::remove(file);  // the project does not need the file
    auto again = Studio::openProject(project, test::smallConfig(20));
    EXPECT_EQ(again->stepCount(), 1u);
    EXPECT_EQ(skeletons(*again), landed);
}
