// SPDX-License-Identifier: MIT
// The UI's files: the recent-projects list (order, duplicates, pruning of folders that are
// gone) and preferences saved as the user's config (atomically, read back by loadConfig);
// the help overlay lists every binding.
#include "vsculpt/app/Log.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/app/WindowUi.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/core/Project.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

using namespace vsculpt;
namespace fs = std::filesystem;

namespace {

// Points an XDG variable at a private folder for one test, and puts it back.
class ScopedEnv {
  public:
    ScopedEnv(const char* name, const fs::path& value) : mName(name) {
        if (const char* v = std::getenv(name)) mOld = v;
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (mOld)
            ::setenv(mName, mOld->c_str(), 1);
        else
            ::unsetenv(mName);
    }

  private:
    const char* mName;
    std::optional<std::string> mOld;
};

fs::path freshDir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

TEST(RecentProjects, MostRecentFirstWithoutDuplicatesAndCut) {
    using P = std::vector<fs::path>;
    EXPECT_EQ(app::withRecentProject({}, "/a"), P{"/a"});
    EXPECT_EQ(app::withRecentProject({"/a", "/b", "/c"}, "/c"), (P{"/c", "/a", "/b"}));
    EXPECT_EQ(app::withRecentProject({"/a", "/b"}, "/d"), (P{"/d", "/a", "/b"}));
    EXPECT_EQ(app::withRecentProject({"/a", "/b", "/c"}, "/d", 3), (P{"/d", "/a", "/b"}));
}

// Found by QA: the export key's default name was checked for a clash under another folder,
// so two exports within a second wrote one file, the second replacing the first.
TEST(RecentProjects, TimeNamesNeverReuseAFileOrFolderThere) {
    const fs::path d = freshDir("time-names");
    std::vector<fs::path> names;
    for (int i = 0; i < 3; ++i) {
        const fs::path p = app::unusedTimeName(d, ".glb");
        EXPECT_EQ(p.parent_path(), d);
        EXPECT_EQ(p.extension(), ".glb");
        EXPECT_FALSE(fs::exists(p)) << p;
        for (const fs::path& q : names)
            EXPECT_NE(p, q);
        std::ofstream(p) << "taken";
        names.push_back(p);
    }
    // A dangling symbolic link takes its name too.
    const fs::path next = app::unusedTimeName(d, ".glb");
    fs::create_symlink(d / "nowhere", next);
    EXPECT_NE(app::unusedTimeName(d, ".glb"), next);
    fs::remove_all(d);
}

TEST(RecentProjects, RememberedInOrderAndOnlyExistingOnesOffered) {
    const fs::path root = freshDir("vsculpt-recent");
    ScopedEnv data("XDG_DATA_HOME", root / "data");
    std::vector<fs::path> projects;
    for (const char* name : {"a", "b", "c"}) {
        const fs::path p = root / name;
        fs::create_directories(p);
        std::ofstream(core::snapshotPath(p)) << "x";  // a folder holding a project
        projects.push_back(p);
    }
    std::ostringstream log;
    {
        app::LogScope scope(log, app::Verbosity::Normal);  // warnings would land in `log`
        for (int i : {0, 1, 2, 0})
            app::rememberLastProject(projects[size_t(i)]);
    }
    EXPECT_EQ(log.str(), "");
    EXPECT_EQ(app::recentProjects(),
              (std::vector<fs::path>{projects[0], projects[2], projects[1]}));
    EXPECT_EQ(app::lastProject(), projects[0]);
    fs::remove_all(projects[2]);  // gone: no longer offered
    EXPECT_EQ(app::recentProjects(), (std::vector<fs::path>{projects[0], projects[1]}));
    fs::remove_all(root);
}

// A window opened with --project DIR lists it among the recent projects but leaves the last
// project (what a plain `vsculpt` continues) alone; `vsculpt play --project` lists nothing.
TEST(RecentProjects, GivenProjectsOfWindowsAreRecentButNotLast) {
    const fs::path root = freshDir("vsculpt-given");
    ScopedEnv data("XDG_DATA_HOME", root / "data");
    core::SculptConfig cfg;
    cfg.polygonizer.gridN = 16;
    {
        app::RigOptions autosave = app::windowRigOptions("", false, false);
        app::Rig rig(cfg, autosave);  // a new autosave project: last and recent
    }
    const auto last = app::lastProject();
    ASSERT_TRUE(last.has_value());
    { app::Rig rig(cfg, app::windowRigOptions((root / "given").string(), false, false)); }
    EXPECT_EQ(app::lastProject(), last);
    EXPECT_EQ(app::recentProjects(), (std::vector<fs::path>{root / "given", *last}));
    {
        app::RigOptions play;  // what `vsculpt play --project` builds
        play.project = app::ProjectChoice::Given;
        play.projectDir = root / "played";
        app::Rig rig(cfg, play);
    }
    EXPECT_EQ(app::recentProjects(), (std::vector<fs::path>{root / "given", *last}));
    fs::remove_all(root);
}

// The last project moved or deleted: a plain `vsculpt` starts a new project, and says why, so
// the user looks for the old one rather than thinking the work lost (found by QA).
TEST(RecentProjects, ALastProjectNoLongerThereIsNamedWhenANewOneStarts) {
    const fs::path root = freshDir("vsculpt-moved");
    ScopedEnv data("XDG_DATA_HOME", root / "data");
    core::SculptConfig cfg;
    cfg.polygonizer.gridN = 16;
    { app::Rig rig(cfg, app::windowRigOptions("", false, false)); }
    const auto first = app::lastProject();
    ASSERT_TRUE(first.has_value());
    fs::rename(*first, root / "moved");
    std::ostringstream log;
    {
        app::LogScope scope(log, app::Verbosity::Normal);
        app::Rig rig(cfg, app::windowRigOptions("", false, false));
        ASSERT_TRUE(rig.session().projectDir().has_value());
        EXPECT_EQ(rig.session().recoveredEdits(), 0u);
    }
    EXPECT_NE(log.str().find("the last project, " + first->string() +
                             ", is no longer there (moved or deleted?)"),
              std::string::npos)
        << log.str();
    // The new project is the last one now: the next start continues it without a warning.
    std::ostringstream again;
    {
        app::LogScope scope(again, app::Verbosity::Normal);
        app::Rig rig(cfg, app::windowRigOptions("", false, false));
    }
    EXPECT_EQ(again.str().find("no longer there"), std::string::npos) << again.str();
    // A folder that holds no project, and a file holding anything, are named as such, its
    // bytes escaped (found by QA: an escape sequence reached the terminal).
    const fs::path recorded = root / "data" / "vsculpt" / "last-project";
    fs::create_directories(root / "empty");
    for (const std::string& line : {(root / "empty").string(), std::string("\x1b[31mred")}) {
        std::ofstream(recorded) << line << "\n";
        std::ostringstream said;
        {
            app::LogScope scope(said, app::Verbosity::Normal);
            app::Rig rig(cfg, app::windowRigOptions("", false, false));
        }
        EXPECT_EQ(said.str().find('\x1b'), std::string::npos) << said.str();
        EXPECT_NE(said.str().find(line[0] == '/' ? "holds no project (no snapshot.vsnap)"
                                                 : "\\x1B[31mred, is no longer there"),
                  std::string::npos)
            << said.str();
    }
    fs::remove_all(root);
}

// "~/out.obj" typed in the export dialog is in the home folder, not in a folder named "~" in
// the current one (found by QA), and the message says the absolute path.
TEST(RecentProjects, APathTypedInADialogExpandsTheHomeFolder) {
    const fs::path root = freshDir("vsculpt-tilde");
    ScopedEnv home("HOME", root);
    ScopedEnv data("XDG_DATA_HOME", root / "data");
    core::SculptConfig cfg;
    cfg.polygonizer.gridN = 16;
    app::Rig rig(cfg, app::windowRigOptions("", false, false));
    app::UiState state;
    std::string message;
    bool switched = false;
    ASSERT_TRUE(
        app::applySharedUiAction({"export", "~/out.stl"}, rig, state, cfg, message, switched));
    if (auto done = rig.pollBackgroundWork(true)) message = *done;
    EXPECT_TRUE(fs::exists(root / "out.stl")) << message;
    EXPECT_FALSE(fs::exists(fs::current_path() / "~"));
    EXPECT_NE(message.find((root / "out.stl").string()), std::string::npos) << message;
    fs::remove_all(root);
}

// Opening a recent project switches the rig's studio only once the new one is open and
// locked: a folder without a project, or one open elsewhere, leaves the session as it was.
TEST(RecentProjects, OpeningOneSwitchesSafely) {
    const fs::path root = freshDir("vsculpt-open");
    ScopedEnv data("XDG_DATA_HOME", root / "data");
    core::SculptConfig cfg;
    cfg.polygonizer.gridN = 16;
    auto options = [&](const fs::path& dir) {
        app::RigOptions o;
        o.project = app::ProjectChoice::Given;
        o.projectDir = dir;
        return o;
    };
    { app::Rig make(cfg, options(root / "b")); }  // a project to open later
    app::Rig rig(cfg, options(root / "a"));
    app::Rig holder(cfg, options(root / "c"));  // keeps "c" locked
    EXPECT_THROW(rig.openProject(root / "nothing-here"), core::ProjectError);
    EXPECT_THROW(rig.openProject(root / "c"), std::exception);
    EXPECT_EQ(rig.session().projectDir(), root / "a");
    const std::string said = rig.openProject(root / "b");
    EXPECT_NE(said.find("opened " + (root / "b").string()), std::string::npos) << said;
    EXPECT_EQ(rig.session().projectDir(), root / "b");
    EXPECT_EQ(app::recentProjects().front(), root / "b");
    // "a" was saved and unlocked: another rig can open it now.
    EXPECT_NO_THROW(app::Rig(cfg, options(root / "a")));
}

TEST(Preferences, SavedAtomicallyAsTheUserConfigAndReadBack) {
    const fs::path root = freshDir("vsculpt-prefs");
    ScopedEnv config("XDG_CONFIG_HOME", root);
    core::SculptConfig cfg;
    cfg.render.stereo = "anaglyph";
    cfg.render.ipdMm = 58.5;
    cfg.render.uiScale = 1.5;
    cfg.render.uiDepthMm = 450;
    cfg.interaction.rotateRadPerPixel = 0.02;
    const fs::path written = app::savePreferences(cfg);
    EXPECT_EQ(written, root / "vsculpt" / "sculpt.json");
    EXPECT_EQ(core::defaultConfigPath(), written);  // what the next start reads
    const core::SculptConfig back = core::loadConfig(written);
    EXPECT_EQ(back.render.stereo, "anaglyph");
    EXPECT_EQ(back.render.ipdMm, 58.5);
    EXPECT_EQ(back.render.uiScale, 1.5);
    EXPECT_EQ(back.render.uiDepthMm, 450);
    EXPECT_EQ(back.interaction.rotateRadPerPixel, 0.02);
    EXPECT_EQ(back.interaction.bindings, cfg.interaction.bindings);
    // Saving again replaces the file through a temporary: nothing else is left in the folder.
    cfg.render.ipdMm = 61;
    app::savePreferences(cfg);
    EXPECT_EQ(core::loadConfig(written).render.ipdMm, 61);
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(root / "vsculpt")) {
        (void)e;
        ++files;
    }
    EXPECT_EQ(files, 1u);
    fs::remove_all(root);
}

TEST(Preferences, SavingOverAUsersFileKeepsItsComments) {
    const fs::path root = freshDir("vsculpt-prefs-comments");
    ScopedEnv config("XDG_CONFIG_HOME", root);
    fs::create_directories(root / "vsculpt");
    const std::string mine =
        "// my settings\n{\n  \"render\": {\n    \"ipd_mm\": 63.0  // measured\n  }\n}\n";
    { std::ofstream(root / "vsculpt" / "sculpt.json") << mine; }
    core::SculptConfig cfg = core::loadConfig(root / "vsculpt" / "sculpt.json");
    cfg.render.ipdMm = 61;
    const fs::path written = app::savePreferences(cfg);
    std::ifstream in(written);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text,
              "// my settings\n{\n  \"render\": {\n    \"ipd_mm\": 61.0  // measured\n  }\n}\n");
    EXPECT_EQ(core::loadConfig(written).render.ipdMm, 61);
    fs::remove_all(root);
}

TEST(Preferences, UiKeysAreValidated) {
    EXPECT_THROW(core::parseConfig(R"({"render": {"ui_scale": 9}})", "t.json"), core::ConfigError);
    EXPECT_THROW(core::parseConfig(R"({"render": {"ui_depth_mm": -1}})", "t.json"),
                 core::ConfigError);
    EXPECT_EQ(core::parseConfig(R"({"render": {"ui_depth_mm": 300}})", "t.json").render.uiDepthMm,
              300);
}

TEST(HelpOverlay, ListsEveryBindingAndTheMouse) {
    const core::SculptConfig cfg;
    for (bool sketch : {false, true}) {
        const auto& bindings = sketch ? cfg.interaction.sketchBindings : cfg.interaction.bindings;
        const auto lines = app::helpLines(bindings, sketch);
        for (const auto& [action, key] : bindings) {
            const bool listed =
                std::find(lines.begin(), lines.end(), std::make_pair(action, key)) != lines.end();
            EXPECT_TRUE(listed) << action;
        }
        EXPECT_GT(lines.size(), bindings.size());  // and the mouse
        bool leftButton = false;
        for (const auto& l : lines)
            leftButton |= l.second == "left button";
        EXPECT_TRUE(leftButton);
    }
    // The help key is bound in both windows, and not to a key the sketch window uses.
    EXPECT_EQ(cfg.interaction.bindings.at("help"), "F1");
    EXPECT_EQ(cfg.interaction.sketchBindings.at("help"), "F4");
}

}  // namespace

// Found by QA: the import dialog showed and used the export dialog's last up axis and units,
// so an import after a +Z / cm export came in ten times too large. Each dialog has its own.
TEST(Preferences, TheImportAndExportDialogsKeepTheirOwnFrames) {
    app::UiState state;
    state.pathField = "/tmp/x.stl";
    state.exportUp = 2;     // +Z
    state.exportUnits = 2;  // cm
    state.dialog = app::UiState::Dialog::Import;
    const app::UiAction plain = app::dialogAction(state);
    EXPECT_EQ(plain.name, "import");
    EXPECT_FALSE(plain.importOptions.up.has_value());
    EXPECT_FALSE(plain.importOptions.mmPerUnit.has_value());
    state.importUp = 1;     // +Y
    state.importUnits = 3;  // m
    const app::UiAction chosen = app::dialogAction(state);
    ASSERT_TRUE(chosen.importOptions.up.has_value());
    EXPECT_EQ(*chosen.importOptions.up, core::UpAxis::Y);
    ASSERT_TRUE(chosen.importOptions.mmPerUnit.has_value());
    EXPECT_EQ(*chosen.importOptions.mmPerUnit, 1000.0);
    state.dialog = app::UiState::Dialog::Export;
    const app::UiAction exported = app::dialogAction(state);
    EXPECT_EQ(exported.name, "export");
    EXPECT_EQ(exported.exportOptions.up, core::UpAxis::Z);
    EXPECT_EQ(exported.exportOptions.units, core::LengthUnit::Centimetre);
}
