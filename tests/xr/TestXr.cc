// SPDX-License-Identifier: MIT
// The OpenXR path end to end: the real vsculpt executable, the real Khronos loader and its
// core validation layer, and the scripted test runtime (TestRuntime.cpp) found through
// XR_RUNTIME_JSON; GL from Mesa under the xvfb-run the test binary runs in. Every run must leave
// the validation layer and the debug messenger silent.
#include "vsculpt/app/XrPanelUi.h"
#include "vsculpt/render/Viewer.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/Studio.h"

#include <gtest/gtest.h>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct XrRun {
    int exitCode = -1;
    std::string output;            ///< vsculpt's stdout and stderr
    std::vector<std::string> log;  ///< the test runtime's log
    std::string validation;        ///< what the validation layer wrote to its file
};

class Xr : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::temp_directory_path() /
               ("vsculpt-xr-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override {
        if (!HasFailure()) fs::remove_all(mDir);
    }

    fs::path write(const std::string& name, const std::string& text) {
        std::ofstream(mDir / name) << text;
        return mDir / name;
    }

    /// vsculpt ARGS with the test runtime (or `manifest`) and the validation layer.
    XrRun run(const std::string& script, const std::string& args,
              const std::string& manifest = VSCULPT_XR_TEST_MANIFEST,
              const std::string& extraEnv = "", bool display = true,
              const std::string& project = "--no-project") {
        const fs::path scriptPath = write("script.txt", script);
        const fs::path logPath = mDir / "runtime.log", validationPath = mDir / "validation.txt";
        fs::remove(logPath);
        fs::remove(validationPath);
        std::ostringstream cmd;
        cmd << "env XR_RUNTIME_JSON='" << manifest << "'"
            << " XR_ENABLE_API_LAYERS=XR_APILAYER_LUNARG_core_validation"
            << " XR_CORE_VALIDATION_EXPORT_TYPE=text XR_CORE_VALIDATION_FILE_NAME='"
            << validationPath.string() << "'"
            << " VSCULPT_TEST_XR_SCRIPT='" << scriptPath.string() << "'"
            << " VSCULPT_TEST_XR_LOG='" << logPath.string() << "' " << extraEnv << " "
            << (display ? "" : "env -u DISPLAY -u WAYLAND_DISPLAY ") << VSCULPT_BINARY << " "
            << project << " --no-devices --hidden " << args << " 2>&1";
        XrRun r;
        FILE* p = ::popen(cmd.str().c_str(), "r");
        if (!p) return r;
        char buf[4096];
        size_t n;
        while ((n = std::fread(buf, 1, sizeof buf, p)) > 0)
            r.output.append(buf, n);
        const int status = ::pclose(p);
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        std::ifstream in(logPath);
        for (std::string line; std::getline(in, line);)
            r.log.push_back(line);
        std::ifstream v(validationPath);
        r.validation.assign(std::istreambuf_iterator<char>(v), {});
        return r;
    }

    fs::path mDir;
};

/// `vsculpt play INPUT` (a script or a recording): its exit code, and its stdout and stderr
/// in `output`.
int play(const fs::path& input, std::string& output) {
    const std::string cmd =
        std::string(VSCULPT_BINARY) + " play '" + input.string() + "' --no-progress 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return -1;
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;)
        output.append(buf, n);
    const int status = ::pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The run was validated and nothing was reported: the layer was loaded (it announces its
/// output), its file is empty, and the app's debug messenger counted no warning or error.
void expectValidationClean(const XrRun& r) {
    EXPECT_NE(r.output.find("Core Validation output type: text"), std::string::npos)
        << "the validation layer was not loaded:\n"
        << r.output;
    EXPECT_EQ(r.validation, "") << "validation layer messages";
    EXPECT_NE(r.output.find(" 0 debug message(s)"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("VUID"), std::string::npos) << r.output;
}

std::string match(const std::string& text, const std::string& re) {
    std::smatch m;
    return std::regex_search(text, m, std::regex(re)) ? m[1].str() : std::string();
}

size_t indexOf(const std::vector<std::string>& log, const std::string& line, size_t from = 0) {
    for (size_t i = from; i < log.size(); ++i)
        if (log[i] == line) return i;
    return std::string::npos;
}

std::vector<std::string> linesStarting(const std::vector<std::string>& log,
                                       const std::string& prefix) {
    std::vector<std::string> out;
    for (const std::string& l : log)
        if (l.rfind(prefix, 0) == 0) out.push_back(l);
    return out;
}

// Poses in local space are metres; the sculpture's origin sits at (0, -0.25, -0.5) (the
// config's default). Multiples of 1/256 m are exact in float and in mm (3.90625 mm), so the
// poses the runtime hands over in floats land on the script's numbers bit for bit.
std::string local(int xSteps, int upSteps, int backSteps) {
    std::ostringstream s;
    s.precision(17);
    s << xSteps / 256.0 << " " << -0.25 + upSteps / 256.0 << " " << -0.5 + backSteps / 256.0;
    return s.str();
}

TEST_F(Xr, SessionLifecycleAndBothEyesEveryFrame) {
    const XrRun r = run("", "--xr --frames 12");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    // The session goes idle -> ready -> (begun) -> synchronized -> visible -> focused, and
    // on --frames: exit requested -> stopping -> (ended) -> idle -> exiting -> destroyed.
    size_t at = 0;
    for (const char* step :
         {"state idle", "state ready", "begin session", "state synchronized", "state visible",
          "state focused", "request exit", "state stopping", "end session", "state idle",
          "state exiting", "destroy session", "destroy instance"}) {
        const size_t i = indexOf(r.log, step, at);
        ASSERT_NE(i, std::string::npos) << "missing or out of order: " << step;
        at = i + 1;
    }
    EXPECT_EQ(linesStarting(r.log, "swapchain 256x256 format 0x8058").size(), 2u)
        << "one linear RGBA8 swapchain per eye";
    EXPECT_EQ(linesStarting(r.log, "swapchain 720x360 format 0x8058").size(), 1u)
        << "the status panel's";
    EXPECT_EQ(linesStarting(r.log, "bindings /interaction_profiles/").size(), 4u);
    const auto frames = linesStarting(r.log, "frame ");
    ASSERT_EQ(frames.size(), 12u);
    // Both eyes' projection layer, then the status panel as a quad layer over it.
    const std::regex both(
        R"(frame \d+ layers 2 projection views 2 eye0 released 1 rect 256x256 lit (-?\d+) eye1 released 1 rect 256x256 lit (-?\d+) quad 720x360 size 0.360x0.180 released 1 lit (-?\d+))");
    for (const std::string& f : frames) {
        std::smatch m;
        ASSERT_TRUE(std::regex_match(f, m, both)) << f;
    }
    // Frame 0 is read back: the sculpture is in front of both eyes.
    std::smatch m;
    ASSERT_TRUE(std::regex_match(frames[0], m, both));
    EXPECT_GT(std::stol(m[1]), 100) << frames[0];
    EXPECT_GT(std::stol(m[2]), 100) << frames[0];
    EXPECT_GT(std::stol(m[3]), 1000) << "the status panel has text: " << frames[0];
    EXPECT_NE(r.output.find("12 frame(s), 12 with both eyes drawn"), std::string::npos) << r.output;
}

TEST_F(Xr, RuntimeEndingTheSessionEndsTheProgram) {
    const XrRun r = run("at 6 exit\n", "--xr");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    EXPECT_NE(r.output.find("the OpenXR runtime ended the session"), std::string::npos) << r.output;
    EXPECT_EQ(indexOf(r.log, "request exit"), std::string::npos);
    EXPECT_NE(indexOf(r.log, "end session"), std::string::npos);
}

TEST_F(Xr, LossPendingIsAFailure) {
    const XrRun r = run("at 4 lose\n", "--xr");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    expectValidationClean(r);
    EXPECT_NE(r.output.find("the headset was lost"), std::string::npos) << r.output;
    EXPECT_NE(indexOf(r.log, "destroy session"), std::string::npos);
}

TEST_F(Xr, TriggerStrokeSculptsTheSameMeshAsTheScript) {
    // The pen rests above the sphere (radius 40 mm), the trigger goes down at frame 5, the pen
    // sweeps along x at z = 39.0625 mm, y = -3.90625 mm, the trigger comes up at frame 14.
    std::ostringstream xr, vsc;
    xr << "at 0 right " << local(-16, 32, 1) << " 0 0 0 1\n";
    vsc << "space world\nstroke";
    for (int i = 0; i <= 8; ++i) {
        xr << "at " << 5 + i << " right " << local(-16 + 4 * i, 10, 1) << " 0 0 0 1\n";
        vsc << " " << (-16 + 4 * i) * 3.90625 << " -3.90625 39.0625";
    }
    xr << "at 5 /user/hand/right/input/trigger/value 1\n"
       << "at 14 /user/hand/right/input/trigger/value 0\n";
    vsc << "\n";
    const XrRun r = run(xr.str(), "--xr --frames 20");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    const std::string xrHash = match(r.output, "mesh hash ([0-9a-f]{16})");
    EXPECT_NE(r.output.find(", 1 step(s)"), std::string::npos) << r.output;

    const fs::path vscPath = write("stroke.vsc", vsc.str());
    std::string playOut;
    ASSERT_EQ(play(vscPath, playOut), 0) << playOut;
    const std::string playHash = match(playOut, "mesh hash ([0-9a-f]{16})");
    ASSERT_FALSE(playHash.empty()) << playOut;
    EXPECT_EQ(xrHash, playHash) << r.output << "\n" << playOut << "\n" << vsc.str();
    // And the stroke changed the sculpture (the untouched sphere hashes otherwise).
    const XrRun still = run("", "--xr --frames 3");
    EXPECT_NE(match(still.output, "mesh hash ([0-9a-f]{16})"), xrHash);
}

TEST_F(Xr, GripTurnsAndMovesTheSculpture) {
    // The left hand closes its grip at frame 4, turns 90 degrees about the vertical and moves
    // 0.25 m up by frame 8, and lets go at frame 10; then it moves away.
    const double h = std::sqrt(0.5);
    std::ostringstream s;
    s << "at 0 left " << local(-40, 0, 0) << " 0 0 0 1\n"
      << "at 4 /user/hand/left/input/squeeze/value 1\n"
      << "at 8 left " << local(-40, 64, 0) << " 0 " << h << " 0 " << h << "\n"
      << "at 10 /user/hand/left/input/squeeze/value 0\n"
      << "at 12 left " << local(0, 0, 0) << " 0 0 0 1\n";
    const XrRun r = run(s.str(), "--xr --frames 16");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    const std::string pose = match(r.output, R"(object pose: (rotation \(.*\) mm))");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        pose, m,
        std::regex(R"(rotation \((\S+) (\S+) (\S+) (\S+)\), translation \((\S+) (\S+) (\S+)\))")))
        << r.output;
    // Local y is the world's z: a quarter turn about +z about the hand (156.25 mm to the
    // sculpture's left) swings the sculpture from the hand's +x to its +y; plus the hand's
    // 250 mm rise.
    EXPECT_NEAR(std::abs(std::stod(m[1])), h, 1e-5);
    EXPECT_NEAR(std::abs(std::stod(m[4])), h, 1e-5);
    EXPECT_NEAR(std::stod(m[2]), 0, 1e-5);
    EXPECT_NEAR(std::stod(m[3]), 0, 1e-5);
    EXPECT_NEAR(std::stod(m[5]), -156.25, 1e-2);
    EXPECT_NEAR(std::stod(m[6]), 156.25, 1e-2);
    EXPECT_NEAR(std::stod(m[7]), 250, 1e-2);
}

TEST_F(Xr, HapticPulsesFollowContact) {
    // Air (well above the sphere), touching (centre 3 mm outside it), inside (the centre),
    // air again. No trigger: nothing is sculpted, the sphere stays as it is.
    std::ostringstream s;
    s << "at 0 right " << local(0, 32, 0) << " 0 0 0 1\n"
      << "at 6 right " << local(0, 11, 0) << " 0 0 0 1\n"
      << "at 10 right " << local(0, 0, 0) << " 0 0 0 1\n"
      << "at 14 right " << local(0, 32, 0) << " 0 0 0 1\n";
    const XrRun r = run(s.str(), "--xr --frames 20");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    std::map<int, std::string> byFrame;
    const std::regex pulse(R"(haptic frame (\d+) hand right amplitude ([0-9.]+) duration_ms 20.0)");
    const std::regex stop(R"(haptic_stop frame (\d+) hand right)");
    for (const std::string& l : r.log) {
        std::smatch m;
        if (std::regex_match(l, m, pulse)) byFrame[std::stoi(m[1])] = m[2];
        if (std::regex_match(l, m, stop)) byFrame[std::stoi(m[1])] = "stop";
        ASSERT_EQ(l.find("hand left"), std::string::npos) << "only the pen hand vibrates: " << l;
    }
    for (int f = 0; f < 6; ++f)
        EXPECT_EQ(byFrame.count(f), 0u) << "a pulse in the air, frame " << f;
    for (int f = 6; f < 10; ++f)
        EXPECT_EQ(byFrame[f], "0.300") << "touching, frame " << f;
    for (int f = 10; f < 14; ++f)
        EXPECT_EQ(byFrame[f], "0.800") << "inside, frame " << f;
    EXPECT_EQ(byFrame[14], "stop");
    for (int f = 15; f < 20; ++f)
        EXPECT_EQ(byFrame.count(f), 0u) << "a pulse after leaving the clay, frame " << f;
    EXPECT_NE(r.output.find("8 haptic pulse(s)"), std::string::npos) << r.output;
}

TEST_F(Xr, RecordingReplaysToTheSameSculpture) {
    // Grab and turn the sculpture a quarter, then stroke over it: the stroke lands in object
    // space through the turned pose, so the replay must get both the grab and the stroke.
    const double h = std::sqrt(0.5);
    std::ostringstream s;
    s << "at 0 left " << local(-40, 0, 0) << " 0 0 0 1\n"
      << "at 3 /user/hand/left/input/squeeze/value 1\n"
      << "at 5 left " << local(-40, 0, 0) << " 0 " << h << " 0 " << h << "\n"
      << "at 6 /user/hand/left/input/squeeze/value 0\n"
      << "at 0 right " << local(-16, 32, 1) << " 0 0 0 1\n";
    for (int i = 0; i <= 8; ++i)
        s << "at " << 8 + i << " right " << local(-60 + 4 * i, -30, 10) << " 0 0 0 1\n";
    s << "at 8 /user/hand/right/input/trigger/value 1\n"
      << "at 17 /user/hand/right/input/trigger/value 0\n";
    const fs::path rec = mDir / "session.vsrec";
    const XrRun r = run(s.str(), "--xr --frames 22 --record '" + rec.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    EXPECT_NE(r.output.find(", 1 step(s)"), std::string::npos) << r.output;
    const std::string liveHash = match(r.output, "mesh hash ([0-9a-f]{16})");
    ASSERT_TRUE(fs::exists(rec)) << r.output;

    std::string playOut;
    ASSERT_EQ(play(rec, playOut), 0) << playOut;
    EXPECT_EQ(match(playOut, "mesh hash ([0-9a-f]{16})"), liveHash) << r.output << "\n" << playOut;
    EXPECT_NE(playOut.find("xr: "), std::string::npos) << "the device summary:\n" << playOut;
}

// Found by QA: --record wrote over whatever it was given, the project's journal included (the
// project then no longer opened), or the script being played; and without --xr it was
// silently ignored. All are refused before the session, the files untouched.
TEST_F(Xr, ARecordingThatWouldOverwriteTheSessionsOwnFilesIsRefused) {
    const std::string scriptText = "stroke 0 0 40  10 0 40\n";
    const fs::path script = write("s.vsc", scriptText);
    XrRun r = run(
        "", "--xr --frames 3 --play '" + script.string() + "' --record '" + script.string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("that is the script being played"), std::string::npos) << r.output;
    std::ifstream in(script);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), scriptText);

    // The project's own files: a journal with one edit, left as it was.
    const fs::path project = mDir / "p";
    ASSERT_EQ(std::system((std::string(VSCULPT_BINARY) + " play '" + script.string() +
                           "' --project '" + project.string() + "' -q")
                              .c_str()),
              0);
    const std::string snapshot = [&] {
        std::ifstream f(project / "snapshot.vsnap", std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    r = run("", "--xr --frames 3 --record '" + (project / "journal.vsrec").string() + "'",
            VSCULPT_XR_TEST_MANIFEST, "", true, "--project '" + project.string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("inside the project folder"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(project / "journal.vsrec"));
    // A hard link of the snapshot outside the project is the snapshot (found by QA: the
    // recording was written into it).
    const fs::path link = mDir / "linked.vsrec";
    fs::create_hard_link(project / "snapshot.vsnap", link);
    r = run("", "--xr --frames 3 --record '" + link.string() + "'", VSCULPT_XR_TEST_MANIFEST, "",
            true, "--project '" + project.string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("that is the project's snapshot.vsnap under another name"),
              std::string::npos)
        << r.output;
    {
        std::ifstream f(project / "snapshot.vsnap", std::ios::binary);
        EXPECT_EQ(std::string(std::istreambuf_iterator<char>(f), {}), snapshot);
    }

    // Not a recording's name, and --record without a headset session.
    r = run("", "--xr --frames 3 --record '" + (mDir / "take.png").string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("name the file .vsrec"), std::string::npos) << r.output;
    r = run("", "--frames 3 --record '" + (mDir / "take.vsrec").string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("it needs --xr"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(mDir / "take.vsrec"));
}

TEST_F(Xr, LeftButtonsCycleTheToolOnTouchControllers) {
    // Oculus Touch: x cycles the tool (add -> carve), y steps the size.
    const XrRun r =
        run("profile /interaction_profiles/oculus/touch_controller\n"
            "at 3 /user/hand/left/input/x/click 1\n"
            "at 5 /user/hand/left/input/x/click 0\n"
            "at 6 /user/hand/left/input/y/click 1\n",
            "--xr --frames 10");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    EXPECT_NE(r.output.find("tool carve"), std::string::npos) << r.output;
    const XrRun before = run("", "--xr --frames 2");
    EXPECT_NE(match(before.output, "size (\\d+)"), match(r.output, "size (\\d+)")) << r.output;
}

// The local-space pose (metres; "X Y Z QX QY QZ QW") of a pen a third of a metre in front of
// the headset's panel, pointing at the centre of its button `name` as the panel lays it out
// (the same UI code and font in this process, under the same Xvfb).
std::string penAtPanelButton(const std::string& name) {
    static std::map<std::string, vsculpt::app::UiRect> rects;
    const vsculpt::devices::XrPanel panel;
    if (rects.empty()) {
        vsculpt::render::Viewer viewer(64, 64, "panel layout", false);
        const vsculpt::core::SculptConfig cfg;
        vsculpt::studio::Studio studio(cfg);
        vsculpt::studio::Interaction interaction(studio);
        vsculpt::app::XrPanelUi ui(viewer, panel, cfg.render.xr, float(cfg.render.uiScale));
        ui.draw(vsculpt::app::sculptUiViewOf(studio.session(), interaction), "pen up", 0.011);
        rects = ui.state().rects;
    }
    const vsculpt::app::UiRect r = rects.at("button:" + name);
    const glm::dmat3 axes = glm::mat3_cast(glm::normalize(panel.orientation));
    const double heightM = panel.widthM * panel.heightPx / panel.widthPx;
    const glm::dvec3 target =
        panel.positionM + axes * glm::dvec3((r.cx() / panel.widthPx - 0.5) * panel.widthM,
                                            (0.5 - r.cy() / panel.heightPx) * heightM, 0);
    const glm::dvec3 pen = target + axes * glm::dvec3(0, 0, 0.33) + glm::dvec3(0.03, -0.02, 0);
    const glm::dquat q = glm::rotation(glm::dvec3(0, 0, -1), glm::normalize(target - pen));
    std::ostringstream out;
    out.precision(9);
    out << pen.x << " " << pen.y << " " << pen.z << " " << q.x << " " << q.y << " " << q.z << " "
        << q.w;
    return out.str();
}

TEST_F(Xr, ThePenClicksThePanelAndARecordingReplaysTheClick) {
    // The pen points at the panel's "x" mirror button and the trigger clicks it (sculpting
    // nothing there), then a stroke beside the plane x = 0 adds clay on both sides.
    std::ostringstream s;
    s << "at 0 right " << penAtPanelButton("mirror x") << "\n"
      << "at 2 /user/hand/right/input/trigger/value 1\n"
      << "at 4 /user/hand/right/input/trigger/value 0\n";
    std::ostringstream stroke;
    for (int i = 0; i <= 8; ++i)
        stroke << "at " << 8 + i << " right " << local(4 + 2 * i, 10, 1) << " 0 0 0 1\n";
    stroke << "at 8 /user/hand/right/input/trigger/value 1\n"
           << "at 17 /user/hand/right/input/trigger/value 0\n";
    const fs::path rec = mDir / "session.vsrec";
    const XrRun r = run(s.str() + stroke.str(), "--xr --frames 22 --record '" + rec.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    // One step: the click added no clay where the pen was.
    EXPECT_NE(r.output.find(", 1 step(s)"), std::string::npos) << r.output;
    const std::string liveHash = match(r.output, "mesh hash ([0-9a-f]{16})");
    const XrRun plain = run(stroke.str(), "--xr --frames 22");
    ASSERT_EQ(plain.exitCode, 0) << plain.output;
    EXPECT_NE(match(plain.output, "mesh hash ([0-9a-f]{16})"), liveHash)
        << "the stroke was not mirrored: the click did not reach the studio";

    // The recording holds the click with the hands: the replay mirrors the stroke too.
    std::string playOut;
    ASSERT_EQ(play(rec, playOut), 0) << playOut;
    EXPECT_EQ(match(playOut, "mesh hash ([0-9a-f]{16})"), liveHash) << r.output << "\n" << playOut;
}

TEST_F(Xr, ThumbsticksJumpToASizeAndZoomIn) {
    // Index: the right stick pushed left jumps to the smallest size zoom 1 offers (5), the
    // left stick up zooms in one level, where the smallest size at zoom 2 (4) is offered.
    const XrRun r =
        run("at 3 /user/hand/right/input/thumbstick/x -1\n"
            "at 5 /user/hand/right/input/thumbstick/x 0\n"
            "at 6 /user/hand/left/input/thumbstick/y 1\n"
            "at 8 /user/hand/left/input/thumbstick/y 0\n",
            "--xr --frames 12");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectValidationClean(r);
    EXPECT_EQ(match(r.output, "size (\\d+)"), "5") << r.output;
    EXPECT_EQ(match(r.output, "zoom (\\d+)"), "2") << r.output;
}

TEST_F(Xr, ConfigOutputXrOpensTheHeadsetWithoutTheFlag) {
    const fs::path cfg = write("config.json", R"({"render": {"output": "xr"}})");
    const XrRun r = run("", "--config '" + cfg.string() + "' --frames 3");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("openxr: scripted test headset on vsculpt test runtime"),
              std::string::npos)
        << r.output;
}

TEST_F(Xr, NoRuntimeFallsBackToTheWindow) {
    const XrRun r = run("", "--xr --frames 3", (mDir / "no-such-runtime.json").string());
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("no headset: no OpenXR runtime (XR_ERROR_RUNTIME_UNAVAILABLE)"),
              std::string::npos)
        << r.output;
    // The loader's own lines stay out of it (XR_LOADER_DEBUG brings them back).
    EXPECT_EQ(r.output.find("OpenXR-Loader"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("opening the desktop window instead"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("3 frame(s)"), std::string::npos) << "the window ran:\n" << r.output;
}

TEST_F(Xr, NoHeadsetFallsBackToTheWindow) {
    const XrRun r =
        run("", "--xr --frames 3", VSCULPT_XR_TEST_MANIFEST, "VSCULPT_TEST_XR_NO_HMD=1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("no headset (XR_ERROR_FORM_FACTOR_UNAVAILABLE"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("3 frame(s)"), std::string::npos) << r.output;
}

TEST_F(Xr, NoRuntimeAndNoDisplayFails) {
    const XrRun r =
        run("", "--xr --frames 3", (mDir / "none.json").string(), "", /*display=*/false);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("no sculpting window"), std::string::npos) << r.output;
}

}  // namespace
