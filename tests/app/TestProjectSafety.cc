// SPDX-License-Identifier: MIT
// No lost work, through the real executable: the sculpting window journals into a project
// and survives kill -9, a project is open in one process at a time, planted symlinks are
// never followed, `vsculpt render` never changes a project, bad outputs and spacings are
// refused before any work.
#include "vsculpt/core/Project.h"
#include "vsculpt/studio/Studio.h"

#include "../TestFiles.h"
#include "../TestFixtures.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

extern char** environ;

using namespace vsculpt;
using namespace vsculpt::studio;
using core::Vec3;
using test::TempDir;

namespace {

struct Child {
    pid_t pid = -1;
    std::filesystem::path log;
};

// Starts `args` with stdout and stderr into `log` and `extraEnv` added to the environment.
Child spawn(const std::vector<std::string>& args, const std::filesystem::path& log,
            const std::vector<std::string>& extraEnv = {}) {
    std::vector<char*> argv;
    for (const auto& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    std::vector<std::string> envStore;
    for (char** e = environ; *e; ++e) {
        const std::string var(*e);
        bool replaced = false;
        for (const std::string& x : extraEnv)
            replaced |= var.substr(0, var.find('=') + 1) == x.substr(0, x.find('=') + 1);
        if (!replaced) envStore.push_back(var);
    }
    envStore.insert(envStore.end(), extraEnv.begin(), extraEnv.end());
    std::vector<char*> env;
    for (auto& e : envStore)
        env.push_back(e.data());
    env.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    Child c;
    c.log = log;
    if (posix_spawn(&c.pid, argv[0], &actions, nullptr, argv.data(), env.data()) != 0) c.pid = -1;
    posix_spawn_file_actions_destroy(&actions);
    return c;
}

int wait(const Child& c) {
    int status = 0;
    waitpid(c.pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

using vsculpt::test::readFile;

// Runs the executable to the end: exit code and what it printed.
std::pair<int, std::string> run(const std::vector<std::string>& args, const TempDir& dir,
                                const std::vector<std::string>& env = {}) {
    std::vector<std::string> all{VSCULPT_BINARY};
    all.insert(all.end(), args.begin(), args.end());
    const Child c = spawn(all, dir.path / "out.log", env);
    const int code = wait(c);
    return {code, readFile(c.log)};
}

// A script of `n` strokes over the sphere, a few undone, one command a line.
std::filesystem::path writeScript(const std::filesystem::path& path, int n) {
    std::ofstream script(path);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-25, 25);
    for (int i = 0; i < n; ++i) {
        script << "tool " << (i % 4 == 3 ? "carve" : "add") << "\nsize " << 5 + i % 3 << "\nstroke";
        const Vec3 p(U(rng), U(rng), U(rng));
        for (int k = 0; k < 6; ++k)
            script << "  " << p.x + 2.0 * k << " " << p.y << " " << p.z + k;
        script << "\n";
        if (i % 7 == 6) script << "undo\n";
    }
    return path;
}

std::filesystem::path writeConfig(const std::filesystem::path& path) {
    std::ofstream(path)
        << R"({"polygonizer": {"grid_n": 48}, "initial_sphere": {"radius_mm": 30}})";
    return path;
}

// A private X server for the window (Xvfb picks a free display and tells it on a pipe).
class XServer {
  public:
    XServer() {
        int fds[2];
        if (pipe(fds) != 0) return;
        const std::string fd = std::to_string(fds[1]);
        std::vector<std::string> args{"/usr/bin/Xvfb", "-displayfd", fd,   "-screen", "0",
                                      "1024x768x24",   "-nolisten",  "tcp"};
        std::vector<char*> argv;
        for (auto& a : args)
            argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addclose(&actions, fds[0]);
        posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
        if (posix_spawn(&mPid, argv[0], &actions, nullptr, argv.data(), environ) != 0) mPid = -1;
        posix_spawn_file_actions_destroy(&actions);
        ::close(fds[1]);
        // The display number, written once the server is ready, ends with a newline.
        std::string number;
        char ch = 0;
        while (::read(fds[0], &ch, 1) == 1 && ch != '\n')
            number += ch;
        ::close(fds[0]);
        if (!number.empty()) mDisplay = ":" + number;
    }
    ~XServer() {
        if (mPid > 0) {
            ::kill(mPid, SIGTERM);
            waitpid(mPid, nullptr, 0);
        }
    }
    const std::string& display() const { return mDisplay; }

  private:
    pid_t mPid = -1;
    std::string mDisplay;
};

TEST(ProjectSafety, WindowKilledMidSessionReopensAsTheJournalPrefix) {
    TempDir dir;
    XServer x;
    ASSERT_FALSE(x.display().empty()) << "Xvfb did not start";
    const auto script = writeScript(dir.path / "s.vsc", 60);
    const auto config = writeConfig(dir.path / "c.json");
    const auto project = dir.path / "window-project";
    // The window plays a command a frame and never closes by itself: it is killed.
    const Child c =
        spawn({VSCULPT_BINARY, "--hidden", "--no-devices", "--frames", "0", "--play",
               script.string(), "--project", project.string(), "--config", config.string()},
              dir.path / "window.log", {"DISPLAY=" + x.display()});
    ASSERT_GT(c.pid, 0);
    // Until the journal holds a dozen records (the window saves as it sculpts), then kill -9.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    size_t records = 0;
    while (std::chrono::steady_clock::now() < deadline && records < 12) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        records = core::readJournal(core::journalPath(project)).records.size();
    }
    ::kill(c.pid, SIGKILL);
    const int code = wait(c);
    ASSERT_GE(records, 12u) << readFile(c.log);
    EXPECT_EQ(code, 128 + SIGKILL) << "the window ended by itself: " << readFile(c.log);

    const core::SculptConfig cfg = core::loadConfig(config);
    auto reopened = Session::openProject(project, cfg);
    const size_t edits = size_t(reopened->editSequence());
    EXPECT_GE(edits, 12u);
    Session replay(cfg);
    size_t applied = 0;
    for (const ScriptCommand& cmd : loadScript(script).commands) {
        if (applied == edits) break;
        applied += replay.apply(cmd) ? 1 : 0;
    }
    ASSERT_EQ(applied, edits);
    EXPECT_EQ(core::canonicalMeshHash(reopened->view().mesh()),
              core::canonicalMeshHash(replay.view().mesh()));
    EXPECT_EQ(reopened->verifyMesh(), "");
}

TEST(ProjectSafety, TheWindowSavesToAnAutosaveProjectAndReopensIt) {
    TempDir dir;
    XServer x;
    ASSERT_FALSE(x.display().empty());
    const auto script = writeScript(dir.path / "s.vsc", 4);
    const auto config = writeConfig(dir.path / "c.json");
    const std::vector<std::string> env{"DISPLAY=" + x.display(),
                                       "XDG_DATA_HOME=" + (dir.path / "data").string()};
    const std::vector<std::string> args{"--hidden", "--no-devices",  "--frames", "30",
                                        "--play",   script.string(), "--config", config.string()};
    const auto [code, log] = run(args, dir, env);
    ASSERT_EQ(code, 0) << log;
    const auto autosave = dir.path / "data" / "vsculpt" / "autosave";
    ASSERT_TRUE(std::filesystem::is_directory(autosave)) << log;
    std::vector<std::filesystem::path> projects;
    for (const auto& e : std::filesystem::directory_iterator(autosave))
        projects.push_back(e.path());
    ASSERT_EQ(projects.size(), 1u);
    EXPECT_NE(log.find(projects[0].string()), std::string::npos) << log;
    size_t strokes = 0;
    {
        auto s = Session::openProject(projects[0], core::loadConfig(config), ProjectMode::ReadOnly);
        strokes = s->history().done().size();
        EXPECT_EQ(strokes, 4u);  // every stroke journaled, none lost on closing
    }
    // Closing wrote a snapshot of them: the next start reads it and replays nothing (through
    // placement rules that may have changed since).
    EXPECT_EQ(core::readJournal(core::journalPath(projects[0])).records.size(), 0u);
    const core::RecoveredProject stored = core::readProject(projects[0]);
    ASSERT_TRUE(stored.snapshot.has_value());
    EXPECT_EQ(stored.snapshot->lastSequence, 4u);
    EXPECT_TRUE(stored.records.empty());
    // The next window continues the same project (the script adds its strokes again).
    const auto [code2, log2] = run(args, dir, env);
    ASSERT_EQ(code2, 0) << log2;
    EXPECT_NE(log2.find(projects[0].string()), std::string::npos) << log2;
    auto s = Session::openProject(projects[0], core::loadConfig(config), ProjectMode::ReadOnly);
    EXPECT_EQ(s->history().done().size(), 2 * strokes);
}

TEST(ProjectSafety, ASecondProcessIsRefusedWhileTheProjectIsOpen) {
    TempDir dir;
    const auto script = writeScript(dir.path / "s.vsc", 3);
    const auto project = dir.path / "p";
    uint64_t hash = 0;
    {
        auto held = Studio::openProject(project, test::smallConfig());
        held->stroke({Vec3(0, 0, 30), Vec3(5, 0, 30)}, false);
        hash = core::canonicalMeshHash(held->session().view().mesh());
        const auto [code, log] =
            run({"play", script.string(), "--project", project.string(), "--no-progress"}, dir);
        EXPECT_EQ(code, 2) << log;
        EXPECT_NE(log.find("open in another vsculpt (pid " + std::to_string(::getpid()) + ")"),
                  std::string::npos)
            << log;
    }
    // Nothing of the refused run reached the journal.
    auto s = Session::openProject(project, test::smallConfig());
    EXPECT_EQ(s->history().done().size(), 1u);
    EXPECT_EQ(core::canonicalMeshHash(s->view().mesh()), hash);
}

TEST(ProjectSafety, PlantedSymlinksAreNeverFollowed) {
    TempDir dir;
    const auto script = writeScript(dir.path / "s.vsc", 2);
    const auto victim = dir.path / "victim.txt";
    std::ofstream(victim) << "precious";
    // At the lock file: refused with the path, the victim untouched.
    const auto p1 = dir.path / "p1";
    std::filesystem::create_directories(p1);
    std::filesystem::create_symlink(victim, p1 / "lock");
    const auto [code, log] =
        run({"play", script.string(), "--project", p1.string(), "--no-progress"}, dir);
    EXPECT_EQ(code, 2) << log;
    EXPECT_NE(log.find((p1 / "lock").string()), std::string::npos) << log;
    EXPECT_EQ(readFile(victim), "precious");
    // At the fixed temporary names writers used to use: they are not used any more, so a
    // link there changes nothing, and a save never writes through it.
    const auto p2 = dir.path / "p2";
    std::filesystem::create_directories(p2);
    for (const char* name : {"snapshot.vsnap.tmp", "sketch.json.tmp", "journal.vjl.tmp"})
        std::filesystem::create_symlink(victim, p2 / name);
    const auto out = dir.path / "out.obj";
    std::filesystem::create_symlink(victim, dir.path / "out.obj.tmp");
    const auto [code2, log2] = run(
        {"play", script.string(), "--project", p2.string(), "--no-progress", "--out", out.string()},
        dir);
    EXPECT_EQ(code2, 0) << log2;
    EXPECT_EQ(readFile(victim), "precious");
    EXPECT_TRUE(std::filesystem::is_regular_file(out));
}

TEST(ProjectSafety, RenderNeverChangesAProject) {
    TempDir dir;
    const auto project = dir.path / "p";
    {
        auto s = Studio::openProject(project, test::smallConfig());
        s->stroke({Vec3(0, 0, 30), Vec3(8, 0, 30)}, false);
        s->stroke({Vec3(0, 0, -30), Vec3(8, 0, -30)}, false);
    }
    // A torn record at the journal's end: opening for writing would cut it off.
    std::ofstream(core::journalPath(project), std::ios::app | std::ios::binary) << "torn";
    std::map<std::string, std::string> before;
    for (const auto& e : std::filesystem::directory_iterator(project))
        before[e.path().filename().string()] = readFile(e.path());
    const auto png = dir.path / "still.png";
    const auto [code, log] = run({"render", project.string(), "--out", png.string(), "--size",
                                  "64x48", "--samples", "1", "--spacing", "3"},
                                 dir);
    EXPECT_EQ(code, 0) << log;
    EXPECT_TRUE(std::filesystem::exists(png));
    EXPECT_NE(log.find("journal.vjl"), std::string::npos) << "the torn tail is reported: " << log;
    std::map<std::string, std::string> after;
    for (const auto& e : std::filesystem::directory_iterator(project))
        after[e.path().filename().string()] = readFile(e.path());
    after.erase("lock");  // a reader may leave the (empty) lock file
    before.erase("lock");
    EXPECT_EQ(after, before);
    // Beside a process that has it open, render still reads it (and says so).
    auto held = Studio::openProject(project, test::smallConfig());
    const auto [code2, log2] = run({"render", project.string(), "--out", png.string(), "--size",
                                    "64x48", "--samples", "1", "--spacing", "3"},
                                   dir);
    EXPECT_EQ(code2, 0) << log2;
    EXPECT_NE(log2.find("open in another vsculpt"), std::string::npos) << log2;
    EXPECT_NE(log2.find("reading it as it is now"), std::string::npos) << log2;
    // Neither a note called a warning nor the writer's advice to a reader.
    EXPECT_EQ(log2.find("note:"), std::string::npos) << log2;
    EXPECT_EQ(log2.find("close it first"), std::string::npos) << log2;
}

TEST(ProjectSafety, BadOutputsAndSpacingsAreRefusedBeforeTheRun) {
    TempDir dir;
    const auto script = writeScript(dir.path / "s.vsc", 2);
    const auto missing = dir.path / "no-such-folder" / "x.obj";
    auto [code, log] = run({"play", script.string(), "--out", missing.string()}, dir);
    EXPECT_EQ(code, 2) << log;
    EXPECT_NE(log.find(missing.parent_path().string()), std::string::npos) << log;
    EXPECT_EQ(log.find("command(s)"), std::string::npos) << "the session ran: " << log;
    // A spacing so small the grid's cell count overflows any integer: refused, no UB.
    std::tie(code, log) =
        run({"play", script.string(), "--export-spacing", "1e-300", "--no-progress"}, dir);
    EXPECT_EQ(code, 2) << log;
    EXPECT_NE(log.find("1024 cells per axis hold at that spacing: give --export-spacing"),
              std::string::npos)
        << log;
}

}  // namespace
