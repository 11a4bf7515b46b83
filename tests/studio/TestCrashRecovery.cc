// SPDX-License-Identifier: MIT
// kill -9 at random moments of a recorded session, 20 times: reopening the project must give
// exactly the sculpture of replaying the journal's complete prefix of edits.
#include "vsculpt/studio/Session.h"

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
#include <thread>

extern char** environ;

using namespace vsculpt;
using namespace vsculpt::studio;
using core::Vec3;

namespace {

pid_t spawn(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const auto& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return rc == 0 ? pid : -1;
}

TEST(CrashRecovery, KillNineLosesAtMostTheEditInFlight) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("vsculpt-crash-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto scriptPath = dir / "session.vsc";
    const auto configPath = dir / "config.json";
    std::ofstream(configPath)
        << R"({"polygonizer": {"grid_n": 64}, "initial_sphere": {"radius_mm": 30}})";
    {
        std::ofstream script(scriptPath);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> U(-30, 30);
        for (int i = 0; i < 40; ++i) {
            script << "tool " << (i % 4 == 3 ? "carve" : "add") << "\nsize " << 5 + i % 3
                   << "\nstroke";
            const Vec3 p(U(rng), U(rng), U(rng));
            for (int k = 0; k < 8; ++k)
                script << "  " << p.x + 2.0 * k << " " << p.y << " " << p.z + k;
            script << "\n";
            if (i % 9 == 8) script << "undo\n";
        }
    }
    const Script script = loadScript(scriptPath);
    const core::SculptConfig cfg = core::loadConfig(configPath);
    auto run = [&](const std::filesystem::path& project) {
        return spawn({VSCULPT_BINARY, "play", scriptPath.string(), "--project", project.string(),
                      "--config", configPath.string(), "--no-progress"});
    };

    // How long an uninterrupted run takes, to spread the kills over it.
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t full = run(dir / "full");
    ASSERT_GT(full, 0);
    int status = 0;
    waitpid(full, &status, 0);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    const double runMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> when(0.05 * runMs, 0.95 * runMs);
    int midRun = 0;
    for (int kill = 0; kill < 20; ++kill) {
        const auto project = dir / ("p" + std::to_string(kill));
        const pid_t pid = run(project);
        ASSERT_GT(pid, 0);
        std::this_thread::sleep_for(std::chrono::microseconds(int64_t(when(rng) * 1000)));
        ::kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        if (WIFSIGNALED(status)) ++midRun;
        if (!std::filesystem::exists(core::snapshotPath(project))) continue;  // killed at start

        auto reopened = Session::openProject(project, cfg);
        // Snapshot + journal hold a prefix of the script's edits: replay that prefix afresh.
        const size_t edits = size_t(reopened->editSequence());
        Session replay(cfg);
        size_t applied = 0;
        for (const ScriptCommand& c : script.commands) {
            if (applied == edits) break;
            applied += replay.apply(c) ? 1 : 0;
        }
        ASSERT_EQ(applied, edits);
        EXPECT_EQ(core::canonicalMeshHash(reopened->view().mesh()),
                  core::canonicalMeshHash(replay.view().mesh()))
            << "kill " << kill << " after " << edits << " edit(s)";
        EXPECT_EQ(reopened->verifyMesh(), "");
    }
    RecordProperty("kills_mid_run", midRun);
    EXPECT_GE(midRun, 1);
    std::filesystem::remove_all(dir);
}

}  // namespace
