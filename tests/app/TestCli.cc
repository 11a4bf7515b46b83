// SPDX-License-Identifier: MIT
#include "vsculpt/app/Cli.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <unistd.h>

namespace {

struct CliRun {
    int code;
    std::string out, err;
};

CliRun run(std::vector<const char*> args) {
    args.insert(args.begin(), "vsculpt");
    std::ostringstream out, err;
    const int code = vsculpt::app::runCli(int(args.size()), args.data(), out, err);
    return {code, out.str(), err.str()};
}

TEST(Cli, InfoPrintsTheInitialSculpture) {
    const CliRun r = run({"info"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("placement mode: swept"), std::string::npos) << r.out;  // the default
    EXPECT_NE(r.out.find("support calibrated"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("initial sphere: radius 40.000 mm"), std::string::npos) << r.out;
    // One row per tool level.
    for (const char* row : {"    1 ", "    7 "})
        EXPECT_NE(r.out.find(row), std::string::npos);
}

// A recording replays with the config it was recorded with: one whose config lacks the
// sphere's core was recorded before the core existed and keeps the one-skeleton sphere; one
// recorded today keeps its core; --config replaces the recorded config altogether.
TEST(Cli, ARecordingReplaysWithTheSphereItWasRecordedWith) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("vsculpt-cli-sphere-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string before = (dir / "before.vsrec").string(),
                      today = (dir / "today.vsrec").string();
    std::ofstream(before)
        << "vsculpt-recording 1\nmeta config {\"initial_sphere\": {\"radius_mm\": 30}}\n";
    std::ofstream(today)
        << "vsculpt-recording 1\nmeta config {\"initial_sphere\": {\"radius_mm\": 30, "
           "\"core_weight\": 0.5}}\n";
    const CliRun a = run({"play", before.c_str(), "--no-progress"});
    EXPECT_EQ(a.code, 0) << a.err;
    EXPECT_NE(a.err.find(", 1 skeletons,"), std::string::npos) << a.err;
    const CliRun b = run({"play", today.c_str(), "--no-progress"});
    EXPECT_EQ(b.code, 0) << b.err;
    EXPECT_NE(b.err.find(", 2 skeletons,"), std::string::npos) << b.err;
    const std::string empty = (dir / "empty.json").string();
    std::ofstream(empty) << "{}";
    const CliRun c = run({"--config", empty.c_str(), "play", before.c_str(), "--no-progress"});
    EXPECT_EQ(c.code, 0) << c.err;
    EXPECT_NE(c.err.find(", 2 skeletons,"), std::string::npos) << c.err;  // today's defaults
    std::filesystem::remove_all(dir);
}

// A script checks itself: `expect inside|outside` fails the run (exit 1, file and line) when
// the clay is not so, after the strokes before it; `probe` says what the clay is at a point.
TEST(Cli, AScriptsExpectationsCheckTheClay) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("vsculpt-cli-expect-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string good = (dir / "good.vsc").string(), bad = (dir / "bad.vsc").string();
    // A size-5 carve dab at the top of the sphere (radius 40): a pit 7.5 mm deep.
    const char* carve = "expect inside 0 0 38\ntool carve\nsize 5\nstroke 0 0 40\n";
    std::ofstream(good) << carve << "expect outside 0 0 38\nexpect inside 0 0 31\nprobe 0 0 38\n";
    std::ofstream(bad) << carve << "expect outside 0 0 34\nexpect inside 0 0 38\n";
    const CliRun a = run({"play", good.c_str(), "--no-progress"});
    EXPECT_EQ(a.code, 0) << a.err;
    const size_t said = a.err.find("line 7: probe (0, 0, 38): outside the clay (f - c = -");
    ASSERT_NE(said, std::string::npos) << a.err;
    // The pit's floor straight below it: 38 - (40 - 7.5) (the dab's pit within 5 %).
    const size_t away = a.err.find("the surface ", said);
    ASSERT_NE(away, std::string::npos) << a.err;
    const double floorMm = std::atof(a.err.c_str() + away + 12);
    EXPECT_GT(floorMm, 5.5 - 0.4) << a.err;
    EXPECT_LT(floorMm, 5.5 + 0.4) << a.err;
    EXPECT_NE(
        a.err.find("mm away towards (0.00, 0.00, -1.00); outward normal (0.00, 0.00, 1.00)", said),
        std::string::npos)
        << a.err;
    const CliRun b = run({"play", bad.c_str(), "--no-progress"});
    EXPECT_EQ(b.code, 1) << b.err;
    EXPECT_NE(b.err.find("bad.vsc:6: expect inside failed: (0, 0, 38): outside the clay"),
              std::string::npos)
        << b.err;
    std::filesystem::remove_all(dir);
}

TEST(Cli, WithoutADisplayTheDefaultRunSaysSoAndPrintsTheSummary) {
    ::unsetenv("DISPLAY");
    ::unsetenv("WAYLAND_DISPLAY");
    const CliRun r = run({});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.err.find("no sculpting window"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("vsculpt play"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("initial sphere: radius 40.000 mm"), std::string::npos) << r.out;
}

TEST(Cli, HelpTellsTheOptions) {
    const CliRun r = run({"--help"});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("--config"), std::string::npos);
    EXPECT_NE(r.out.find("not built yet"), std::string::npos);
    EXPECT_NE(r.out.find("--stereo"), std::string::npos);
}

TEST(Cli, BadArgumentsAndConfigsExitWithTwo) {
    CliRun r = run({"--no-such-flag"});
    EXPECT_EQ(r.code, 2);
    EXPECT_FALSE(r.err.empty());
    r = run({"--config", "/nonexistent.json"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("/nonexistent.json: cannot open config file"), std::string::npos) << r.err;
}

}  // namespace
