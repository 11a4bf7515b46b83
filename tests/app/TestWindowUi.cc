// SPDX-License-Identifier: MIT
// The windows' on-screen UI (Dear ImGui) under Xvfb + Mesa: the panels are on screen with
// their colours and text, the help overlay comes with its key, side by side the UI is in both
// eyes at its disparity, clicks on the UI change the session without sculpting, and typing in
// the export dialog runs no key bindings; the headset's panel clicks where the pen points.
#include "vsculpt/app/Interrupt.h"
#include "vsculpt/app/SketchWindow.h"
#include "vsculpt/app/Window.h"
#include "vsculpt/app/XrPanelUi.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/render/Shot.h"
#include "vsculpt/render/Viewer.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/Studio.h"

#include <gtest/gtest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key and button codes

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace vsculpt;
using render::InputEvent;
namespace fs = std::filesystem;

namespace {

bool near(const uint8_t* p, const std::array<uint8_t, 3>& c, int tol) {
    return std::abs(p[0] - c[0]) <= tol && std::abs(p[1] - c[1]) <= tol &&
           std::abs(p[2] - c[2]) <= tol;
}

struct Census {
    size_t panel = 0, text = 0, total = 0;
};

// Panel-background and text-coloured pixels inside `r` (offset by dx), in `img`.
Census census(const render::Image& img, const app::UiRect& r, int dx = 0) {
    Census c;
    for (int y = int(r.y0); y < int(r.y1); ++y)
        for (int x = int(r.x0) + dx; x < int(r.x1) + dx; ++x) {
            if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
            const uint8_t* p = img.pixel(x, y);
            c.panel += near(p, app::kUiPanelRgb, 2);
            c.text += near(p, app::kUiTextRgb, 12);
            ++c.total;
        }
    return c;
}

app::WindowOptions scratchWindow(int frames) {
    app::WindowOptions o;
    o.noProject = true;
    o.devices = false;
    o.hidden = true;
    o.width = 960;
    o.height = 640;
    o.frames = frames;
    return o;
}

InputEvent key(int code, bool pressed) {
    return {InputEvent::Kind::Key, code, pressed, 0, 0};
}
InputEvent character(char c) {
    return {InputEvent::Kind::Char, int(c), true, 0, 0};
}
InputEvent cursor(double x, double y) {
    return {InputEvent::Kind::Cursor, 0, false, x, y};
}
InputEvent leftButton(bool pressed) {
    return {InputEvent::Kind::MouseButton, GLFW_MOUSE_BUTTON_LEFT, pressed, 0, 0};
}

// A click on the centre of the UI's rectangle `name` as it was last drawn: the pointer moves
// there at `at`, the button goes down a frame later and up the frame after.
void clickOn(const std::string& name, size_t at, size_t frame, const app::UiState& ui,
             std::vector<InputEvent>& inject, app::UiRect& where) {
    if (frame == at) {
        auto it = ui.rects.find(name);
        ASSERT_NE(it, ui.rects.end()) << name << " is not on screen";
        where = it->second;
        inject.push_back(cursor(where.cx(), where.cy()));
    }
    if (frame == at + 1) inject.push_back(leftButton(true));
    if (frame == at + 2) inject.push_back(leftButton(false));
}

TEST(WindowUi, PanelsAreOnScreenAndHelpComesWithItsKey) {
    app::WindowOptions o = scratchWindow(10);
    render::Image img;
    app::WindowOptions::Report report;
    o.lastFrame = &img;
    o.report = &report;
    bool helpBeforeKey = true;
    o.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        if (frame == 4) helpBeforeKey = ui.rects.count("help") > 0;
        if (frame == 4) inject.push_back(key(GLFW_KEY_F1, true));  // help (default binding)
        if (frame == 5) inject.push_back(key(GLFW_KEY_F1, false));
    };
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    EXPECT_FALSE(helpBeforeKey);
    ASSERT_EQ(img.width, 960);
    for (const char* name : {"status", "palette", "help"}) {
        ASSERT_TRUE(report.ui.rects.count(name)) << name;
        const Census c = census(img, report.ui.rects.at(name));
        // Mostly panel background, with text on it (labels, numbers).
        EXPECT_GT(c.panel, c.total / 3) << name;
        EXPECT_GT(c.text, 150u) << name;
    }
    // The status panel at the top left, the palette along the bottom, help in the middle.
    EXPECT_LT(report.ui.rects.at("status").y1, 320);
    EXPECT_GT(report.ui.rects.at("palette").y0, 320);
    EXPECT_TRUE(report.ui.rects.at("help").contains(480, 320));
    // Every size offered at zoom 1, each zoom level, the tools and undo/redo are buttons.
    for (const char* b : {"button:size 7", "button:size 6", "button:size 5", "button:zoom 1",
                          "button:zoom 5", "button:add", "button:carve", "button:select",
                          "button:undo", "button:redo", "button:export...", "button:help"})
        EXPECT_TRUE(report.ui.rects.count(b)) << b;
    // Outside the panels the scene is untouched: the window's middle-left is background.
    const uint8_t* bg = img.pixel(60, 320);
    EXPECT_TRUE(
        near(bg, {render::kBackground[0], render::kBackground[1], render::kBackground[2]}, 3));
}

TEST(WindowUi, SideBySideShowsTheUiInBothEyesAtItsDisparity) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("vsculpt-ui-sbs-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto run = [&](double depthMm, render::Image& img, app::WindowOptions::Report& report) {
        const std::filesystem::path config = dir / "c.json";
        core::writeFileAtomically(
            config, "{\"render\": {\"ui_depth_mm\": " + std::to_string(depthMm) + "}}", false);
        app::WindowOptions o = scratchWindow(4);
        o.configPath = config.string();
        o.stereo = "sbs";
        o.lastFrame = &img;
        o.report = &report;
        std::ostringstream out, err;
        ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    };
    render::Image flat, deep;
    app::WindowOptions::Report flatReport, deepReport;
    run(0, flat, flatReport);
    // A little nearer than the sculpture's centre (the zero-parallax plane): crossed
    // disparity of a few pixels.
    const double depth = 0.93 * flatReport.display.focalDistanceMm;
    run(depth, deep, deepReport);
    const int eyeW = 480;
    const int left = int(
        std::lround(render::eyeShiftNdc(deepReport.display, depth, render::Eye::Left) * eyeW / 2));
    const int right = int(
        std::lround(render::eyeShiftNdc(deepReport.display, depth, render::Eye::Right) * eyeW / 2));
    ASSERT_GT(left, 3);
    EXPECT_EQ(right, -left);
    EXPECT_NEAR(deepReport.uiShiftNdc[0], 2.0 * left / eyeW, 1e-12);
    for (const char* name : {"status", "palette"}) {
        const app::UiRect r = flatReport.ui.rects.at(name);
        EXPECT_LT(r.x1, eyeW) << name;  // laid out in one eye's image
        // On the plane: the same panel in both halves.
        for (int dx : {0, eyeW}) {
            const Census c = census(flat, r, dx);
            EXPECT_GT(c.panel, c.total / 3) << name << " " << dx;
            EXPECT_GT(c.text, 100u) << name << " " << dx;
        }
        // Nearer: each eye's copy moved by its shift (the panels' right edges are inside both
        // eyes' images; the left edges are near the image's edge).
        const app::UiRect d = deepReport.ui.rects.at(name);
        const int row = int(d.cy());
        auto lastPanel = [&](int x0, int x1) {
            for (int x = x1 - 1; x >= x0; --x)
                if (near(deep.pixel(x, row), app::kUiPanelRgb, 2)) return x;
            return -1;
        };
        const int l = lastPanel(0, eyeW), r2 = lastPanel(eyeW, 2 * eyeW);
        ASSERT_GE(l, 0);
        ASSERT_GE(r2, 0);
        EXPECT_EQ((r2 - eyeW) - l, right - left) << name;
        EXPECT_NEAR(l - d.x1, left, 2) << name;  // its border is a pixel or so
        const Census cl = census(deep, d, left), cr = census(deep, d, eyeW + right);
        EXPECT_GT(cl.panel, cl.total / 3) << name;
        EXPECT_GT(cr.panel, cr.total / 3) << name;
    }
    std::filesystem::remove_all(dir);
}

TEST(WindowUi, ClicksOnTheUiChangeSizeToolAndZoomWithoutSculpting) {
    // The control: the same click on the sculpture sculpts (so the check below can fail).
    {
        app::WindowOptions o = scratchWindow(8);
        app::WindowOptions::Report report;
        o.report = &report;
        o.onFrame = [&](size_t frame, const app::UiState&, std::vector<InputEvent>& inject) {
            if (frame == 2) inject.push_back(cursor(480, 320));
            if (frame == 3) inject.push_back(leftButton(true));
            if (frame == 4) inject.push_back(cursor(490, 322));
            if (frame == 5) inject.push_back(leftButton(false));
        };
        std::ostringstream out, err;
        ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
        EXPECT_GT(report.skeletons, 0u);
        EXPECT_EQ(report.steps, 1u);
    }
    app::WindowOptions o = scratchWindow(14);
    app::WindowOptions::Report report;
    o.report = &report;
    app::UiRect size5, carve;
    o.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        clickOn("button:size 5", 2, frame, ui, inject, size5);
        clickOn("button:carve", 6, frame, ui, inject, carve);
    };
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    EXPECT_EQ(report.size, 5);
    EXPECT_EQ(report.tool, studio::ToolKind::Carve);
    EXPECT_EQ(report.skeletons, 0u);  // nothing sculpted
    EXPECT_EQ(report.steps, 0u);

    // The smooth tool and a mirror plane, from the palette.
    app::WindowOptions m = scratchWindow(14);
    app::WindowOptions::Report mirrored;
    m.report = &mirrored;
    app::UiRect smooth, mirrorX;
    m.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        clickOn("button:smooth", 2, frame, ui, inject, smooth);
        clickOn("button:mirror x", 6, frame, ui, inject, mirrorX);
    };
    ASSERT_EQ(app::runWindow(m, out, err), 0) << err.str();
    EXPECT_EQ(mirrored.tool, studio::ToolKind::Smooth);
    EXPECT_EQ(mirrored.mirror, core::MirrorAxis::X);
    EXPECT_EQ(mirrored.steps, 0u);

    app::WindowOptions z = scratchWindow(8);
    app::WindowOptions::Report zoomed;
    z.report = &zoomed;
    app::UiRect zoom2;
    z.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        clickOn("button:zoom 2", 2, frame, ui, inject, zoom2);
    };
    ASSERT_EQ(app::runWindow(z, out, err), 0) << err.str();
    EXPECT_EQ(zoomed.zoom, 2);
    EXPECT_EQ(zoomed.skeletons, 0u);
    EXPECT_EQ(zoomed.steps, 0u);
}

// The left button held on the sculpture without moving: one dab, however many frames it is
// held. The tool rests on the clay as it was when the stroke began; on the live clay each
// frame's sample climbed the clay the last one added (a pillar toward the eye, more clay every
// frame).
TEST(WindowUi, HoldingTheButtonStillMakesOneDab) {
    auto hold = [](int frames) {
        app::WindowOptions o = scratchWindow(frames + 6);
        app::WindowOptions::Report report;
        o.report = &report;
        o.onFrame = [&](size_t frame, const app::UiState&, std::vector<InputEvent>& inject) {
            if (frame == 2) inject.push_back(cursor(480, 320));
            if (frame == 3) inject.push_back(leftButton(true));
            if (frame == size_t(3 + frames)) inject.push_back(leftButton(false));
        };
        std::ostringstream out, err;
        EXPECT_EQ(app::runWindow(o, out, err), 0) << err.str();
        EXPECT_EQ(report.steps, 1u);
        return report.skeletons;
    };
    const size_t brief = hold(2), held = hold(30);
    EXPECT_GT(brief, 0u);
    EXPECT_EQ(held, brief);
}

// What the close box does, Ctrl-C and SIGTERM (a logout) do too: the stroke in flight is
// ended and journaled, the project snapshotted, so the next open recovers nothing. The same
// for a `--play` line refused mid-script: the work before it is closed as usual.
// Reopened, the project holds `steps` steps and `skeletons` skeletons in its snapshot: the
// journal is empty, nothing is recovered.
void expectClosedWithASnapshot(const fs::path& dir, size_t steps, size_t skeletons) {
    EXPECT_EQ(core::readJournal(core::journalPath(dir)).records.size(), 0u)
        << "no closing snapshot absorbed the journal";
    auto studio = studio::Studio::openProject(dir, core::SculptConfig{});
    EXPECT_EQ(studio->session().recoveredEdits(), 0u);
    EXPECT_EQ(studio->stepCount(), steps);
    EXPECT_EQ(studio->session().sculpture().counts().lattice, skeletons);
}

TEST(WindowUi, SigtermClosesTheWindowAsItsCloseBoxWouldAndSavesTheWork) {
    const fs::path dir =
        fs::temp_directory_path() / ("vsculpt-sigterm-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    app::WindowOptions o = scratchWindow(0);  // no frame limit: only the signal ends it
    o.noProject = false;
    o.projectDir = dir.string();
    app::WindowOptions::Report report;
    o.report = &report;
    size_t lastFrame = 0;
    o.onFrame = [&](size_t frame, const app::UiState&, std::vector<InputEvent>& inject) {
        lastFrame = frame;
        if (frame == 2) inject.push_back(cursor(480, 320));
        if (frame == 3) inject.push_back(leftButton(true));  // held: a stroke in flight
        if (frame == 6) ::raise(SIGTERM);
        // A window that ignored the signal would run forever: end it, and fail below.
        if (frame == 100) inject.push_back({InputEvent::Kind::Close});
    };
    std::ostringstream out, err;
    EXPECT_EQ(app::runWindow(o, out, err), 0) << err.str();
    EXPECT_EQ(app::takeInterruptSignal(), SIGTERM);
    EXPECT_LE(lastFrame, 7u) << "the window went on after SIGTERM";
    EXPECT_NE(err.str().find("closing: "), std::string::npos) << err.str();
    EXPECT_EQ(report.steps, 1u);
    EXPECT_GT(report.skeletons, 0u);
    expectClosedWithASnapshot(dir, 1, report.skeletons);
    fs::remove_all(dir);
}

TEST(WindowUi, AScriptLineRefusedClosesTheWindowWithItsWorkSaved) {
    const fs::path dir =
        fs::temp_directory_path() / ("vsculpt-playfail-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir.parent_path());
    const fs::path script =
        fs::temp_directory_path() / ("vsculpt-playfail-" + std::to_string(::getpid()) + ".vsc");
    // Size 1 is not offered at zoom 1: refused when it runs, after the stroke was made.
    std::ofstream(script) << "stroke 0 0 40  10 0 40\nsize 1\nstroke 0 0 -40  10 0 -40\n";
    app::WindowOptions o = scratchWindow(50);
    o.noProject = false;
    o.projectDir = dir.string();
    o.playScript = script.string();
    app::WindowOptions::Report report;
    o.report = &report;
    std::ostringstream out, err;
    EXPECT_EQ(app::runWindow(o, out, err), 2) << err.str();
    EXPECT_NE(err.str().find(":2: "), std::string::npos) << err.str();
    EXPECT_EQ(report.steps, 1u);
    expectClosedWithASnapshot(dir, 1, report.skeletons);
    fs::remove_all(dir);
    fs::remove(script);
}

// Found by QA: --frames fewer than the script's commands ended the run part way, silently.
TEST(WindowUi, AWindowClosedBeforeItsScriptEndedSaysWhereItStopped) {
    const fs::path script =
        fs::temp_directory_path() / ("vsculpt-short-" + std::to_string(::getpid()) + ".vsc");
    std::ofstream(script) << "# three strokes\nstroke 0 0 40  10 0 40\nstroke 0 0 -40  10 0 -40\n"
                             "stroke 40 0 0  40 10 0\n";
    for (int frames : {2, 4}) {
        app::WindowOptions o = scratchWindow(frames);
        o.playScript = script.string();
        std::ostringstream out, err;
        EXPECT_EQ(app::runWindow(o, out, err), 0) << err.str();
        const bool warned =
            err.str().find("the window closed before the script ended: " + script.string() +
                           ":4 and the 0 command(s) after it were not run") != std::string::npos;
        EXPECT_EQ(warned, frames == 2) << err.str();
    }
    fs::remove(script);
}

// Found by QA: the scroll depth was kept in mm, so three notches set at size 7 (25 mm) buried
// a size-5 tool out of sight, and its carve made a hidden cavity inside the sphere. The depth
// is a share of the tool: the same carve now opens a groove in the surface.
TEST(WindowUi, TheScrollDepthFollowsTheToolSize) {
    const fs::path dir =
        fs::temp_directory_path() / ("vsculpt-depth-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    app::WindowOptions o = scratchWindow(30);
    o.noProject = false;
    o.projectDir = dir.string();
    app::WindowOptions::Report report;
    o.report = &report;
    o.onFrame = [&](size_t frame, const app::UiState&, std::vector<InputEvent>& inject) {
        if (frame == 2) inject.push_back(cursor(480, 330));
        if (frame >= 3 && frame <= 5) inject.push_back({InputEvent::Kind::Scroll, 0, false, 0, 1});
        if (frame == 6) inject.push_back(key(GLFW_KEY_5, true));
        if (frame == 7) inject.push_back(key(GLFW_KEY_TAB, true));  // carve
        if (frame == 9) inject.push_back(leftButton(true));
        if (frame >= 10 && frame <= 16) inject.push_back(cursor(480 + 6.0 * (frame - 9), 330));
        if (frame == 18) inject.push_back(leftButton(false));
    };
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    EXPECT_EQ(report.tool, studio::ToolKind::Carve);
    EXPECT_EQ(report.size, 5);
    EXPECT_EQ(report.steps, 1u);
    auto studio = studio::Studio::openProject(dir, core::SculptConfig{});
    const core::Mesh mesh = studio->session().wholeMesh();
    EXPECT_EQ(core::analyzeTopology(mesh).components, 1u) << "the carve left a hidden cavity";
    EXPECT_LT(core::meshVolume(mesh), 4.0 / 3 * M_PI * 40 * 40 * 40 * 0.999)
        << "the carve removed nothing from the surface";
    studio.reset();
    fs::remove_all(dir);
}

// Esc with a panel open closes the panel, not the window (found by QA: Esc in the preferences
// closed the window and lost their unsaved edits); with none open it quits as bound.
TEST(WindowUi, EscClosesAnOpenPanelFirst) {
    app::WindowOptions o = scratchWindow(40);
    app::WindowOptions::Report report;
    o.report = &report;
    size_t lastFrame = 0;
    bool helpShown = false;
    o.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        lastFrame = frame;
        if (frame == 2) inject.push_back(key(GLFW_KEY_F1, true));
        if (frame == 4) helpShown = ui.help;
        if (frame == 5) inject.push_back(key(GLFW_KEY_ESCAPE, true));
        if (frame == 10) inject.push_back(key(GLFW_KEY_ESCAPE, true));
    };
    std::ostringstream out, err;
    EXPECT_EQ(app::runWindow(o, out, err), 0) << err.str();
    EXPECT_TRUE(helpShown);
    EXPECT_FALSE(report.ui.help);
    EXPECT_EQ(lastFrame, 10u) << "the first Esc closed the window, or the second did not";
}

// A message on the status panel (after a save, an error) does not move its buttons (found by
// QA: a click aimed at "recent..." landed on "save" once a message had pushed it down).
TEST(WindowUi, AMessageDoesNotMoveThePanelsButtons) {
    app::WindowOptions o = scratchWindow(12);
    app::WindowOptions::Report report;
    o.report = &report;
    app::UiRect before{}, after{};
    o.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        if (frame == 3) before = ui.rects.at("button:recent...");
        if (frame == 4) inject.push_back(key(GLFW_KEY_F5, true));  // save: says something
    };
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    ASSERT_FALSE(report.message.empty());
    after = report.ui.rects.at("button:recent...");
    EXPECT_EQ(after.cx(), before.cx());
    EXPECT_EQ(after.cy(), before.cy()) << "the message moved the buttons";
}

// ui_scale 4 (allowed: for a 4K screen) on a small window hid the save buttons and the whole
// sculpture (found by QA). The scale is capped to what the window's height can show: the
// status panel and the palette stay inside the window, apart, and leave the middle free.
TEST(WindowUi, ALargeUiScaleIsCappedToTheWindow) {
    EXPECT_FLOAT_EQ(app::fittedUiScale(4, 2240), 4.0f);
    EXPECT_FLOAT_EQ(app::fittedUiScale(4, 640), 640.0f / 560.0f);
    EXPECT_FLOAT_EQ(app::fittedUiScale(1, 640), 1.0f);
    EXPECT_FLOAT_EQ(app::fittedUiScale(1, 100), 0.5f);
    const fs::path cfg =
        fs::temp_directory_path() / ("vsculpt-uiscale-" + std::to_string(::getpid()) + ".json");
    std::ofstream(cfg) << R"({"render": {"ui_scale": 4}})";
    app::WindowOptions o = scratchWindow(4);
    o.configPath = cfg.string();
    app::WindowOptions::Report report;
    o.report = &report;
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    const app::UiRect status = report.ui.rects.at("status"),
                      palette = report.ui.rects.at("palette");
    EXPECT_LE(status.y1, o.height);
    EXPECT_GE(palette.y0, 0);
    EXPECT_LT(status.y1, palette.y0) << "the status panel and the palette overlap";
    EXPECT_TRUE(report.ui.rects.count("button:save (F5)") || report.ui.rects.count("button:save"))
        << "the save button is not drawn";
    fs::remove(cfg);
}

TEST(WindowUi, TypingInTheExportDialogRunsNoBindingsAndErrorsStayInTheDialog) {
    const fs::path dir = std::filesystem::temp_directory_path() /
                         ("vsculpt-ui-export-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    const std::string good = (dir / "typed.stl").string();
    app::WindowOptions o = scratchWindow(30);
    app::WindowOptions::Report report;
    o.report = &report;
    app::UiRect exportButton;
    std::string proposed, fieldAfterTyping, errorAfterBadPath;
    bool dialogAfterBadPath = false;
    o.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        clickOn("button:export...", 2, frame, ui, inject, exportButton);
        if (frame == 7) proposed = ui.pathField;
        // "z", "u", "5": zoom in, undo and size 5 as keys; text in the field, replacing the
        // proposed path (selected when the dialog opens).
        const std::pair<int, char> typed[] = {
            {GLFW_KEY_Z, 'z'}, {GLFW_KEY_U, 'u'}, {GLFW_KEY_5, '5'}};
        for (size_t i = 0; i < 3; ++i) {
            if (frame == 8 + 2 * i) {
                inject.push_back(key(typed[i].first, true));
                inject.push_back(character(typed[i].second));
            }
            if (frame == 9 + 2 * i) inject.push_back(key(typed[i].first, false));
        }
        if (frame == 14) fieldAfterTyping = ui.pathField;
        // Enter: "zu5" is no export format: the error stays in the dialog.
        if (frame == 15) inject.push_back(key(GLFW_KEY_ENTER, true));
        if (frame == 16) inject.push_back(key(GLFW_KEY_ENTER, false));
        if (frame == 19) {
            errorAfterBadPath = ui.dialogError;
            dialogAfterBadPath = ui.rects.count("dialog") > 0;
        }
        // The field has the keyboard again, its text selected: a good path replaces it.
        if (frame == 20)
            for (char c : good)
                inject.push_back(character(c));
        if (frame == 22) inject.push_back(key(GLFW_KEY_ENTER, true));
        if (frame == 23) inject.push_back(key(GLFW_KEY_ENTER, false));
    };
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    // The dialog proposed a .glb in the exports folder.
    ASSERT_GT(proposed.size(), 4u);
    EXPECT_EQ(proposed.substr(proposed.size() - 4), ".glb");
    EXPECT_EQ(fieldAfterTyping, "zu5");
    // None of the typed keys ran its binding.
    EXPECT_EQ(report.zoom, 1);
    EXPECT_EQ(report.size, 7);
    EXPECT_EQ(report.steps, 0u);
    EXPECT_TRUE(dialogAfterBadPath);
    EXPECT_NE(errorAfterBadPath.find("zu5: unknown export format"), std::string::npos)
        << errorAfterBadPath;
    // The export went to the typed path, the dialog closed, the message names the file.
    EXPECT_TRUE(std::filesystem::exists(good)) << err.str();
    EXPECT_FALSE(report.ui.rects.count("dialog"));
    EXPECT_NE(report.message.find("exported " + good), std::string::npos) << report.message;
    std::filesystem::remove_all(dir);
}

TEST(WindowUi, TheImportDialogAddsAMeshAsClay) {
    const fs::path dir = std::filesystem::temp_directory_path() /
                         ("vsculpt-ui-import-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    // A 20 mm cube beside the sphere, outward-wound (OBJ: +Y up, mm).
    const std::string cube = (dir / "cube.obj").string();
    {
        std::ofstream f(cube);
        for (int i = 0; i < 8; ++i)
            f << "v " << 60 + 20 * (i & 1) << " " << -10 + 20 * ((i >> 1) & 1) << " "
              << -10 + 20 * ((i >> 2) & 1) << "\n";
        f << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    }
    const std::string missing = (dir / "missing.stl").string();
    app::WindowOptions o = scratchWindow(26);
    app::WindowOptions::Report report;
    o.report = &report;
    app::UiRect importButton;
    std::string errorAfterMissing;
    o.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        clickOn("button:import mesh...", 2, frame, ui, inject, importButton);
        auto type = [&](const std::string& text) {
            for (char c : text)
                inject.push_back(character(c));
        };
        if (frame == 8) type(missing);
        if (frame == 10) inject.push_back(key(GLFW_KEY_ENTER, true));
        if (frame == 11) inject.push_back(key(GLFW_KEY_ENTER, false));
        if (frame == 14) errorAfterMissing = ui.dialogError;
        if (frame == 15) type(cube);  // the field's text is selected again: replaced
        if (frame == 17) inject.push_back(key(GLFW_KEY_ENTER, true));
        if (frame == 18) inject.push_back(key(GLFW_KEY_ENTER, false));
    };
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    EXPECT_NE(errorAfterMissing.find("missing.stl"), std::string::npos) << errorAfterMissing;
    EXPECT_EQ(report.steps, 1u) << report.message;  // one undo step
    EXPECT_GT(report.skeletons, 100u);
    EXPECT_NE(report.message.find("imported " + cube), std::string::npos) << report.message;
    EXPECT_FALSE(report.ui.rects.count("dialog"));
    std::filesystem::remove_all(dir);
}

TEST(WindowUi, SketchWindowHasItsPanelAndHelpOnItsKey) {
    render::Image img;
    app::UiState ui;
    app::SketchWindowOptions o;
    o.noProject = true;
    o.devices = false;
    o.hidden = true;
    o.width = 1280;
    o.height = 720;
    o.frames = 6;
    o.lastFrame = &img;
    o.uiReport = &ui;
    o.injectedEvents = {{2, key(GLFW_KEY_F4, true)}, {3, key(GLFW_KEY_F4, false)}};
    std::ostringstream out, err;
    ASSERT_EQ(app::runSketchWindow(o, out, err), 0) << err.str();
    for (const char* name : {"status", "help"}) {
        ASSERT_TRUE(ui.rects.count(name)) << name;
        const Census c = census(img, ui.rects.at(name));
        EXPECT_GT(c.panel, c.total / 3) << name;
        EXPECT_GT(c.text, 150u) << name;
    }
    for (const char* b : {"button:draft", "button:clean-up", "button:inflate", "button:outline",
                          "button:next", "button:undo"})
        EXPECT_TRUE(ui.rects.count(b)) << b;
    // F4 is help, not one of the views (F1 to F3 stay the views).
    EXPECT_NE(err.str().find("0 step(s)"), std::string::npos) << err.str();
}

}  // namespace

// The headset's panel (XrPanelUi): the pen's ray is the pointer, its trigger the button.
TEST(XrPanelUi, ThePensTriggerClicksTheButtonItPointsAt) {
    render::Viewer viewer(320, 240, "vsculpt panel test", false);
    core::SculptConfig cfg;
    cfg.polygonizer.gridN = 32;
    studio::Studio studio(cfg);
    studio::Interaction interaction(studio);
    const devices::XrPanel panel;
    app::XrPanelUi panelUi(viewer, panel, cfg.render.xr, 1.0f);
    auto frame = [&] {
        return panelUi.draw(app::sculptUiViewOf(studio.session(), interaction), "pen up", 0.011);
    };
    EXPECT_TRUE(frame().empty());  // lays the panel out
    const std::map<std::string, app::UiRect> rects = panelUi.state().rects;
    // Every button of the palette, and save and export, lies on the panel's image.
    size_t buttons = 0;
    for (const auto& [name, r] : rects)
        if (name.rfind("button:", 0) == 0) {
            ++buttons;
            EXPECT_TRUE(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= panel.widthPx && r.y1 <= panel.heightPx)
                << name << " at " << r.x0 << ", " << r.y0 << " .. " << r.x1 << ", " << r.y1;
        }
    EXPECT_EQ(buttons, 4 + 2 + 4 + interaction.offeredSizes().size() + 5 + 2);

    const glm::dmat4 worldFromP = app::worldFromPanel(panel, cfg.render.xr);
    const glm::dvec2 size = app::panelSizeMm(panel);
    const glm::dvec3 centre(worldFromP[3]), right(worldFromP[0]), up(worldFromP[1]),
        face(worldFromP[2]);
    glm::dvec3 origin;
    // The pen a third of a metre in front of the panel, a little aside, pointing at `r`.
    auto pointingAt = [&](const app::UiRect& r) {
        const glm::dvec3 target = centre + (r.cx() / panel.widthPx - 0.5) * size.x * right +
                                  (0.5 - r.cy() / panel.heightPx) * size.y * up;
        origin = target + 330.0 * face + glm::dvec3(40, -30, 20);
        return glm::inverse(glm::lookAt(origin, target, glm::dvec3(0, 0, 1)));
    };
    app::XrHands h;
    const app::UiRect carve = rects.at("button:carve");
    h.worldFromPen = pointingAt(carve);
    EXPECT_TRUE(panelUi.point(h, true));
    EXPECT_EQ(panelUi.hoveredButton(), "button:carve");
    EXPECT_TRUE(panelUi.enteredButton()) << "onto a button: the frame for a haptic tick";
    ASSERT_TRUE(panelUi.pointer());
    EXPECT_NEAR(panelUi.pointer()->x, carve.cx(), 1e-6);
    EXPECT_NEAR(panelUi.pointer()->y, carve.cy(), 1e-6);
    EXPECT_TRUE(frame().empty());  // pointing clicks nothing
    h.trigger = 1;
    EXPECT_TRUE(panelUi.point(h, true));
    EXPECT_FALSE(panelUi.enteredButton()) << "still on the same button";
    EXPECT_TRUE(frame().empty());  // a button clicks when it is let go, as in the window
    h.trigger = 0.3f;              // under 80 % of the threshold: released
    EXPECT_TRUE(panelUi.point(h, true));
    std::vector<app::UiAction> clicked = frame();
    ASSERT_EQ(clicked.size(), 1u);
    EXPECT_EQ(clicked[0].name, "tool_carve");

    // A pen that is sculpting, or whose tool is in the clay, neither points nor clicks.
    h.worldFromPen = pointingAt(rects.at("button:mirror x"));
    for (float t : {0.0f, 1.0f, 0.0f}) {
        h.trigger = t;
        EXPECT_FALSE(panelUi.point(h, false));
        EXPECT_FALSE(panelUi.pointer());
        EXPECT_TRUE(frame().empty());
    }
    // Free, the same button clicks.
    for (float t : {0.0f, 1.0f, 0.0f}) {
        h.trigger = t;
        EXPECT_TRUE(panelUi.point(h, true));
        clicked = frame();
    }
    ASSERT_EQ(clicked.size(), 1u);
    EXPECT_EQ(clicked[0].name, "mirror_x");

    // Pressed on a button, then pointed away with the trigger held: the trigger stays the
    // panel's until it is let go (no stroke starts), and nothing is clicked.
    h.worldFromPen = pointingAt(rects.at("button:save"));
    h.trigger = 1;
    EXPECT_TRUE(panelUi.point(h, true));
    EXPECT_TRUE(frame().empty());
    const glm::dvec3 from = origin;
    h.worldFromPen = glm::inverse(glm::lookAt(from, from + face, glm::dvec3(0, 0, 1)));
    EXPECT_TRUE(panelUi.point(h, true));
    EXPECT_FALSE(panelUi.pointer());
    EXPECT_TRUE(frame().empty());
    h.trigger = 0;
    EXPECT_TRUE(panelUi.point(h, true));  // the frame it is let go is still the panel's
    EXPECT_TRUE(frame().empty());
    EXPECT_FALSE(panelUi.point(h, true));
}

// Found by QA: a middle drag moved the object, and the camera, framing the object's current
// pose, moved with it: nothing seemed to move. The sculpture now moves across the view with
// the drag (its leftmost pixel on the middle row follows the pointer to the right).
TEST(WindowUi, AMiddleDragMovesTheSculptureAcrossTheView) {
    auto leftEdge = [](const render::Image& img) {
        const int y = img.height / 2;
        for (int x = 0; x < img.width; ++x)
            if (!near(img.pixel(x, y),
                      {render::kBackground[0], render::kBackground[1], render::kBackground[2]}, 12))
                return x;
        return img.width;
    };
    auto run = [&](bool drag) {
        app::WindowOptions o = scratchWindow(10);
        render::Image img;
        o.lastFrame = &img;
        o.onFrame = [&](size_t frame, const app::UiState&, std::vector<InputEvent>& inject) {
            // The pointer stays right of the sculpture's left edge, so the tool drawn under it
            // never is the leftmost pixel.
            if (frame == 3) inject.push_back(cursor(600, 320));
            if (drag && frame == 4)
                inject.push_back(
                    {InputEvent::Kind::MouseButton, GLFW_MOUSE_BUTTON_MIDDLE, true, 0, 0});
            if (frame == 5) inject.push_back(cursor(700, 320));
            if (drag && frame == 6)
                inject.push_back(
                    {InputEvent::Kind::MouseButton, GLFW_MOUSE_BUTTON_MIDDLE, false, 0, 0});
        };
        std::ostringstream out, err;
        EXPECT_EQ(app::runWindow(o, out, err), 0) << err.str();
        return leftEdge(img);
    };
    const int still = run(false), moved = run(true);
    ASSERT_LT(still, 480) << "no sculpture on the middle row";
    EXPECT_GT(moved - still, 40) << "left edge " << still << " -> " << moved;
}

// Found by QA: the palette's zoom buttons centred on where the pointer last was, in empty
// space on its way to the palette: the view came out clipped or empty. They centre on the last
// surface point the tool touched.
TEST(WindowUi, ThePalettesZoomCentresOnTheLastSurfacePointNotOnEmptySpace) {
    app::WindowOptions o = scratchWindow(14);
    app::WindowOptions::Report report;
    o.report = &report;
    app::UiRect where;
    o.onFrame = [&](size_t frame, const app::UiState& ui, std::vector<InputEvent>& inject) {
        if (frame == 3) inject.push_back(cursor(480, 300));  // over the sphere
        if (frame == 5) inject.push_back(cursor(900, 80));   // empty space
        clickOn("button:zoom 3", 7, frame, ui, inject, where);
    };
    std::ostringstream out, err;
    ASSERT_EQ(app::runWindow(o, out, err), 0) << err.str();
    EXPECT_EQ(report.zoom, 3);
    // On the initial sphere's surface (radius 40 mm), not out in the air.
    EXPECT_NEAR(glm::length(report.zoomCentreMm), 40.0, 2.0)
        << report.zoomCentreMm.x << " " << report.zoomCentreMm.y << " " << report.zoomCentreMm.z;
}
