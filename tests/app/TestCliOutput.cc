// SPDX-License-Identifier: MIT
// What the program says and where: levels (--quiet, --verbose) through spdlog, pure machine
// output on stdout, rounded times, progress bars, numbers people can read, turntables.
#include "../TestFiles.h"
#include "vsculpt/app/Cli.h"
#include "vsculpt/app/Interrupt.h"
#include "vsculpt/app/Log.h"
#include "vsculpt/app/ProgressBar.h"
#include "vsculpt/app/RenderStill.h"
#include "vsculpt/core/WriteFileAtomically.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct CliRun {
    int code;
    std::string out, err;
};

CliRun run(std::vector<std::string> args) {
    std::vector<const char*> argv{"vsculpt"};
    for (const std::string& a : args)
        argv.push_back(a.c_str());
    std::ostringstream out, err;
    const int code = vsculpt::app::runCli(int(argv.size()), argv.data(), out, err);
    return {code, out.str(), err.str()};
}

const std::string kSnowman = std::string(VSCULPT_EXAMPLES_DIR) + "/snowman.vsc";

fs::path scratchDir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() /
                       ("vsculpt-cli-output-" + std::to_string(::getpid()) + "-" + name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

using vsculpt::test::readFile;

// Width and height from a PNG's IHDR chunk (bytes 16..23, big-endian).
std::pair<int, int> pngSize(const std::string& bytes) {
    auto be32 = [&](size_t at) {
        return int((uint8_t(bytes[at]) << 24) | (uint8_t(bytes[at + 1]) << 16) |
                   (uint8_t(bytes[at + 2]) << 8) | uint8_t(bytes[at + 3]));
    };
    if (bytes.size() < 24 || bytes.compare(1, 3, "PNG") != 0) return {0, 0};
    return {be32(16), be32(20)};
}

TEST(CliOutput, NormalRunsSayWhatWasWrittenWithARoundedTime) {
    const fs::path dir = scratchDir("normal");
    const CliRun r = run({"play", kSnowman, "--out", (dir / "a.obj").string()});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;  // people's lines go to stderr
    EXPECT_NE(r.err.find("vsculpt play: wrote " + (dir / "a.obj").string()), std::string::npos)
        << r.err;
    // The summary ends with the run's time as people read it: "850 ms" or "12.4 s".
    const std::regex summary(R"(vsculpt play: 29 command\(s\), .* mesh hash [0-9a-f]{16}, )"
                             R"((\d{1,3} ms|\d+\.\d s|\d+ min \d\d s)\n)");
    EXPECT_TRUE(std::regex_search(r.err, summary)) << r.err;
    EXPECT_EQ(r.err.find("debug:"), std::string::npos) << r.err;
    fs::remove_all(dir);
}

TEST(CliOutput, QuietKeepsOnlyErrorsAndWarnings) {
    const fs::path dir = scratchDir("quiet");
    CliRun r = run({"play", kSnowman, "--out", (dir / "a.stl").string(), "--quiet"});
    ASSERT_EQ(r.code, 0) << r.err;
    // Only the warning is left: the snowman's size-1 detail is lost at the default spacing.
    EXPECT_EQ(r.err.rfind("vsculpt play: warning: the export's grid spacing", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(fs::exists(dir / "a.stl"));
    // Before the subcommand as well, and errors still get through.
    r = run({"-q", "play", (dir / "missing.vsc").string()});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("vsculpt play: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("missing.vsc"), std::string::npos) << r.err;
    // --stats - stays pure JSON whatever the level.
    r = run({"play", kSnowman, "--stats", "-", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NO_THROW({
        const nlohmann::json parsed = nlohmann::json::parse(r.out);
        EXPECT_FALSE(parsed.is_null());
    }) << r.out;
    fs::remove_all(dir);
}

// Found by fuzzing: a script whose file name is not UTF-8 ran, exported, and then failed
// (exit 1) writing --stats: JSON strings must be UTF-8. The name is written with U+FFFD.
TEST(CliOutput, StatsOfAScriptWhoseNameIsNotUtf8AreWritten) {
    const fs::path dir = scratchDir("utf8");
    const fs::path script = dir / "sn\xffow.vsc";
    fs::copy_file(kSnowman, script);
    const CliRun r = run({"play", script.string(), "--stats", (dir / "s.json").string(), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json stats = nlohmann::json::parse(readFile(dir / "s.json"));
    EXPECT_EQ(stats["script"].get<std::string>(), (dir / "sn\xef\xbf\xbdow.vsc").string());
    fs::remove_all(dir);
}

TEST(CliOutput, VerboseAddsDebugMessagesAndConflictsWithQuiet) {
    const fs::path dir = scratchDir("verbose");
    CliRun r = run({"play", kSnowman, "--out", (dir / "a.ply").string(), "--verbose"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("vsculpt play: debug: config: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("vsculpt play: debug: meshed the whole sculpture at 2.81 mm"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("vsculpt play: wrote "), std::string::npos) << r.err;
    r = run({"-q", "-v", "info"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("excludes"), std::string::npos) << r.err;
    fs::remove_all(dir);
}

TEST(CliOutput, MessagesAreRestoredAfterARun) {
    // A run points spdlog at its own error stream; afterwards nothing may still write there.
    const auto before = spdlog::default_logger();
    {
        std::ostringstream err;
        vsculpt::app::LogScope scope(err, vsculpt::app::Verbosity::Verbose, "vsculpt test");
        spdlog::info("hello");
        spdlog::debug("details {}", 3);
        spdlog::warn("careful");
        spdlog::error("broken");
        scope.rename("vsculpt again");
        spdlog::info("renamed");
        EXPECT_EQ(err.str(),
                  "vsculpt test: hello\nvsculpt test: debug: details 3\n"
                  "vsculpt test: warning: careful\nvsculpt test: error: broken\n"
                  "vsculpt again: renamed\n");
    }
    EXPECT_EQ(spdlog::default_logger(), before);
    std::ostringstream quietErr;
    {
        vsculpt::app::LogScope scope(quietErr, vsculpt::app::Verbosity::Quiet);
        spdlog::info("not shown");
        spdlog::warn("shown");
    }
    EXPECT_EQ(quietErr.str(), "vsculpt: warning: shown\n");
}

TEST(CliOutput, DurationsAreRounded) {
    using vsculpt::app::formatDuration;
    EXPECT_EQ(formatDuration(0.0004), "0 ms");
    EXPECT_EQ(formatDuration(0.8504), "850 ms");
    EXPECT_EQ(formatDuration(12.44), "12.4 s");
    EXPECT_EQ(formatDuration(185.2), "3 min 05 s");
    EXPECT_EQ(formatDuration(7322), "2 h 02 min");
    EXPECT_EQ(formatDuration(-1), "?");
}

TEST(CliOutput, ProgressBarDrawsAndErasesItself) {
    std::ostringstream s;
    {
        vsculpt::app::ProgressBar bar(s, true, 200, "line");
        bar.update(200, 17);  // the last update is always drawn
        EXPECT_NE(s.str().find("\r[##############################] 100 % line 17"),
                  std::string::npos)
            << s.str();
        bar.clear();
        const std::string drawn = s.str();
        EXPECT_EQ(drawn.substr(drawn.size() - 74), "\r" + std::string(72, ' ') + "\r");
        bar.clear();  // nothing drawn: nothing to erase
        EXPECT_EQ(s.str(), drawn);
    }
    std::ostringstream off;
    {
        vsculpt::app::ProgressBar bar(off, false, 10, "row");
        bar.update(5, 5);
    }
    EXPECT_EQ(off.str(), "");
}

TEST(CliOutput, TurntableFramesAreNumbered) {
    using vsculpt::app::turntablePath;
    EXPECT_EQ(turntablePath("turn.png", 0, 36), "turn-000.png");
    EXPECT_EQ(turntablePath("out/turn.png", 35, 36), "out/turn-035.png");
    EXPECT_EQ(turntablePath("t.png", 1234, 2000), "t-1234.png");
    EXPECT_EQ(turntablePath("frame_##.png", 7, 36), "frame_07.png");
    EXPECT_EQ(turntablePath("f####x.png", 12, 24), "f0012x.png");
    EXPECT_EQ(turntablePath("a.b/turn", 2, 10), "a.b/turn-002");  // a dot in a folder name
}

TEST(CliOutput, TurntableTurnsTheSculptureInOneFraming) {
    const fs::path dir = scratchDir("turntable");
    const std::string pattern = (dir / "t.png").string();
    CliRun r = run({"render", kSnowman, "--out", pattern, "--turntable", "4", "--size", "48x40",
                    "--samples", "1", "--spacing", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("wrote 4 frames"), std::string::npos) << r.err;
    std::vector<std::string> frames;
    for (int i = 0; i < 4; ++i) {
        frames.push_back(readFile(dir / ("t-00" + std::to_string(i) + ".png")));
        EXPECT_EQ(pngSize(frames.back()), std::make_pair(48, 40)) << i;
    }
    EXPECT_FALSE(fs::exists(dir / "t.png"));
    EXPECT_FALSE(fs::exists(dir / "t-004.png"));
    EXPECT_NE(frames[0], frames[1]);  // the snowman's face turns away
    // Frame 1 is the sculpture turned by 90 degrees in the turntable's framing: a turntable
    // started at 90 degrees begins with the very same image.
    const std::string shifted = (dir / "s.png").string();
    r = run({"render", kSnowman, "--out", shifted, "--turntable", "4", "--yaw", "90", "--size",
             "48x40", "--samples", "1", "--spacing", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(readFile(dir / "s-000.png"), frames[1]);
    EXPECT_EQ(readFile(dir / "s-003.png"), frames[0]);
    // Refused before any work: a non-PNG name, a frame count out of range.
    r = run({"render", kSnowman, "--out", (dir / "t.jpg").string(), "--turntable", "3"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("t.jpg: images are written as PNG"), std::string::npos) << r.err;
    r = run({"render", kSnowman, "--out", pattern, "--turntable", "0"});
    EXPECT_EQ(r.code, 2);
    fs::remove_all(dir);
}

TEST(CliOutput, HugeNumbersGetReadableMessages) {
    // std::to_string(1.8e308) has 309 digits: no message may contain such a run.
    const std::regex longRun(R"(\d{16,})");
    const std::vector<std::vector<std::string>> cases = {
        {"play", kSnowman, "--export-spacing", "1e-308"},
        {"play", kSnowman, "--export-spacing", "1e308"},
        {"play", kSnowman, "--export-spacing", "-5"},
        {"render", kSnowman, "--out", "x.png", "--spacing", "1e308"},
        {"render", kSnowman, "--out", "x.png", "--yaw", "1e308"},
        {"render", kSnowman, "--out", "x.png", "--pitch", "-1e999"},
        {"render", kSnowman, "--out", "x.png", "--size", "99999999999999999999x3"},
        {"--frames", "-1"},
        {"record", "--out", "x.vsrec", "--seconds", "1e308"},
    };
    for (const auto& c : cases) {
        CliRun r = run(c);
        std::string joined;
        for (const std::string& a : c) {
            joined += a + " ";
            // The user's own text may be echoed; numbers the program prints may not be long.
            for (size_t at; (at = r.err.find(a)) != std::string::npos;)
                r.err.erase(at, a.size());
        }
        EXPECT_EQ(r.code, 2) << joined << "\n" << r.err;
        EXPECT_FALSE(std::regex_search(r.err, longRun)) << joined << "\n" << r.err;
        EXPECT_FALSE(r.err.empty()) << joined;
    }
}

TEST(CliOutput, BinaryInputIsNamedNotEchoed) {
    const fs::path dir = scratchDir("binary");
    {
        std::ofstream f(dir / "elf.vsc", std::ios::binary);
        f << "tool add\nsize 7\n"
          << std::string(
                 "\x7F"
                 "ELF\x02\x01\x01\0\0\x1b[2J",
                 13);
    }
    for (const char* cmd : {"play", "render"}) {
        std::vector<std::string> args{cmd, (dir / "elf.vsc").string()};
        if (std::string(cmd) == "render")
            args.insert(args.end(), {"--out", (dir / "x.png").string()});
        const CliRun r = run(args);
        EXPECT_EQ(r.code, 2) << cmd;
        EXPECT_NE(r.err.find("elf.vsc:3: not a playback script: binary data (byte 16 is \\x7F"),
                  std::string::npos)
            << r.err;
        for (char c : r.err)
            EXPECT_TRUE(c == '\n' || (static_cast<unsigned char>(c) >= 0x20 && c != 0x7F))
                << cmd << ": raw byte " << int(static_cast<unsigned char>(c)) << " in " << r.err;
    }
    fs::remove_all(dir);
}

}  // namespace

// A sketched solid or an imported mesh wholly inside the clay adds nothing and makes no step;
// `play` says so with the script's line (as the sketch window does), and runs on.
TEST(CliOutput, ASolidOrMeshInsideTheClayIsNamedWithItsLine) {
    const fs::path dir = scratchDir("inside");
    auto loopScript = [&](const std::string& name, double radiusMm) {
        std::ostringstream s;
        s << "page body\nmode cleanup\npen";
        for (int i = 0; i <= 72; ++i) {
            const double a = 2 * 3.14159265358979 * i / 72;
            s << ' ' << radiusMm * std::cos(a) << ',' << radiusMm * std::sin(a) << ",0.8";
        }
        s << "\nendgroup\nrole outline last\nsolid inflate\n";
        const fs::path p = dir / name;
        std::ofstream(p) << s.str();
        return p.string();
    };
    // A 10 mm loop inflates inside the radius-40 sphere; a 60 mm one reaches out of it.
    const std::string small = loopScript("small.vsc", 10), big = loopScript("big.vsc", 60);
    CliRun r = run({"play", small, "--stats", "-"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("warning: " + small + ":6: the solid lies inside the clay: nothing added"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["sketch"]["solids"], 0) << r.out;
    r = run({"play", big, "--stats", "-"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["sketch"]["solids"], 1) << r.out;

    // A 10 mm cube at the sphere's centre, imported: the same.
    std::ofstream(dir / "cube.obj") << "v -5 -5 -5\nv 5 -5 -5\nv 5 5 -5\nv -5 5 -5\n"
                                       "v -5 -5 5\nv 5 -5 5\nv 5 5 5\nv -5 5 5\n"
                                       "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\n"
                                       "f 3 4 8 7\nf 4 1 5 8\n";
    std::ofstream(dir / "import.vsc") << "# a cube inside the sphere\nimport cube.obj\n";
    r = run({"play", (dir / "import.vsc").string()});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find((dir / "import.vsc").string() +
                         ":2: the mesh lies inside the clay: nothing added"),
              std::string::npos)
        << r.err;
    fs::remove_all(dir);
}

namespace {

// An output on the script, on another output or on a project's own files would overwrite
// what the run reads or writes: refused before the run (2), the file untouched.
TEST(CliOutput, OutputsThatWouldOverwriteTheRunsOwnFilesAreRefused) {
    const fs::path dir = scratchDir("clash");
    const fs::path script = dir / "s.vsc";
    std::ofstream(script) << "tool add\nsize 7\nstroke 0 0 40  10 0 45\n";
    const std::string before = readFile(script);
    CliRun r = run({"play", script.string(), "--stats", (dir / "." / "s.vsc").string()});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("that is the script being played"), std::string::npos) << r.err;
    EXPECT_EQ(readFile(script), before);

    r = run({"play", script.string(), "--out", (dir / "a.obj").string(), "--stats",
             (dir / "sub" / ".." / "a.obj").string()});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("the same file as --out " + (dir / "a.obj").string()), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "a.obj"));

    const fs::path project = dir / "p";
    ASSERT_EQ(run({"play", script.string(), "--project", project.string()}).code, 0);
    const std::string snapshot = readFile(project / "snapshot.vsnap");
    r = run({"play", script.string(), "--project", project.string(), "--stats",
             (project / "snapshot.vsnap").string()});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("inside the project folder"), std::string::npos) << r.err;
    EXPECT_EQ(readFile(project / "snapshot.vsnap"), snapshot);
    // Outputs elsewhere, and in a folder within the project, are written as before.
    fs::create_directories(project / "exports");
    r = run({"play", script.string(), "--project", project.string(), "--out",
             (project / "exports" / "s.obj").string()});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(project / "exports" / "s.obj"));
    fs::remove_all(dir);
}

}  // namespace

namespace {

// Ctrl-C or a kill during an export: the process ends as the signal says, and neither the
// export nor its hidden temporary file is left (a fine export's is hundreds of MB). The
// write is stopped with SIGTERM right after its temporary file is made.
TEST(CliOutput, AnInterruptedWriteLeavesNoTemporaryFile) {
    const fs::path dir = scratchDir("interrupt");
    std::ofstream(dir / "out.stl") << "old";
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        vsculpt::app::handleInterrupts();
        vsculpt::core::detail::setAfterTemporaryCreated([](const char*) { ::raise(SIGTERM); });
        try {
            vsculpt::core::writeFileAtomically(dir / "out.stl", std::string(1 << 20, 'x'), false);
        } catch (...) {
        }
        ::_exit(3);  // not reached: the signal ends the process
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << status;
    EXPECT_EQ(WTERMSIG(status), SIGTERM);
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir))
        left.push_back(e.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"out.stl"});
    EXPECT_EQ(readFile(dir / "out.stl"), "old");
    fs::remove_all(dir);
}

// In a window the first signal only asks it to close (it saves, then the process still ends
// as the signal says, so a shell sees 143); a second one ends the process at once.
TEST(CliOutput, AWindowsFirstSignalAsksItToCloseAndTheProcessThenEndsAsTheSignalSays) {
    auto runChild = [](auto body) {
        const pid_t child = ::fork();
        if (child == 0) {
            body();
            ::_exit(3);
        }
        int status = 0;
        EXPECT_EQ(::waitpid(child, &status, 0), child);
        return status;
    };
    // What main() does around a window that a SIGTERM closed: the close runs (exit 4 if the
    // signal had ended the process then), and the process ends by SIGTERM after it.
    int status = runChild([] {
        vsculpt::app::handleInterrupts();
        {
            vsculpt::app::InterruptScope windowOpen;
            ::raise(SIGTERM);
            if (vsculpt::app::interruptSignal() != SIGTERM) ::_exit(4);
        }
        vsculpt::app::endIfInterrupted();
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << status;
    EXPECT_EQ(WTERMSIG(status), SIGTERM);
    // A second Ctrl-C while the window closes does not wait for it.
    status = runChild([] {
        vsculpt::app::InterruptScope windowOpen;
        ::raise(SIGINT);
        ::raise(SIGINT);
        ::_exit(4);
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << status;
    EXPECT_EQ(WTERMSIG(status), SIGINT);
    // A recording stopped by Ctrl-C takes the signal and ends normally.
    status = runChild([] {
        {
            vsculpt::app::InterruptScope recording;
            ::raise(SIGINT);
            if (vsculpt::app::takeInterruptSignal() != SIGINT) ::_exit(4);
        }
        vsculpt::app::endIfInterrupted();
        ::_exit(0);
    });
    ASSERT_TRUE(WIFEXITED(status)) << status;
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
