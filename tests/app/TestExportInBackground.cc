// SPDX-License-Identifier: MIT
// A window's export is meshed and written on its own thread (the frame never waits for it):
// the file holds the clay as it was when the export was asked for, whatever is sculpted
// meanwhile; refusals come at once, before anything starts; closing waits for the file.
// The save key likewise (the last test).
// Read back by Assimp (a third-party loader from Debian).
#include "vsculpt/app/Rig.h"
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/Zoom.h"
#include "vsculpt/studio/Script.h"

#include "../TestFixtures.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <assimp/Importer.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>

using namespace vsculpt;
using core::Vec3;

namespace {

core::SculptConfig smallSphere() {
    return test::smallConfig(25);
}

struct Loaded {
    size_t faces = 0;
    core::Aabb box;
};

Loaded load(const std::filesystem::path& path) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate);
    EXPECT_NE(scene, nullptr) << path << ": " << importer.GetErrorString();
    Loaded out;
    if (!scene) return out;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        out.faces += scene->mMeshes[m]->mNumFaces;
        for (unsigned v = 0; v < scene->mMeshes[m]->mNumVertices; ++v) {
            const aiVector3D& p = scene->mMeshes[m]->mVertices[v];
            out.box.expand(Vec3(p.x, p.y, p.z));
        }
    }
    return out;
}

core::Aabb bounds(const core::Mesh& m) {
    core::Aabb b;
    for (const Vec3& p : m.positions)
        b.expand(p);
    return b;
}

struct ExportInBackground : ::testing::Test {
    test::TempDir temp;
    const std::filesystem::path& dir = temp.path;
};

}  // namespace

TEST_F(ExportInBackground, TheFileHoldsTheClayAsItWasWhenAskedWhileSculptingGoesOn) {
    app::Rig rig(smallSphere(), app::RigOptions{});
    studio::Studio& studio = rig.studio();
    studio.setSize(5);
    studio.stroke({Vec3(-30, 0, 10), Vec3(0, 0, 28), Vec3(30, 0, 10)}, false);
    const core::Mesh asked = rig.session().wholeMesh();
    const std::filesystem::path path = dir / "asked.stl";
    const std::string said = rig.exportTo(path);
    EXPECT_EQ(said.rfind("exporting " + path.string(), 0), 0u) << said;
    // Sculpting goes on at once: a stroke that reaches well beyond the exported clay.
    studio.stroke({Vec3(0, -30, 20), Vec3(0, -45, 35)}, false);
    const core::Mesh after = rig.session().wholeMesh();
    const std::optional<std::string> outcome = rig.pollExport(true);
    ASSERT_TRUE(outcome);
    EXPECT_EQ(*outcome, "exported " + path.string() + " (" + std::to_string(asked.triangleCount()) +
                            " triangles)");
    EXPECT_FALSE(rig.pollExport(true));  // said once
    // The file is the clay as asked (STL: millimetres, Z up, the object's own frame), not
    // as it is now, which differs by more than the comparison's tolerance.
    const Loaded file = load(path);
    EXPECT_EQ(file.faces, asked.triangleCount());
    const core::Aabb want = bounds(asked), now = bounds(after);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(file.box.min[a], want.min[a], 1e-3);
        EXPECT_NEAR(file.box.max[a], want.max[a], 1e-3);
    }
    EXPECT_LT(now.min.y, want.min.y - 5);
    // A second export after the first is done starts as the first did.
    EXPECT_EQ(rig.exportTo(dir / "now.stl").rfind("exporting ", 0), 0u);
    ASSERT_TRUE(rig.pollExport(true));
    EXPECT_EQ(load(dir / "now.stl").faces, after.triangleCount());
}

TEST_F(ExportInBackground, RefusalsComeBeforeAnythingStarts) {
    app::Rig rig(smallSphere(), app::RigOptions{});
    // An unknown format, a frame the format refuses, a folder that is a file: refused with
    // the path named, and nothing is started (nothing to wait for, no file).
    EXPECT_THROW(
        {
            try {
                rig.exportTo(dir / "clay.xyz");
            } catch (const core::ExportError& e) {
                EXPECT_NE(std::string(e.what()).find("clay.xyz"), std::string::npos) << e.what();
                throw;
            }
        },
        core::ExportError);
    core::ExportOptions zUp;
    zUp.up = core::UpAxis::Z;
    EXPECT_THROW(rig.exportTo(dir / "clay.glb", zUp), core::ExportError);
    std::ofstream(dir / "file") << "not a folder";
    EXPECT_ANY_THROW(rig.exportTo(dir / "file" / "clay.stl"));
    EXPECT_FALSE(rig.pollExport(true));
    EXPECT_FALSE(std::filesystem::exists(dir / "clay.xyz"));
    EXPECT_FALSE(std::filesystem::exists(dir / "clay.glb"));
}

TEST_F(ExportInBackground, ClosingWaitsForTheFile) {
    const std::filesystem::path path = dir / "closing.glb";
    size_t triangles = 0;
    {
        app::Rig rig(smallSphere(), app::RigOptions{});
        triangles = rig.session().wholeMesh().triangleCount();
        rig.exportTo(path);
        rig.close();  // what a window does as it goes, right after the export key
        EXPECT_FALSE(rig.pollExport(true));  // close() took the outcome
    }
    ASSERT_TRUE(std::filesystem::exists(path));
    EXPECT_EQ(load(path).faces, triangles);
}

TEST_F(ExportInBackground, TheWindowsExportKeepsTheFinestDetailSculpted) {
    app::Rig rig(smallSphere(), app::RigOptions{});
    studio::Studio& studio = rig.studio();
    const core::SculptConfig& cfg = rig.session().sculpture().config();
    const double zoom1 = core::zoomSpacing(cfg, rig.session().sculpture().levels(), 1),
                 zoom3 = core::zoomSpacing(cfg, rig.session().sculpture().levels(), 3);
    // A size-3 groove (offered from zoom 3 on): at zoom 1's spacing it would be lost.
    studio.setZoom(3, Vec3(0, 0, 25));
    studio.setSize(3);
    studio.setTool(studio::ToolKind::Carve);
    studio.stroke({Vec3(-6, 0, 25), Vec3(6, 0, 25)}, false);
    const std::filesystem::path path = dir / "detail.stl";
    const std::string said = rig.exportTo(path);
    EXPECT_NE(said.find("(the size-3 detail's spacing)"), std::string::npos) << said;
    ASSERT_TRUE(rig.pollExport(true));
    const size_t atZoom3 = rig.session().wholeMesh(zoom3).triangleCount(),
                 atZoom1 = rig.session().wholeMesh(zoom1).triangleCount();
    EXPECT_EQ(load(path).faces, atZoom3);
    EXPECT_GT(atZoom3, 4 * atZoom1);  // a finer grid indeed: 4x the triangles per halving
}

// The save key (F5) goes the same way: the rig says it started, the frame goes on, and the
// outcome comes from the rig's poll; a window's close waits for it.
TEST_F(ExportInBackground, TheSaveKeySavesBesideTheFrame) {
    const std::filesystem::path project = dir / "project";
    uint64_t sequenceAtF5 = 0;
    {
        app::RigOptions options;
        options.project = app::ProjectChoice::Given;
        options.projectDir = project;
        app::Rig rig(smallSphere(), options);
        studio::Studio& studio = rig.studio();
        studio.stroke({Vec3(-6, 0, 25), Vec3(6, 0, 25)}, false);
        sequenceAtF5 = 1;
        EXPECT_EQ(rig.save(), "saving " + project.string() + "...");
        studio.stroke({Vec3(0, -6, 25), Vec3(0, 6, 25)}, false);  // the frame goes on
        const std::optional<std::string> outcome = rig.pollBackgroundWork(true);
        ASSERT_TRUE(outcome);
        EXPECT_EQ(*outcome, "saved " + project.string());
        EXPECT_EQ(core::readSnapshot(core::snapshotPath(project)).lastSequence, sequenceAtF5);
        rig.save();
        rig.close();  // waits for the second save, then has nothing left to snapshot
        EXPECT_FALSE(rig.pollBackgroundWork(true));
        EXPECT_FALSE(rig.session().hasJournaledEdits());
    }
    EXPECT_EQ(core::readSnapshot(core::snapshotPath(project)).lastSequence, 2u);
    EXPECT_TRUE(core::readJournal(core::journalPath(project)).records.empty());
}

// An import asked for in the window (it runs beside the frame, ImportInBackground.h) lands in
// the project before "save as" copies it and before "new project" replaces the studio, whether
// it is still running or done and not yet polled: never dropped with the studio.
TEST_F(ExportInBackground, AnImportUnderWayLandsBeforeTheProjectIsSavedAsOrLeft) {
    const std::filesystem::path part = dir / "part.stl";
    {
        studio::Session s(test::smallConfig(0));
        s.setSize(5);
        s.stroke({Vec3(40, 0, 0), Vec3(60, 0, 0)}, false);
        core::exportMesh(s.wholeMesh(1.5), part);
    }
    const std::filesystem::path project = dir / "project", copy = dir / "copy";
    app::RigOptions options;
    options.project = app::ProjectChoice::Given;
    options.projectDir = project;
    app::Rig rig(smallSphere(), options);
    rig.studio().importMeshInBackground(part);
    rig.saveAs(copy);  // continues in the copy
    EXPECT_EQ(rig.studio().stepCount(), 1u);
    EXPECT_EQ(core::readSnapshot(core::snapshotPath(copy)).lastSequence, 1u);
    rig.studio().importMeshInBackground(part);
    rig.newProject();
    // The copy's journal or snapshot holds the second import too.
    auto reopened = studio::Studio::openProject(copy, smallSphere(), studio::ProjectMode::ReadOnly);
    EXPECT_EQ(reopened->stepCount(), 2u);
}

// "Saved as ... (continuing there)": with the tool, mirror, size and zoom as they were (found
// by QA: the defaults came back, and the next stroke was not mirrored).
TEST_F(ExportInBackground, SaveAsContinuesWithTheToolAsItWas) {
    app::RigOptions options;
    options.project = app::ProjectChoice::Given;
    options.projectDir = dir / "project";
    app::Rig rig(smallSphere(), options);
    rig.studio().setZoom(2, Vec3(0, 0, 20));
    rig.studio().setSize(4);
    rig.studio().setTool(studio::ToolKind::Smooth);
    rig.studio().setMirror(core::MirrorAxis::X);
    const core::GridRegion region = rig.session().region();
    rig.saveAs(dir / "copy");
    const studio::Session& s = rig.session();
    EXPECT_EQ(*s.projectDir(), dir / "copy");
    EXPECT_EQ(s.tool(), studio::ToolKind::Smooth);
    EXPECT_EQ(s.mirror(), core::MirrorAxis::X);
    EXPECT_EQ(s.size(), 4);
    EXPECT_EQ(s.zoom(), 2);
    EXPECT_EQ(s.region().originCell, region.originCell);
}

// Found by QA: save as saved the old project first and copied it, so on a full disk it failed
// as well, and it was the way out of the full disk. It now writes the new project from memory
// and leaves the old project's files as they were (its journal holds every edit); a scratch
// session (started without a project) can save as too.
TEST_F(ExportInBackground, SaveAsWritesFromMemoryAndLeavesTheOldProjectAlone) {
    auto contents = [](const std::filesystem::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    app::RigOptions options;
    options.project = app::ProjectChoice::Given;
    options.projectDir = dir / "project";
    uint64_t hash = 0;
    {
        app::Rig rig(smallSphere(), options);
        rig.studio().setSize(5);
        rig.studio().stroke({Vec3(-30, 0, 10), Vec3(0, 0, 28), Vec3(30, 0, 10)}, false);
        hash = core::canonicalMeshHash(rig.session().wholeMesh());
        const std::string snapshot = contents(core::snapshotPath(options.projectDir));
        const std::string journal = contents(core::journalPath(options.projectDir));
        ASSERT_FALSE(journal.empty());
        rig.saveAs(dir / "copy");
        EXPECT_EQ(*rig.session().projectDir(), dir / "copy");
        EXPECT_EQ(contents(core::snapshotPath(options.projectDir)), snapshot);
        EXPECT_EQ(contents(core::journalPath(options.projectDir)), journal);
        EXPECT_EQ(core::canonicalMeshHash(rig.session().wholeMesh()), hash);
    }
    for (const char* name : {"project", "copy"}) {
        app::RigOptions again = options;
        again.projectDir = dir / name;
        app::Rig rig(smallSphere(), again);
        EXPECT_EQ(core::canonicalMeshHash(rig.session().wholeMesh()), hash) << name;
        EXPECT_EQ(rig.session().history().done().size(), 1u) << name;
    }
    {
        app::Rig scratch(smallSphere(), app::RigOptions{});
        scratch.studio().setSize(5);
        scratch.studio().stroke({Vec3(-30, 0, 10), Vec3(0, 0, 28), Vec3(30, 0, 10)}, false);
        scratch.saveAs(dir / "from-scratch");
        EXPECT_EQ(*scratch.session().projectDir(), dir / "from-scratch");
    }
    app::RigOptions fromScratch = options;
    fromScratch.projectDir = dir / "from-scratch";
    app::Rig reopened(smallSphere(), fromScratch);
    EXPECT_EQ(core::canonicalMeshHash(reopened.session().wholeMesh()), hash);
    EXPECT_EQ(reopened.session().history().done().size(), 1u);
}

// Found by QA: the windows' export of a .dxf held the sculpture only, where `vsculpt play
// --out x.dxf` also writes the sketch's curves (layer "sketch"): both write the same file now.
TEST_F(ExportInBackground, ADxfFromAWindowHoldsTheSketchCurvesAsPlayWritesThem) {
    app::Rig rig(smallSphere(), app::RigOptions{});
    const studio::Script script = studio::loadScript(VSCULPT_EXAMPLES_DIR "/sketch-figure.vsc");
    // The pen strokes, not the solids: the file's curves are what matters, and the sphere
    // alone exports in a moment.
    for (const studio::ScriptCommand& c : script.commands)
        if (!(c.kind == studio::ScriptCommand::Kind::Sketch &&
              c.sketch.verb == studio::SketchCommand::Verb::Solid))
            rig.studio().apply(c);
    const size_t curves = rig.studio().curvesInObjectSpace().size();
    ASSERT_GT(curves, 0u);
    const std::filesystem::path path = dir / "figure.dxf";
    rig.exportTo(path);
    ASSERT_TRUE(rig.pollExport(true));
    std::ifstream in(path);
    std::string line, previous;
    size_t polylines = 0, sketchLayer = 0, faces = 0, closed = 0;
    bool inPolylineHeader = false;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line == "POLYLINE") ++polylines;
        if (line == "POLYLINE" || line == "VERTEX") inPolylineHeader = line == "POLYLINE";
        // Flag 70 of the polyline: 8 = 3D, 9 = 3D and closed.
        if (inPolylineHeader && previous == "70" && line == "9") ++closed;
        if (line == "3DFACE") ++faces;
        if (previous == "8" && line == "sketch") ++sketchLayer;
        previous = line;
    }
    EXPECT_EQ(polylines, curves);
    EXPECT_GT(sketchLayer, 0u);
    // The body outline, a clean-up loop, is closed (found by QA: every curve came out open).
    EXPECT_GE(closed, 1u);
    EXPECT_GT(faces, 1000u);
}
