// SPDX-License-Identifier: MIT
// Scripted sketch sessions (issue #8): pen samples in playback scripts become strokes, clean
// curves and solids in the sculpture; one undo timeline across sketch and sculpt steps.
#include "vsculpt/studio/Studio.h"

#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/WriteFileAtomically.h"

#include "../TestFiles.h"
#include "../TestFixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <sstream>

using namespace vsculpt;
using namespace vsculpt::studio;
using core::Vec3;

namespace {

core::SculptConfig smallConfig() {
    return test::smallConfig(20);
}
using test::readFile;
using test::TempDir;
using test::writeFile;

// A pen stroke along a circle (view mm), `turns` times round, with a slight wobble so
// overdrawn strokes differ like a hand's.
std::string circlePen(double cx, double cy, double r, double turns, double wobble, int n = 72) {
    std::ostringstream s;
    s << "pen";
    for (int i = 0; i <= n; ++i) {
        const double t = 2 * M_PI * turns * i / n;
        const double rr = r + wobble * std::sin(5 * t);
        s << " " << cx + rr * std::cos(t) << "," << cy + rr * std::sin(t) << ",0.6";
    }
    return s.str() + "\n";
}

std::string linePen(double x0, double y0, double x1, double y1, int n = 20) {
    std::ostringstream s;
    s << "pen";
    for (int i = 0; i <= n; ++i)
        s << " " << x0 + (x1 - x0) * i / n << "," << y0 + (y1 - y0) * i / n;
    return s.str() + "\n";
}

void run(Studio& studio, const std::string& text, const char* name = "test.vsc") {
    for (const ScriptCommand& c : parseScript(text, name).commands)
        studio.apply(c);
}

struct State {
    uint64_t mesh = 0, sketch = 0;
    size_t page = 0;
    bool operator==(const State&) const = default;
};
State state(Studio& s) {
    State st;
    st.mesh = core::canonicalMeshHash(s.session().view().mesh());
    st.page = s.document().currentIndex();
    // Every page's content, so an undo on the wrong page is caught (adding a page is not a
    // step, so empty pages do not count).
    for (size_t i = 0; i < s.document().pageCount(); ++i) {
        const studio::PageContent c = s.document().page(i).content();
        if (!(c == studio::PageContent{}))
            st.sketch = (st.sketch * 1099511628211ull) ^ (studio::contentHash(c) + i);
    }
    return st;
}

// An outline away from the initial sphere (radius 20), drawn in clean-up mode on the front
// view (canvas (x, y) -> object (x, z)): a loose loop that overshoots its start a little,
// gone round again.
const std::string kOutline = "page Body Figures\nmode cleanup\nkind curve\n" +
                             circlePen(60, 0, 18, 1.04, 0.3) + circlePen(60, 0, 18, 1.02, -0.3) +
                             "endgroup\nrole outline last\n";

TEST(Studio, ScriptedOutlineInflatesIntoTheSculpture) {
    Studio studio(smallConfig());
    const Session& session = studio.session();
    run(studio, kOutline + "solid inflate\n");
    const studio::SketchPage& page = studio.page();
    ASSERT_EQ(page.cleanCurves().size(), 1u);  // two loops overdrawn: one clean curve
    EXPECT_TRUE(page.cleanCurves()[0].closed);
    ASSERT_TRUE(studio.lastSolid());
    ASSERT_EQ(session.history().done().size(), 1u);
    EXPECT_TRUE(session.history().done()[0].solid);
    EXPECT_EQ(session.verifyMesh(), "");
    const core::Mesh whole = session.wholeMesh();
    const core::MeshTopology topo = core::analyzeTopology(whole);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.components, 2u);  // the sphere and the separate blob
    // Silhouette against the outline: the blob's x and z extent is the circle's (within a
    // lattice spacing), and it is symmetric about the canvas plane y = 0.
    const int level = session.history().done()[0].level;
    const double h = session.sculpture().levels().level(level).spacingMm;
    core::Aabb blob;
    for (const Vec3& p : whole.positions)
        if (p.x > 30) blob.expand(p);
    EXPECT_NEAR(blob.min.x, 42, h);
    EXPECT_NEAR(blob.max.x, 78, h);
    EXPECT_NEAR(blob.min.z, -18, h);
    EXPECT_NEAR(blob.max.z, 18, h);
    EXPECT_NEAR(blob.min.y, -blob.max.y, 0.5 * h);
    EXPECT_GT(blob.max.y, 5);
    // The field is mirror-symmetric about y = 0 up to the signed distance's float rounding.
    core::FieldProbe probe(session.sculpture());
    for (double x = 45; x <= 75; x += 5)
        for (double y = 1; y <= 15; y += 3.5)
            for (double z = -15; z <= 15; z += 5)
                EXPECT_NEAR(probe.value(Vec3(x, y, z)), probe.value(Vec3(x, -y, z)), 1e-4);
}

TEST(Studio, UndoAndRedoCrossSketchAndSculptStepsExactly) {
    Studio studio(smallConfig());
    const Session& session = studio.session();
    std::vector<State> states{state(studio)};
    const std::vector<std::string> steps = {
        "page Body Figures\n" + circlePen(60, 0, 18, 1.0, 0.3),  // sketch: draft stroke
        "tool add\nsize 5\nstroke 0 0 22 5 0 24\n",              // sculpt
        "role outline stroke 0\n",                               // sketch: role
        "solid inflate\n",                                       // sculpt: the solid
        linePen(40, -30, 80, -30),                               // sketch: draft line
        "select 1\nmove 0 -5\n",                                 // sketch: move
        "tool carve\nsize 5\nstroke 60 -20 0 60 20 0\n",         // sculpt: carve the blob
        "page Second\n" + linePen(0, 0, 10, 10),                 // sketch on another page
    };
    for (const std::string& step : steps) {
        run(studio, step);
        states.push_back(state(studio));
        ASSERT_NE(states.back(), states[states.size() - 2]) << step;
    }
    EXPECT_EQ(studio.stepCount(), steps.size());
    for (size_t i = states.size() - 1; i > 0; --i) {
        const size_t before = studio.stepCount();
        studio.undo();
        ASSERT_EQ(studio.stepCount(), before - 1);
        State now = state(studio);
        now.page = states[i - 1].page;  // undo shows the page it acted on, not the old one
        EXPECT_EQ(now.mesh, states[i - 1].mesh) << "after undoing step " << i;
        EXPECT_EQ(now.sketch, states[i - 1].sketch) << "after undoing step " << i;
        EXPECT_EQ(session.verifyMesh(), "");
    }
    EXPECT_FALSE(studio.undo());
    for (size_t i = 1; i < states.size(); ++i) {
        studio.redo();
        const State now = state(studio);
        EXPECT_EQ(now.mesh, states[i].mesh) << "after redoing step " << i;
        EXPECT_EQ(now.sketch, states[i].sketch) << "after redoing step " << i;
    }
    EXPECT_FALSE(studio.redo());
    // A new step clears what could be redone.
    studio.undo();
    run(studio, linePen(5, 5, 9, 9));
    EXPECT_FALSE(studio.redo());
}

TEST(Studio, RegeneratingAfterEditingTheOutlineReplacesTheSolid) {
    Studio studio(smallConfig());
    const Session& session = studio.session();
    // A draft outline (a raw stroke that closes on itself), inflated; then the stroke is
    // scaled down and the solid rebuilt.
    run(studio, circlePen(60, 0, 18, 1.0, 0.3) + "role outline stroke 0\nsolid inflate\n");
    const uint64_t first = core::canonicalMeshHash(session.view().mesh());
    const double volumeFirst = core::meshVolume(session.wholeMesh());
    run(studio, "select 0\nscale 0.7\nsolid inflate\n");
    const double volumeSecond = core::meshVolume(session.wholeMesh());
    EXPECT_LT(volumeSecond, volumeFirst);  // replaced by the smaller one, not added to it
    EXPECT_TRUE(core::analyzeTopology(session.wholeMesh()).watertight());
    EXPECT_EQ(session.verifyMesh(), "");
    EXPECT_EQ(session.history().done().size(), 2u);
    // Undo the rebuild: the first solid is back exactly; then the scaling, then the solid.
    studio.undo();
    EXPECT_EQ(core::canonicalMeshHash(session.view().mesh()), first);
    EXPECT_EQ(core::meshVolume(session.wholeMesh()), volumeFirst);
    studio.undo();
    EXPECT_EQ(studio.page().selection().size(), 1u);
    studio.undo();
    EXPECT_EQ(session.history().done().size(), 0u);
}

// Found by QA: a body inflated, then a head's outline inflated (the body's given role none)
// replaced the body, which vanished without a word. A solid is regenerated only from the
// lines it was built from; from other lines it is another solid.
TEST(Studio, AnotherOutlineInflatedIsAnotherSolidAndTheFirstStays) {
    Studio studio(smallConfig());
    const Session& session = studio.session();
    run(studio, circlePen(100, 0, 20, 1.0, 0.3) + "role outline last\nsolid inflate\n");
    const double bodyVolume = core::meshVolume(session.wholeMesh());
    run(studio, "role none stroke 0\n" + circlePen(100, 60, 10, 1.0, 0.3) +
                    "role outline last\nsolid inflate\n");
    EXPECT_EQ(session.history().done().size(), 2u);
    // The body is still there: the sculpture grew by the head.
    const double both = core::meshVolume(session.wholeMesh());
    EXPECT_GT(both, bodyVolume * 1.05);
    core::FieldProbe probe(session.sculpture());  // > 0 inside the clay
    EXPECT_GT(probe.value(Vec3(100, 0, 0)), 0) << "the body's centre is no longer clay";
    EXPECT_GT(probe.value(Vec3(100, 0, 60)), 0) << "the head's centre is not clay";
    // Deleting the body's outline rather than giving it role none: the same.
    Studio deleted(smallConfig());
    run(deleted, circlePen(100, 0, 20, 1.0, 0.3) + "role outline last\nsolid inflate\n");
    run(deleted, "select 0\ndelete\n" + circlePen(100, 60, 10, 1.0, 0.3) +
                     "role outline last\nsolid inflate\n");
    EXPECT_EQ(core::canonicalMeshHash(deleted.session().view().mesh()),
              core::canonicalMeshHash(session.view().mesh()));
}

// Two outlines on one page: which one was meant is the designer's to say, not the older one's
// by default (QA: the newer was silently ignored). Lines on the wrong view are refused too
// (QA: a sweep path drawn on a front page ran along y, not up).
TEST(Studio, AmbiguousRolesAndLinesOnTheWrongViewAreRefusedByName) {
    Studio studio(smallConfig());
    run(studio, "page body\n" + circlePen(100, 0, 20, 1.0, 0.3) + "role outline last\n" +
                    circlePen(-100, 0, 20, 1.0, 0.3) + "role outline last\n");
    try {
        run(studio, "solid inflate\n");
        ADD_FAILURE() << "two outlines were taken";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(),
                     "inflate: page 'body' has 2 outline lines (stroke 0, stroke 1); give the "
                     "ones not meant role none");
    }
    EXPECT_EQ(studio.session().history().done().size(), 0u);
    run(studio, "role none stroke 1\nsolid inflate\n");
    EXPECT_EQ(studio.session().history().done().size(), 1u);

    // The sketch library's function names stay out of what the designer reads, and a figure
    // eight is said to cross itself, not to enclose no area.
    Studio eight(smallConfig());
    run(eight, std::string("mode draft\n") +
                   "pen 100,0 110,10 120,0 110,-10 100,0 90,10 80,0 90,-10 100,0\n"
                   "role outline last\n");
    try {
        run(eight, "solid inflate\n");
        ADD_FAILURE() << "a figure eight was inflated";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("inflate: outline self-intersects: segment ", 0), 0u)
            << e.what();
    }

    Studio sweep(smallConfig());
    run(sweep, "page side-view\n" + circlePen(0, 40, 6, 1.0, 0.0) +
                   "role sweep-section last\npage body\n" + linePen(-30, 0, 30, 0) +
                   "role sweep-path last\n");
    try {
        run(sweep, "solid sweep\n");
        ADD_FAILURE() << "a path on a front view was taken as a top view's";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("the sweep-path line must be drawn on a top view; "
                                             "page 'body' is a front view"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(sweep.session().history().done().size(), 0u);
}

TEST(Studio, SweepFromASideSectionAndATopPath) {
    Studio studio(smallConfig());
    const Session& session = studio.session();
    // Section on the side view (canvas x -> object y, y -> z) around z = 40; path on the top
    // view along x, away from the sphere.
    run(studio, "page side-view\n" + circlePen(0, 40, 6, 1.0, 0.0) +
                    "role sweep-section last\npage top-view\n" + linePen(-30, 0, 30, 0) +
                    "role sweep-path last\nsolid sweep\n");
    ASSERT_EQ(session.history().done().size(), 1u);
    EXPECT_EQ(studio.plane(1), SketchPlane::Side);
    EXPECT_EQ(studio.plane(2), SketchPlane::Top);
    const core::Mesh whole = session.wholeMesh();
    EXPECT_TRUE(core::analyzeTopology(whole).watertight());
    core::Aabb bar;
    for (const Vec3& p : whole.positions)
        if (p.z > 30) bar.expand(p);
    const double h =
        session.sculpture().levels().level(session.history().done()[0].level).spacingMm;
    EXPECT_NEAR(bar.min.x, -30, 1.5 * h);
    EXPECT_NEAR(bar.max.x, 30, 1.5 * h);
    EXPECT_NEAR(bar.max.z - bar.min.z, 12, 1.5 * h);
    EXPECT_NEAR(bar.max.y - bar.min.y, 12, 1.5 * h);
}

TEST(Studio, ProjectKeepsTheSketchAndTheTimeline) {
    TempDir dir;
    State expected;
    {
        auto studioPtr = Studio::openProject(dir.path, smallConfig());
        Studio& studio = *studioPtr;
        run(studio, kOutline + "solid inflate\n" + linePen(0, 30, 20, 30));
        expected = state(studio);
    }  // no save: the journal and sketch.json carry everything
    auto studioPtr = Studio::openProject(dir.path, smallConfig());
    Studio& studio = *studioPtr;
    const Session* session = &studio.session();
    EXPECT_EQ(state(studio), expected);
    // Undo continues across the reopening in the original order: the line, then the solid.
    studio.undo();
    EXPECT_EQ(core::canonicalMeshHash(session->view().mesh()), expected.mesh);
    studio.undo();
    EXPECT_NE(core::canonicalMeshHash(session->view().mesh()), expected.mesh);
    EXPECT_EQ(session->history().done().size(), 0u);
}

namespace {

/// A project with a solid made from a sketch (sculpt and sketch steps on its timeline); its
/// mesh hash.
uint64_t projectWithASketchedSolid(const std::filesystem::path& dir) {
    auto studioPtr = Studio::openProject(dir, smallConfig());
    run(*studioPtr, kOutline + "solid inflate\n");
    return core::canonicalMeshHash(studioPtr->session().view().mesh());
}

/// Opens the project in `dir`, whose sketch.json cannot be read, and returns the recovery
/// warning. What a damaged sketch.json must cost is the sketch pages, never the sculpture:
/// the sculpture opens with its mesh (`mesh`) and every sculpt step to undo, the journal is
/// untouched, and the damaged bytes are kept as sketch.json.damaged (removed again here, so
/// that the next case is kept under the same name).
std::string openedPastADamagedSketchFile(const std::filesystem::path& dir, uint64_t mesh) {
    const auto file = dir / "sketch.json", kept = dir / "sketch.json.damaged";
    const std::string damaged = readFile(file), journal = readFile(dir / "journal.vjl");
    std::string warning;
    {
        auto studioPtr = Studio::openProject(dir, smallConfig());
        const Studio& studio = *studioPtr;
        const Session& session = studio.session();
        warning = session.recoveryWarning();
        EXPECT_EQ(core::canonicalMeshHash(session.view().mesh()), mesh);
        EXPECT_EQ(studio.timeline().size(), session.history().done().size());
        for (const Studio::Step& step : studio.timeline())
            EXPECT_TRUE(step.sculpt());
        EXPECT_EQ(studio.document().toJson(), SketchDocument(studio.document().params()).toJson());
        EXPECT_TRUE(studio.surfaceLines().empty());
        EXPECT_FALSE(std::filesystem::exists(file));
        EXPECT_EQ(readFile(kept), damaged);
        EXPECT_NE(warning.find("the file is kept as " + kept.string()), std::string::npos)
            << warning;
    }
    EXPECT_EQ(readFile(dir / "journal.vjl"), journal);
    std::filesystem::remove(kept);
    return warning;
}

/// Writes `damaged` as the project's sketch.json and opens past it: the warning must begin
/// with the file and `expected`.
void expectSetAsideFor(const std::filesystem::path& dir, uint64_t mesh, const std::string& damaged,
                       const std::string& expected) {
    const auto file = dir / "sketch.json";
    writeFile(file, damaged);
    const std::string what = openedPastADamagedSketchFile(dir, mesh);
    EXPECT_EQ(what.rfind(file.string() + ": " + expected + "; ", 0), 0u) << what;
}

}  // namespace

// Found by fuzzing: a sketch.json holding 200 000 nested arrays in its document overflowed the
// stack (the loader writes the document back out, recursively). The file is now named with its
// line and column, and set aside: the sculpture opens.
TEST(Studio, ASketchFileNestedTooDeepIsSetAsideWithItsLine) {
    TempDir dir;
    const uint64_t mesh = projectWithASketchedSolid(dir.path);
    const auto file = dir.path / "sketch.json";
    std::string text = readFile(file);
    const size_t at = text.find("\"document\"");
    ASSERT_NE(at, std::string::npos);
    text.insert(at, "\"junk\": " + std::string(200000, '[') + std::string(200000, ']') + ",\n");
    writeFile(file, text);
    const std::string what = openedPastADamagedSketchFile(dir.path, mesh);
    EXPECT_NE(what.find(file.string() + ":"), std::string::npos) << what;
    EXPECT_NE(what.find(": nested more than 64 levels deep"), std::string::npos) << what;
}

// Found by fuzzing: a timeline undo cannot walk. Surface-line counts of 2^63 twice summed to 0
// and passed the check, then undo popped an empty list (SIGSEGV); a sketch step on a page whose
// log has nothing to undo reached Studio::undo's invariant (an abort under the headset's input).
// Opening now names the file and the key, and sets the file aside.
TEST(Studio, ATimelineUndoCannotWalkIsSetAsideOnOpening) {
    TempDir dir;
    const uint64_t mesh = projectWithASketchedSolid(dir.path);
    const auto file = dir.path / "sketch.json";
    const std::string good = readFile(file);
    const std::string key = "\"timeline\": [";
    const size_t timeline = good.find(key);
    ASSERT_NE(timeline, std::string::npos) << good;
    const size_t open = timeline + key.size();
    const std::string huge = R"({"sketch":false,"surface_lines":9223372036854775808},)";
    const struct {
        std::string steps, expected;
    } cases[] = {
        {huge + huge, "surface_lines: fewer lines than the timeline's steps hold"},
        {R"({"sketch":true,"page":0},)",
         "timeline: 1 sketch step(s) on page 0, whose log holds 0 action(s) to undo"},
    };
    for (const auto& c : cases)
        expectSetAsideFor(dir.path, mesh, std::string(good).insert(open, c.steps), c.expected);
}

// Found by fuzzing: values of the wrong type in sketch.json gave nlohmann's bare words
// ("type must be string, but is number", "cannot use operator[] with a numeric argument").
TEST(Studio, ASketchFileValueOfTheWrongTypeIsNamedByItsKey) {
    TempDir dir;
    const uint64_t mesh = projectWithASketchedSolid(dir.path);
    const auto file = dir.path / "sketch.json";
    const nlohmann::json good = nlohmann::json::parse(readFile(file));
    ASSERT_FALSE(good["timeline"].empty());
    const struct {
        std::function<void(nlohmann::json&)> damage;
        std::string expected;
    } cases[] = {
        {[](nlohmann::json& j) { j["version"] = "1"; }, "version: expected 1"},
        {[](nlohmann::json& j) { j["format"] = 7; }, "format: expected \"vsculpt-studio\""},
        {[](nlohmann::json& j) { j["timeline"] = 5; }, "timeline: expected a list"},
        {[](nlohmann::json& j) { j["planes"] = nlohmann::json::object(); },
         "planes: expected a list"},
        {[](nlohmann::json& j) { j["timeline"][0]["page"] = "x"; },
         "timeline[0].page: expected a count"},
        {[](nlohmann::json& j) { j["timeline"][0]["surface_lines"] = -1; },
         "timeline[0].surface_lines: expected a count"},
        {[](nlohmann::json& j) { j["surface_lines"] = {5}; },
         "surface_lines[0]: expected a list of points"},
    };
    for (const auto& c : cases) {
        nlohmann::json j = good;
        c.damage(j);
        expectSetAsideFor(dir.path, mesh, j.dump(1), c.expected);
    }
}

// A damaged sketch.json used to refuse the whole project: the sculpture, its snapshot and its
// journal intact, yet nothing opened until the file was moved away by hand. Now the sketch
// pages start empty and the file is kept; later sketching writes a new sketch.json, a second
// damaged one is kept beside the first, and a read-only reader (render) changes nothing.
TEST(Studio, ADamagedSketchFileCostsTheSketchPagesNeverTheSculpture) {
    TempDir dir;
    const uint64_t mesh = projectWithASketchedSolid(dir.path);
    const auto file = dir.path / "sketch.json";
    const std::string damaged = "{\"format\": \"vsculpt-studio\", \"version\": 1, \"docu";
    writeFile(file, damaged);
    {
        auto reader = Studio::openProject(dir.path, smallConfig(), ProjectMode::ReadOnly);
        EXPECT_EQ(core::canonicalMeshHash(reader->session().view().mesh()), mesh);
        const std::string& what = reader->session().recoveryWarning();
        EXPECT_NE(what.find(file.string() + ":1:49: invalid JSON: syntax error"), std::string::npos)
            << what;
        EXPECT_EQ(what.find("json.exception"), std::string::npos) << what;
        EXPECT_NE(what.find("read-only, so the file is left as it is"), std::string::npos) << what;
    }
    EXPECT_EQ(readFile(file), damaged);
    State sketched;
    {
        auto studioPtr = Studio::openProject(dir.path, smallConfig());
        Studio& studio = *studioPtr;
        EXPECT_EQ(core::canonicalMeshHash(studio.session().view().mesh()), mesh);
        EXPECT_EQ(readFile(dir.path / "sketch.json.damaged"), damaged);
        // Undo walks back through the sculpt steps the journal has, then redoes them.
        ASSERT_EQ(studio.timeline().size(), 1u);
        studio.undo();
        EXPECT_NE(core::canonicalMeshHash(studio.session().view().mesh()), mesh);
        studio.redo();
        EXPECT_EQ(core::canonicalMeshHash(studio.session().view().mesh()), mesh);
        run(studio, linePen(0, 30, 20, 30));
        sketched = state(studio);
    }
    {
        auto studioPtr = Studio::openProject(dir.path, smallConfig());
        EXPECT_EQ(state(*studioPtr), sketched);
        EXPECT_EQ(studioPtr->session().recoveryWarning(), "");
    }
    writeFile(file, "not json either");
    {
        auto studioPtr = Studio::openProject(dir.path, smallConfig());
        EXPECT_EQ(readFile(dir.path / "sketch.json.damaged"), damaged);
        EXPECT_EQ(readFile(dir.path / "sketch.json.damaged-2"), "not json either");
    }
}

// sketch.json is written on the studio's writer thread, so a write that fails is not the
// step's error: waitForSketchFile() throws it, a background save's outcome includes it (and
// counts as failed), and save() throws it. (The notice sink tells it at the next step when
// nothing asked before.)
TEST(Studio, ASketchFileThatCannotBeWrittenIsReportedByTheSave) {
    TempDir dir;
    auto studioPtr = Studio::openProject(dir.path, smallConfig());
    Studio& studio = *studioPtr;
    const auto file = dir.path / "sketch.json";
    std::filesystem::remove(file);
    std::filesystem::create_directory(file);  // nothing can replace a folder
    run(studio, linePen(0, 30, 20, 30));
    try {
        studio.waitForSketchFile();
        ADD_FAILURE() << "the failed write was not reported";
    } catch (const core::FileWriteError& e) {
        EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(studio.waitForSketchFile());  // told once
    run(studio, linePen(0, 40, 20, 40));
    ASSERT_TRUE(studio.saveInBackground());
    bool failed = false;
    const std::optional<std::string> outcome = studio.pollSave(true, &failed);
    ASSERT_TRUE(outcome.has_value());
    EXPECT_TRUE(failed);
    EXPECT_NE(outcome->find("; the sketch was not saved: " + file.string()), std::string::npos)
        << *outcome;
    EXPECT_THROW(studio.save(), core::FileWriteError);
    std::filesystem::remove(file);
    studio.save();  // the folder gone, the file is written again
    EXPECT_TRUE(std::filesystem::is_regular_file(file));
}

TEST(Studio, BadSketchCommandsNameTheLine) {
    auto message = [](const std::string& text) {
        try {
            parseScript(text, "s.vsc");
        } catch (const ScriptError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_EQ(message("pen 1,2\npen 1,2,3,4,5\n"),
              "s.vsc:2: expected a pen sample as X,Y[,PRESSURE[,TIME]], got '1,2,3,4,5'");
    EXPECT_NE(message("pen 1,2,1.5\n").find("s.vsc:1: pen pressure '1,2,1.5' outside 0..1"),
              std::string::npos);
    EXPECT_NE(message("pen 1,2,0.5 3,4\n").find("for every sample"), std::string::npos);
    EXPECT_NE(message("pen 1,2,0.5,2 3,4,0.5,1\n").find("time goes backwards"), std::string::npos);
    EXPECT_NE(message("role wing last\n").find("s.vsc:1: unknown role 'wing'"), std::string::npos);
    EXPECT_NE(message("solid blob\n").find("unknown solid construction 'blob'"), std::string::npos);
    EXPECT_NE(message("canvas zoom 0 1 1\n").find("must be positive"), std::string::npos);
    EXPECT_NE(message("select lasso 1,1 2,2\n").find("at least three points"), std::string::npos);
    // Errors that depend on the state are reported when the command runs.
    Studio studio(smallConfig());
    const Session& session = studio.session();
    const Script s = parseScript("role outline stroke 7\nsolid inflate\n", "s.vsc");
    EXPECT_THROW(studio.apply(s.commands[0]), std::invalid_argument);
    try {
        studio.apply(s.commands[1]);
        ADD_FAILURE() << "built a solid without an outline";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("outline"), std::string::npos) << e.what();
    }
    EXPECT_EQ(studio.stepCount(), 0u);
    EXPECT_EQ(session.history().done().size(), 0u);
    // A session alone refuses sketch commands rather than skipping them.
    Session alone(smallConfig());
    EXPECT_THROW(alone.apply(s.commands[1]), SessionError);
}

}  // namespace

namespace {

TEST(Studio, ModelLinesNeedAProjectorAndAreRefusedWithoutOne) {
    Studio studio(smallConfig());
    const Script s = parseScript("model-line 400 300 20,150 380,150\n", "s.vsc");
    EXPECT_THROW(studio.apply(s.commands[0]), std::invalid_argument);
    EXPECT_EQ(studio.stepCount(), 0u);
    // With one, its pieces become surface lines in one step; too-short pieces are dropped.
    studio.setSurfaceProjector([](const Session&, const std::vector<glm::dvec2>& px, glm::ivec2) {
        std::vector<std::vector<Vec3>> lines(2);
        for (const glm::dvec2& p : px)
            lines[0].push_back(Vec3(p.x, 0, p.y));
        lines[1].push_back(Vec3(0.0));  // one point: not a line
        return lines;
    });
    studio.apply(s.commands[0]);
    ASSERT_EQ(studio.surfaceLines().size(), 1u);
    EXPECT_EQ(studio.surfaceLines()[0].size(), 2u);
    EXPECT_EQ(studio.stepCount(), 1u);
    EXPECT_TRUE(studio.undo() == false);  // not a sculpt step
    EXPECT_TRUE(studio.surfaceLines().empty());
}

}  // namespace

namespace {

// A journal ending "stroke, undo" (no save) keeps its redo after reopening, with and without
// sketch steps on the same timeline.
TEST(Studio, RedoSurvivesRecovery) {
    for (const bool withSketch : {false, true}) {
        TempDir dir;
        uint64_t afterStroke = 0, afterUndo = 0;
        {
            auto studio = Studio::openProject(dir.path, smallConfig());
            if (withSketch) run(*studio, "page Body Figures\n" + linePen(40, -30, 80, -30));
            run(*studio, "tool add\nsize 5\nstroke 0 0 22 5 0 24\n");
            afterStroke = core::canonicalMeshHash(studio->session().view().mesh());
            ASSERT_TRUE(studio->undo());
            afterUndo = core::canonicalMeshHash(studio->session().view().mesh());
            ASSERT_NE(afterUndo, afterStroke);
        }  // closed without saving: the journal carries the stroke and its undo
        auto studio = Studio::openProject(dir.path, smallConfig());
        EXPECT_EQ(core::canonicalMeshHash(studio->session().view().mesh()), afterUndo);
        EXPECT_EQ(studio->redoCount(), 1u) << "with sketch: " << withSketch;
        EXPECT_TRUE(studio->redo()) << "with sketch: " << withSketch;
        EXPECT_EQ(core::canonicalMeshHash(studio->session().view().mesh()), afterStroke);
        EXPECT_EQ(studio->stepCount(), withSketch ? 2u : 1u);
        // And undo takes it back again through the same single timeline.
        EXPECT_TRUE(studio->undo());
        EXPECT_EQ(core::canonicalMeshHash(studio->session().view().mesh()), afterUndo);
    }
}

// A stroke the journal cannot take is rolled back: the sculpture never shows an edit a
// reopened project would not have.
TEST(Studio, ReadOnlyProjectsRefuseEditsAndKeepTheSculptureAsItWas) {
    TempDir dir;
    {
        auto s = Studio::openProject(dir.path, smallConfig());
        s->stroke({Vec3(0, 0, 22), Vec3(4, 0, 22)}, false);
    }
    auto ro = Studio::openProject(dir.path, smallConfig(), ProjectMode::ReadOnly);
    const uint64_t before = core::canonicalMeshHash(ro->session().view().mesh());
    EXPECT_THROW(ro->stroke({Vec3(0, 0, -22), Vec3(4, 0, -22)}, false), SessionError);
    EXPECT_EQ(core::canonicalMeshHash(ro->session().view().mesh()), before);
    EXPECT_EQ(ro->session().history().done().size(), 1u);
    EXPECT_EQ(ro->stepCount(), 1u);
    EXPECT_THROW(ro->undo(), SessionError);
    EXPECT_EQ(ro->stepCount(), 1u);
    EXPECT_THROW(ro->save(), SessionError);
    EXPECT_EQ(ro->session().verifyMesh(), "");
}

}  // namespace

namespace {

// Sculpt steps, undos and redos leave sketch.json as it was wherever the journal alone gives
// the timeline back on opening (a stroke made with nothing to redo always does). Random
// sessions of strokes, sketch lines, lines on the model, undos and redos, reopened every one to
// three steps without saving: the timeline, what can be redone, the mesh and the sketch are
// exactly as they were live, and undo walks back the same way.
TEST(Studio, ReopeningGivesTheTimelineBackWhateverTheStepsSinceTheSketchFile) {
    using Step = Studio::Step;
    size_t quietStrokes = 0, sculptStepsWithSketchRedo = 0;
    for (const unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        TempDir dir;
        std::mt19937 rng(seed);
        std::vector<Step> done, redo;
        State live;
        for (int round = 0; round < 24; ++round) {
            auto studio = Studio::openProject(dir.path, smallConfig());
            studio->setSurfaceProjector(
                [](const Session&, const std::vector<glm::dvec2>& px, glm::ivec2) {
                    std::vector<std::vector<Vec3>> lines(1);
                    for (const glm::dvec2& p : px)
                        lines[0].push_back(Vec3(p.x / 20, -20, p.y / 20));
                    return lines;
                });
            if (round > 0) {
                EXPECT_EQ(studio->timeline(), done) << "round " << round;
                EXPECT_EQ(studio->redoTimeline(), redo) << "round " << round;
                EXPECT_EQ(state(*studio), live) << "round " << round;
            }
            for (int k = 0, n = 1 + int(rng() % 3); k < n; ++k) {
                // The file's time set back: a write replaces the file with one of the time now.
                // (The file is written on the studio's writer thread: what earlier steps posted
                // is waited for first, and what this one posted before the check.)
                studio->waitForSketchFile();
                const auto file = dir.path / "sketch.json";
                const auto longAgo = std::filesystem::file_time_type{};
                if (std::filesystem::exists(file)) std::filesystem::last_write_time(file, longAgo);
                const bool sketchBefore =
                    std::any_of(studio->redoTimeline().begin(), studio->redoTimeline().end(),
                                [](const Step& s) { return !s.sculpt(); });
                const size_t redoBefore = studio->redoTimeline().size();
                // 0, 1: a stroke (add, carve), 2: a sketch line, 3: a line on the model,
                // 4: undo (three times as often), 5: redo (twice), so that steps of every
                // kind come to be redone.
                const int r = int(rng() % 9);
                const int op = r <= 3 ? r : r <= 6 ? 4 : 5;
                const double x = double(rng() % 40) - 20, z = double(rng() % 10) + 16;
                bool sculptOp = false;
                if (op == 0 || op == 1) {
                    std::ostringstream s;
                    s << "tool " << (op == 0 ? "add" : "carve") << "\nsize 5\nstroke " << x << " 0 "
                      << z << " " << x + 4 << " 0 " << z + 1 << "\n";
                    run(*studio, s.str());
                    sculptOp = true;
                } else if (op == 2) {
                    run(*studio, "page Body Figures\n" + linePen(40 + x, -30, 80 + x, -30 + z));
                } else if (op == 3) {
                    run(*studio, "model-line 400 300 20,150 380," + std::to_string(100 + z) + "\n");
                } else if (op == 4) {
                    sculptOp = !studio->timeline().empty() && studio->timeline().back().sculpt();
                    studio->undo();
                } else {
                    sculptOp =
                        !studio->redoTimeline().empty() && studio->redoTimeline().back().sculpt();
                    studio->redo();
                }
                const bool sketchAfter =
                    std::any_of(studio->redoTimeline().begin(), studio->redoTimeline().end(),
                                [](const Step& s) { return !s.sculpt(); });
                studio->waitForSketchFile();
                const bool written = std::filesystem::exists(file) &&
                                     std::filesystem::last_write_time(file) != longAgo;
                // A stroke made with nothing to redo (the common case: sculpting on) leaves the
                // file as it was.
                if (op <= 1 && redoBefore == 0) {
                    EXPECT_FALSE(written) << "round " << round;
                    ++quietStrokes;
                }
                // Where the file must say more than the journal: a sculpt undo or redo with
                // sketch steps to redo.
                sculptStepsWithSketchRedo += sculptOp && sketchBefore && sketchAfter;
            }
            done = studio->timeline();
            redo = studio->redoTimeline();
            live = state(*studio);
        }
        // Undo walks the reopened timeline back to the start.
        auto studio = Studio::openProject(dir.path, smallConfig());
        EXPECT_EQ(studio->timeline(), done);
        for (size_t left = studio->stepCount(); left > 0; --left)
            studio->undo();
        EXPECT_EQ(studio->stepCount(), 0u);
        EXPECT_EQ(studio->session().history().done().size(), 0u);
    }
    // The sessions did what the test is about: strokes left the file alone, and sculpt undos
    // and redos had sketch steps to redo at times.
    EXPECT_GT(quietStrokes, 10u);
    EXPECT_GT(sculptStepsWithSketchRedo, 2u);
}

}  // namespace

namespace {

// Undo a stroke, then draw a sketch line: the line is a new step, so the stroke can no longer
// be redone, and reopening the project must not offer it again (it did: the session keeps its
// own redo list until its next stroke, and opening read that list as redo steps the file had
// not seen, so redo re-applied a stroke the sculptor had thrown away).
TEST(Studio, AStrokeASketchStepTookOffTheTimelineIsNotRedoneAfterReopening) {
    TempDir dir;
    uint64_t afterUndo = 0;
    {
        auto studio = Studio::openProject(dir.path, smallConfig());
        run(*studio, "tool add\nsize 5\nstroke 0 0 22 5 0 24\n");
        ASSERT_TRUE(studio->undo());
        afterUndo = core::canonicalMeshHash(studio->session().view().mesh());
        run(*studio, "page Body Figures\n" + linePen(40, -30, 80, -30));
        EXPECT_EQ(studio->redoCount(), 0u);
    }  // closed without saving
    auto studio = Studio::openProject(dir.path, smallConfig());
    EXPECT_EQ(studio->redoCount(), 0u);
    EXPECT_FALSE(studio->redo());
    EXPECT_EQ(core::canonicalMeshHash(studio->session().view().mesh()), afterUndo);
    // A save (a snapshot) does not bring it back either.
    studio->save();
    studio.reset();
    studio = Studio::openProject(dir.path, smallConfig());
    EXPECT_EQ(studio->redoCount(), 0u);
    EXPECT_EQ(core::canonicalMeshHash(studio->session().view().mesh()), afterUndo);
}

}  // namespace
