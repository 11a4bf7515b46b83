// SPDX-License-Identifier: MIT
#include "vsculpt/app/Cli.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <vector>

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
