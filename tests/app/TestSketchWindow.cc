// SPDX-License-Identifier: MIT
// The sketch window under Xvfb + Mesa: the canvas and the 3D view side by side, driven by a
// playback script; the screenshot shows the sketch on paper at the left and the solid it made
// (with a surface line drawn on the model) at the right.
#include "../../app/src/KeyNames.h"
#include "vsculpt/app/SketchWindow.h"
#include "vsculpt/app/Window.h"
#include "vsculpt/render/Shot.h"
#include "vsculpt/studio/Session.h"

#include <gtest/gtest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key and button codes

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <unistd.h>

using namespace vsculpt;

namespace {

std::string circlePen(double cx, double cy, double r) {
    std::ostringstream s;
    s << "pen";
    for (int i = 0; i <= 60; ++i) {
        const double t = 2 * M_PI * i / 60;
        s << " " << cx + r * std::cos(t) << "," << cy + r * std::sin(t) << ",0.8";
    }
    return s.str() + "\n";
}

bool paper(const uint8_t* p) {
    return p[0] > 225 && p[1] > 225 && p[2] > 215;
}
bool background(const uint8_t* p) {
    return std::abs(p[0] - int(render::kBackground[0])) < 6 &&
           std::abs(p[1] - int(render::kBackground[1])) < 6 &&
           std::abs(p[2] - int(render::kBackground[2])) < 6;
}
bool reddish(const uint8_t* p) {
    return p[0] > 90 && p[0] > 2 * p[1] && p[0] > 2 * p[2];
}

TEST(SketchWindow, ScreenshotShowsTheCanvasAndTheSolid) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("vsculpt-sketchwin-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::filesystem::path script = dir / "s.vsc";
    {
        std::ofstream f(script);
        // An outline inflated at x = 60 (right of the initial sphere), a surface line across
        // the sphere, and the plain view so the window frames the ink.
        f << "page body\n"
          << circlePen(60, 0, 18) << "role outline last\nsolid inflate\n"
          << "model-line 640 480 40,240 320,240 600,240\ncanvas reset\n";
    }
    render::Image img;
    app::SketchWindowOptions o;
    o.noProject = true;  // a fresh scratch session: the tests count its steps
    o.playScript = script.string();
    o.width = 1280;
    o.height = 480;
    o.frames = 10;
    o.hidden = true;
    o.devices = false;
    o.lastFrame = &img;
    std::ostringstream out, err;
    ASSERT_EQ(app::runSketchWindow(o, out, err), 0) << err.str();
    ASSERT_EQ(img.width, 1280);
    size_t leftPaper = 0, leftInk = 0, rightBackground = 0, rightSculpture = 0, rightLine = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const uint8_t* p = img.pixel(x, y);
            if (x < 640) {
                leftPaper += paper(p);
                leftInk += !paper(p) && (reddish(p) || p[0] < 120);
            } else {
                rightBackground += background(p);
                rightSculpture += !background(p) && !reddish(p);
                rightLine += reddish(p);
            }
        }
    const size_t half = size_t(640) * img.height;
    EXPECT_GT(leftPaper, half * 8 / 10);  // mostly paper (with grid lines)
    EXPECT_GT(leftInk, 300u);             // the outline's ink
    EXPECT_GT(rightBackground, half / 3);
    EXPECT_GT(rightSculpture, half / 20);  // the sphere and the inflated solid
    EXPECT_GT(rightLine, 50u);             // the surface line drawn on the model
    EXPECT_NE(err.str().find("10 frame(s), 2 page(s), 4 step(s)"), std::string::npos) << err.str();
    std::filesystem::remove_all(dir);
}

// The headset sees the sketched solid in side-by-side stereo while the designer sketches:
// both eye images show the sculpture, shifted by the eyes' parallax.
TEST(SketchWindow, HeadsetWindowShowsTheSolidInStereo) {
    const std::filesystem::path script = std::filesystem::temp_directory_path() /
                                         ("vsculpt-headset-" + std::to_string(::getpid()) + ".vsc");
    std::ofstream(script) << "page body\n"
                          << circlePen(60, 0, 18) << "role outline last\nsolid inflate\n";
    render::Image desk, hmd;
    app::SketchWindowOptions o;
    o.noProject = true;  // a fresh scratch session: the tests count its steps
    o.playScript = script.string();
    o.frames = 6;
    o.hidden = true;
    o.devices = false;
    o.headset = true;
    o.lastFrame = &desk;
    o.lastHeadsetFrame = &hmd;
    std::ostringstream out, err;
    ASSERT_EQ(app::runSketchWindow(o, out, err), 0) << err.str();
    ASSERT_EQ(hmd.width, 1280);
    auto eye = [&](int x0) {
        size_t n = 0;
        double sx = 0;
        for (int y = 0; y < hmd.height; ++y)
            for (int x = x0; x < x0 + 640; ++x)
                if (!background(hmd.pixel(x, y))) {
                    ++n;
                    sx += x - x0;
                }
        return std::make_pair(n, n ? sx / double(n) : 0.0);
    };
    const auto [leftN, leftX] = eye(0);
    const auto [rightN, rightX] = eye(640);
    EXPECT_GT(leftN, size_t(640 * 720 / 20));
    EXPECT_GT(rightN, size_t(640 * 720 / 20));
    // Crossed parallax: the nearer sculpture sits right of centre in the left eye's image.
    EXPECT_GT(leftX - rightX, 1.0);
    EXPECT_LT(std::abs(double(leftN) - double(rightN)), 0.1 * double(leftN));
    // The desktop window still shows the canvas beside the 3D view.
    ASSERT_EQ(desk.width, 1280);
    EXPECT_TRUE(paper(desk.pixel(10, 10)));
    std::filesystem::remove(script);
}

// Every key name a config may give has a GLFW key code, a code of its own: the windows can
// bind whatever the config accepted.
TEST(SketchWindow, EveryKeyNameHasItsOwnGlfwCode) {
    std::set<int> codes;
    for (const std::string& name : core::keyNames()) {
        const int code = app::keyCode(name);
        EXPECT_GE(code, 0) << name;
        EXPECT_TRUE(codes.insert(code).second) << name;
    }
    EXPECT_EQ(app::keyCode("ESC"), -1);
    EXPECT_EQ(app::keyCode("F9"), GLFW_KEY_F9);
    EXPECT_EQ(app::keyCode("KP_ENTER"), GLFW_KEY_KP_ENTER);
}

// The sketch window's keys come from the config; a key bound twice is refused with the file
// and the binding, before any window opens.
TEST(SketchWindow, SketchKeysAreConfiguredAndCheckedForClashes) {
    const std::filesystem::path cfg = std::filesystem::temp_directory_path() /
                                      ("vsculpt-keys-" + std::to_string(::getpid()) + ".json");
    std::ofstream(cfg) << R"({"interaction": {"sketch_bindings": {"lasso": "I"}}})";
    app::SketchWindowOptions o;
    o.noProject = true;  // a fresh scratch session: the tests count its steps
    o.configPath = cfg.string();
    o.frames = 2;
    o.hidden = true;
    o.devices = false;
    std::ostringstream out, err;
    EXPECT_EQ(app::runSketchWindow(o, out, err), 2);
    EXPECT_NE(err.str().find(cfg.string() + ": interaction.sketch_bindings.lasso: key 'I' is "
                                            "already bound to solid_inflate"),
              std::string::npos)
        << err.str();
    // Moving inflate to another key resolves it.
    std::ofstream(cfg)
        << R"({"interaction": {"sketch_bindings": {"lasso": "I", "solid_inflate": "Y"}}})";
    std::ostringstream out2, err2;
    EXPECT_EQ(app::runSketchWindow(o, out2, err2), 0) << err2.str();
    std::filesystem::remove(cfg);
}

// The window's own input path, driven by events as the mouse and keyboard deliver them: a loop
// drawn with the left button on the canvas, the outline key, the inflate key; then a stroke
// across the 3D view drawn on the model, and undo by key.
TEST(SketchWindow, MouseDrawingAndKeysMakeASolid) {
    using E = render::InputEvent;
    app::SketchWindowOptions o;
    o.noProject = true;  // a fresh scratch session: the tests count its steps
    o.width = 1280;
    o.height = 720;
    o.hidden = true;
    o.devices = false;
    std::vector<std::pair<size_t, E>> ev;
    size_t f = 2;
    // A loop of radius 200 px around the canvas centre (320, 360): 50 mm at 4 px/mm, so its
    // solid reaches out of the initial sphere (radius 40; a solid inside clay adds nothing).
    auto at = [](int i) {
        const double a = 2 * M_PI * i / 64;
        return std::make_pair(320 + 200 * std::cos(a), 360 + 200 * std::sin(a));
    };
    ev.push_back({f++, E{E::Kind::Cursor, 0, false, at(0).first, at(0).second}});
    ev.push_back({f++, E{E::Kind::MouseButton, GLFW_MOUSE_BUTTON_LEFT, true, 0, 0}});
    for (int i = 1; i <= 64; ++i)
        ev.push_back({f++, E{E::Kind::Cursor, 0, false, at(i).first, at(i).second}});
    ev.push_back({f++, E{E::Kind::MouseButton, GLFW_MOUSE_BUTTON_LEFT, false, 0, 0}});
    ev.push_back({f++, E{E::Kind::Key, GLFW_KEY_O, true, 0, 0}});  // role outline
    ev.push_back({f++, E{E::Kind::Key, GLFW_KEY_I, true, 0, 0}});  // inflate
    // Over the 3D view (x >= 640): a horizontal stroke through its middle, on the model.
    ev.push_back({f++, E{E::Kind::Cursor, 0, false, 700, 360}});
    ev.push_back({f++, E{E::Kind::MouseButton, GLFW_MOUSE_BUTTON_LEFT, true, 0, 0}});
    for (int x = 720; x <= 1220; x += 20)
        ev.push_back({f++, E{E::Kind::Cursor, 0, false, double(x), 360}});
    ev.push_back({f++, E{E::Kind::MouseButton, GLFW_MOUSE_BUTTON_LEFT, false, 0, 0}});
    o.injectedEvents = ev;
    o.frames = int(f + 2);
    render::Image img;
    o.lastFrame = &img;
    std::ostringstream out, err;
    ASSERT_EQ(app::runSketchWindow(o, out, err), 0) << err.str();
    // stroke, role, solid, line on the model
    EXPECT_NE(err.str().find("1 page(s), 4 step(s)"), std::string::npos) << err.str();
    size_t line = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 640; x < img.width; ++x)
            line += reddish(img.pixel(x, y));
    EXPECT_GT(line, 50u);  // the surface line shows in the 3D view

    // The same, then the undo key twice: the line and the solid are gone again.
    o.injectedEvents.push_back({f, E{E::Kind::Key, GLFW_KEY_U, true, 0, 0}});
    o.injectedEvents.push_back({f + 1, E{E::Kind::Key, GLFW_KEY_U, true, 0, 0}});
    o.frames = int(f + 4);
    std::string said;
    o.messageReport = &said;
    std::ostringstream out2, err2;
    ASSERT_EQ(app::runSketchWindow(o, out2, err2), 0) << err2.str();
    EXPECT_NE(err2.str().find("1 page(s), 2 step(s)"), std::string::npos) << err2.str();
    EXPECT_EQ(said, "undone");  // not what the undone step said (found by QA: "inflate")
    o.messageReport = nullptr;

    // A loop of a quarter the size inflates to a solid wholly inside the sphere: no step, and
    // the window says why nothing changed.
    for (auto& [at, e] : o.injectedEvents)
        if (e.kind == E::Kind::Cursor && e.x < 640) {
            e.x = 320 + (e.x - 320) / 4;
            e.y = 360 + (e.y - 360) / 4;
        }
    std::ostringstream out3, err3;
    ASSERT_EQ(app::runSketchWindow(o, out3, err3), 0) << err3.str();
    EXPECT_NE(err3.str().find("the solid lies inside the clay, nothing added"), std::string::npos)
        << err3.str();
}

TEST(SketchWindow, BadScriptIsRefusedWithTheLine) {
    const std::filesystem::path script =
        std::filesystem::temp_directory_path() /
        ("vsculpt-badsketch-" + std::to_string(::getpid()) + ".vsc");
    std::ofstream(script) << "page body\nsolid inflate\n";
    app::SketchWindowOptions o;
    o.noProject = true;  // a fresh scratch session: the tests count its steps
    o.playScript = script.string();
    o.frames = 5;
    o.hidden = true;
    o.devices = false;
    std::ostringstream out, err;
    EXPECT_EQ(app::runSketchWindow(o, out, err), 2);
    EXPECT_NE(err.str().find(script.string() + ":2: inflate: outline missing"), std::string::npos)
        << err.str();
    std::filesystem::remove(script);
}

}  // namespace

namespace {

// A project reopened after a crash whose last journal record was cut short: both windows say
// on their panel what was recovered and that a record was lost (the terminal said it before,
// the sketch window's panel said nothing).
TEST(SketchWindow, BothWindowsSayOnThePanelWhatWasRecoveredAndLost) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("vsculpt-recovery-panel-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    {
        core::SculptConfig cfg;
        cfg.polygonizer.gridN = 32;
        auto s = studio::Session::openProject(dir, cfg);
        s->stroke({core::Vec3(0, -42, 0), core::Vec3(8, -42, 4)}, false);
        s->stroke({core::Vec3(0, 42, 0), core::Vec3(8, 42, 4)}, false);
    }  // no save: both strokes are only in the journal
    const auto journal = dir / "journal.vjl";
    std::filesystem::resize_file(journal, std::filesystem::file_size(journal) - 7);
    auto copy = [&](const char* name) {
        const auto d = dir.parent_path() / (dir.filename().string() + name);
        std::filesystem::remove_all(d);
        std::filesystem::copy(dir, d);
        std::filesystem::remove(d / "lock");
        return d;
    };
    const auto forSketch = copy("-sketch"), forWindow = copy("-window");

    app::SketchWindowOptions so;
    so.projectDir = forSketch.string();
    so.hidden = true;
    so.devices = false;
    so.frames = 2;
    std::string sketchMessage;
    so.messageReport = &sketchMessage;
    std::ostringstream out, err;
    ASSERT_EQ(app::runSketchWindow(so, out, err), 0) << err.str();
    EXPECT_NE(sketchMessage.find("recovered 1 edit(s)"), std::string::npos) << sketchMessage;
    EXPECT_NE(sketchMessage.find("warning: "), std::string::npos) << sketchMessage;
    EXPECT_NE(sketchMessage.find("record 2 is truncated"), std::string::npos) << sketchMessage;

    app::WindowOptions wo;
    wo.projectDir = forWindow.string();
    wo.hidden = true;
    wo.devices = false;
    wo.frames = 2;
    app::WindowOptions::Report report;
    wo.report = &report;
    ASSERT_EQ(app::runWindow(wo, out, err), 0) << err.str();
    EXPECT_NE(report.message.find("recovered 1 edit(s)"), std::string::npos) << report.message;
    EXPECT_NE(report.message.find("record 2 is truncated"), std::string::npos) << report.message;
    for (const auto& d : {dir, forSketch, forWindow})
        std::filesystem::remove_all(d);
}

}  // namespace
