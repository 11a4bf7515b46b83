// SPDX-License-Identifier: MIT
#include "vsculpt/app/SketchWindow.h"

#include "KeyNames.h"
#include "vsculpt/app/CliChecks.h"
#include "vsculpt/app/Interrupt.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/app/SketchInkList.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/render/ProjectStroke.h"
#include "vsculpt/render/SketchCanvas.h"
#include "vsculpt/render/UiLayer.h"
#include "vsculpt/render/Viewer.h"
#include "vsculpt/studio/SketchSolids.h"
#include "vsculpt/studio/Studio.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>

namespace vsculpt::app {

using namespace vsculpt::studio;

namespace {

// Screen millimetres per pixel of the canvas (about 100 dpi): view mm are what the designer
// sees, so ink widths look the same on any window size.
constexpr double kPxPerMm = 4.0;

// The page's view (canvas = scale * view + offset) as the renderer takes it.
render::CanvasView canvasView(const studio::CanvasView& v, glm::ivec2 px) {
    render::CanvasView r;
    r.panMm = v.offset;
    r.zoom = 1.0 / v.scale;
    r.viewportPx = px;
    r.viewportMm = glm::dvec2(px) / kPxPerMm;
    return r;
}

}  // namespace

int runSketchWindow(const SketchWindowOptions& options, std::ostream& out, std::ostream& err) {
    (void)out;  // nothing here is data: every message is a log line on `err`
    LogScope log(err, options.verbosity, "vsculpt sketch");
    SketchWindowOptions o = options;
    // A shot without a frame count is of the first frame, not of a window left open.
    if (!o.shotPath.empty() && o.frames == 0) o.frames = 1;
    if (!o.shotPath.empty()) {
        try {
            requirePngPath(o.shotPath, "--shot");
            core::ensureWritable(o.shotPath);
        } catch (const std::exception& e) {
            spdlog::error("{}", e.what());
            return 2;
        }
    }
    core::SculptConfig cfg;
    Script script;
    try {
        cfg = core::loadConfig(o.configPath.empty() ? core::defaultConfigPath()
                                                    : std::filesystem::path(o.configPath));
        if (!o.playScript.empty()) script = loadWindowScript(o.playScript);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    spdlog::debug("config: {}", cfg.source);
    std::map<int, std::string> actionOfKey;
    if (!bindingsByKey(cfg, cfg.interaction.sketchBindings, "sketch_bindings", actionOfKey))
        return 2;
    std::unique_ptr<render::Viewer> viewer;
    std::unique_ptr<render::UiLayer> uiLayer;
    try {
        viewer = std::make_unique<render::Viewer>(o.width, o.height, "vsculpt sketch", !o.hidden,
                                                  cfg.render.msaaSamples);
        if (o.ui) uiLayer = std::make_unique<render::UiLayer>(*viewer);
    } catch (const render::RenderError& e) {
        spdlog::error("no sketch window: {}", e.what());
        spdlog::info(
            "for a headless sketch session run `vsculpt play SCRIPT` with sketch "
            "commands (docs/playback.md)");
        return 1;
    }
    // The same studio, project and devices as every session (Rig.h): by default the last
    // project or a new autosave project, every step saved as it is made.
    const RigOptions ro =
        windowRigOptions(o.projectDir, o.noProject, o.devices, !o.playScript.empty());
    std::unique_ptr<Rig> rig;
    try {
        rig = std::make_unique<Rig>(cfg, ro);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    logLines(spdlog::level::info, rig->projectSummary());
    // What recovery dropped is a warning, as `play` says it (found by QA: info lines).
    logLines(spdlog::level::warn, rig->session().recoveryWarning());
    render::SketchCanvas canvas;
    // The headset sees the sculpture in stereo while the designer sketches on the desktop.
    std::unique_ptr<render::Viewer> headset;
    if (o.headset) {
        try {
            headset = std::make_unique<render::Viewer>(1280, 720, "vsculpt sketch — headset",
                                                       !o.hidden, cfg.render.msaaSamples);
            if (cfg.render.fullscreenMonitor >= 0 &&
                !headset->goFullscreen(cfg.render.fullscreenMonitor))
                spdlog::warn(
                    "monitor {} not found (render.fullscreen_monitor); the headset view "
                    "stays a window",
                    cfg.render.fullscreenMonitor);
        } catch (const render::RenderError& e) {
            spdlog::error("no headset window: {}", e.what());
            return 1;
        }
        viewer->makeCurrent();
    }

    const auto start = std::chrono::steady_clock::now();
    auto now = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    double cursorX = 0, cursorY = 0, lastX = 0, lastY = 0;
    bool drawing = false, panning = false, rotating = false, lassoMode = false;
    bool showHistory = false;       // undone and deleted strokes drawn faintly, to reuse (F-04)
    std::vector<glm::dvec2> lasso;  // canvas mm
    std::vector<glm::dvec2> modelStroke;  // pixels of the 3D view
    bool modelDrawing = false;
    bool tabletTouching = false;
    // Recovery is reported on the panel too, as in the sculpting window.
    std::string message = rig->recoveryMessage();
    if (message.empty()) message = "TAB mode, I inflate, U undo";
    size_t commandIndex = 0, frame = 0;
    bool running = true;
    core::Aabb frameBox = rig->session().published()->bounds;
    // The panel spans the whole window (canvas and 3D view), drawn over both.
    if (uiLayer) uiLayer->setScale(fittedUiScale(cfg.render.uiScale, viewer->height()));
    UiState uiState;
    glm::dvec2 uiPointer(-1.0);
    bool uiOwnsButton[3] = {};
    double frameMs = 0;
    auto overUi = [&] {
        return uiLayer && (uiLayer->wantsMouse() || uiState.covers(uiPointer.x, uiPointer.y));
    };

    InterruptScope interrupts;
    int code = 0;
    while (running) {
        // Ctrl-C, SIGTERM (a logout, a session manager) or SIGHUP: closed as the close box
        // would, so the work is snapshotted and the next open has nothing to recover.
        if (const int sig = interruptSignal()) {
            spdlog::info("closing: {}", ::strsignal(sig));
            break;
        }
        // A resized window keeps its UI inside it (fonts rebuilt only when the scale changes).
        if (uiLayer) uiLayer->setScale(fittedUiScale(cfg.render.uiScale, viewer->height()));
        const auto t0 = std::chrono::steady_clock::now();
        // Save as and new project replace the studio: fetched anew every frame.
        Studio& studio = rig->studio();
        const Session* session = &rig->session();
        DeviceInput* devices = rig->devices();
        bool switched = false;
        viewer->makeCurrent();
        const int W = viewer->width(), H = viewer->height();
        const int canvasW = W / 2;
        const glm::ivec2 canvasPx(canvasW, H);
        // Pages may be added (reallocated) by any command: always fetch the current one.
        auto page = [&]() -> studio::SketchPage& { return studio.page(); };
        // A page first shown with the plain view gets the canvas origin in the middle, where
        // the object's origin is in the 3D view.
        // With ink on it, the page is framed instead (HOME does the same later).
        auto centre = [&](studio::SketchPage& p) {
            const glm::dvec2 viewSize = glm::dvec2(canvasPx) / kPxPerMm;
            glm::dvec2 lo(1e300), hi(-1e300);
            for (const studio::DrawItem& d : p.drawList())
                for (const glm::dvec2& q : d.points) {
                    lo = glm::min(lo, q);
                    hi = glm::max(hi, q);
                }
            studio::CanvasView v;
            if (lo.x <= hi.x) {
                lo = glm::min(lo, glm::dvec2(0.0));  // keep the origin in view too
                hi = glm::max(hi, glm::dvec2(0.0));
                const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1.0));
                v.scale = std::max(size.x / viewSize.x, size.y / viewSize.y) / 0.8;
                v.offset = 0.5 * (lo + hi) - v.scale * 0.5 * viewSize;
            } else {
                v.offset = -0.5 * viewSize;
            }
            p.setView(v);
        };
        if (page().view() == studio::CanvasView{} && !page().penIsDown()) centre(page());
        // Window pixels (top-left origin) of the canvas -> view mm (lower-left origin, y up).
        auto viewMm = [&](double x, double y) {
            return glm::dvec2(x / kPxPerMm, (H - y) / kPxPerMm);
        };
        auto penSample = [&](double x, double y, std::optional<double> pressure) {
            studio::PenSample s;
            s.view = viewMm(x, y);
            s.pressure = pressure;
            s.time = now();
            return s;
        };
        auto act = [&](const std::function<void()>& f) {
            try {
                f();
            } catch (const std::exception& e) {
                message = e.what();
                spdlog::warn("{}", e.what());
            }
        };
        auto sketchCommand = [&](SketchCommand::Verb verb, const std::string& name = "") {
            ScriptCommand c;
            c.kind = ScriptCommand::Kind::Sketch;
            c.sketch.verb = verb;
            c.sketch.name = name;
            act([&] {
                const size_t steps = studio.stepCount();
                studio.apply(c);
                message = name.empty() ? "done" : name;
                if (verb == SketchCommand::Verb::Solid && studio.stepCount() == steps) {
                    // Clay where there is clay already: no step, but say why nothing changed.
                    message = name + ": the solid lies inside the clay, nothing added";
                    spdlog::info("{}", message);
                }
            });
        };

        // A script line refused stops the script; the work before it is closed as usual.
        if (const int failed = playNextScriptCommand(studio, script, commandIndex)) {
            code = failed;
            break;
        }
        for (const auto& [at, ev] : o.injectedEvents)
            if (at == frame) viewer->injectEvent(ev);
        // One action, from a key binding or the panel (the same names): applied the same way.
        auto applyAction = [&](const std::string& action) {
            using V = SketchCommand::Verb;
            if (action == "help") {
                uiState.help = !uiState.help;
            } else if (action == "quit") {
                running = false;
            } else if (Rig::handles(action)) {
                act([&] {
                    message = rig->projectAction(action);
                    spdlog::info("{}", message);
                    switched = action == "save_as" || action == "new_project";
                });
                if (switched) {
                    drawing = modelDrawing = tabletTouching = false;
                    lasso.clear();
                }
            } else if (action == "recenter") {
                // The head-tracked view looks toward what the 3D view frames.
                act([&] {
                    if (!devices) throw std::runtime_error("recenter: the devices are not open");
                    message = devices->recenterHeadOn(frameBox, session->objectPose().matrix());
                    spdlog::info("{}", message);
                });
            } else if (action == "undo") {
                // The status line says what happened now, not what the undone step said
                // (found by QA: "inflate" stayed after U).
                act([&] {
                    const size_t steps = studio.stepCount();
                    studio.undo();
                    message = studio.stepCount() < steps ? "undone" : "nothing to undo";
                });
            } else if (action == "redo") {
                act([&] {
                    const size_t steps = studio.stepCount();
                    studio.redo();
                    message = studio.stepCount() > steps ? "redone" : "nothing to redo";
                });
            } else if (action == "mode") {
                page().setMode(page().mode() == studio::SketchMode::Draft
                                   ? studio::SketchMode::Cleanup
                                   : studio::SketchMode::Draft);
            } else if (action == "kind_line" || action == "kind_curve") {
                page().setKind(action == "kind_line" ? sketch::StrokeKind::Line
                                                     : sketch::StrokeKind::Curve);
            } else if (action == "end_group") {
                act([&] { studio.sketchStep([](auto& p) { p.endGroup(); }); });
            } else if (action.rfind("role_", 0) == 0) {
                // role_surface_x -> "surface-x", the script's role names.
                std::string role = action.substr(5);
                std::replace(role.begin(), role.end(), '_', '-');
                ScriptCommand c;
                c.kind = ScriptCommand::Kind::Sketch;
                c.sketch.verb = V::Role;
                c.sketch.name = role;
                c.sketch.target = SketchCommand::Target::Last;
                act([&] {
                    studio.apply(c);
                    message = "role " + role;
                });
            } else if (action.rfind("solid_", 0) == 0) {
                std::string construction = action.substr(6);
                std::replace(construction.begin(), construction.end(), '_', '-');
                sketchCommand(V::Solid, construction);
            } else if (action == "lasso") {
                lassoMode = !lassoMode;
                message = lassoMode ? "lasso select" : "draw";
            } else if (action == "delete") {
                act([&] { studio.sketchStep([](auto& p) { p.deleteSelection(); }); });
            } else if (action.rfind("move_", 0) == 0) {
                // One view millimetre per press, whatever the zoom.
                const double step = page().view().scale;
                const glm::dvec2 d = action == "move_left"    ? glm::dvec2(-step, 0)
                                     : action == "move_right" ? glm::dvec2(step, 0)
                                     : action == "move_up"    ? glm::dvec2(0, step)
                                                              : glm::dvec2(0, -step);
                act([&] { studio.sketchStep([&](auto& p) { p.moveSelection(d); }); });
            } else if (action == "scale_down" || action == "scale_up") {
                const double f = action == "scale_down" ? 1 / 1.1 : 1.1;
                act([&] { studio.sketchStep([&](auto& p) { p.scaleSelection(f); }); });
            } else if (action == "page_previous" || action == "page_next") {
                const size_t n = studio.document().pageCount();
                const size_t i = studio.document().currentIndex();
                studio.document().selectPage(action == "page_next" ? (i + 1) % n : (i + n - 1) % n);
            } else if (action == "page_new") {
                ScriptCommand c;
                c.kind = ScriptCommand::Kind::Sketch;
                c.sketch.verb = V::Page;
                c.sketch.name = "Sketch " + std::to_string(studio.document().pageCount() + 1);
                act([&] { studio.apply(c); });
            } else if (action.rfind("view_", 0) == 0) {
                act([&] {
                    studio.setPlane(studio.document().currentIndex(),
                                    action == "view_front"  ? SketchPlane::Front
                                    : action == "view_side" ? SketchPlane::Side
                                                            : SketchPlane::Top);
                });
            } else if (action == "frame") {
                centre(page());
            } else if (action == "history") {
                showHistory = !showHistory;
                message =
                    showHistory ? "history shown (reuse with the reuse key)" : "history hidden";
            } else if (action == "reuse") {
                act([&] {
                    const auto id = nearestHistoryStroke(
                        page(), page().view().canvasFromView(viewMm(cursorX, cursorY)),
                        5 * page().view().scale);
                    if (!id)
                        throw std::invalid_argument(
                            "no undone or deleted stroke under the pointer");
                    studio.sketchStep([&](auto& p) { p.reuse(*id); });
                    message = "stroke " + std::to_string(*id) + " reused";
                });
            }
        };
        for (const render::InputEvent& ev : viewer->pollEvents()) {
            using K = render::InputEvent::Kind;
            const bool overCanvas = cursorX < canvasW;
            if (uiLayer) uiLayer->feed(ev);
            if (ev.kind == K::Close) running = false;
            if (switched) break;
            // Keys typed into a text field (or with a dialog open) are the UI's only.
            if (ev.kind == K::Key && ev.pressed && !(uiLayer && uiLayer->wantsKeyboard())) {
                auto bound = actionOfKey.find(ev.code);
                if (bound != actionOfKey.end() &&
                    !(bound->second == "quit" && closeOpenPanel(uiState)))
                    applyAction(bound->second);
            }
            if (ev.kind == K::MouseButton && ev.code >= 0 && ev.code < 3) {
                // A press on the panel is the panel's (and so is its release): it never draws.
                if (ev.pressed && overUi()) {
                    uiOwnsButton[ev.code] = true;
                    continue;
                }
                if (!ev.pressed && uiOwnsButton[ev.code]) {
                    uiOwnsButton[ev.code] = false;
                    continue;
                }
            }
            if (ev.kind == K::MouseButton) {
                if (ev.code == GLFW_MOUSE_BUTTON_LEFT && overCanvas && !lassoMode) {
                    if (ev.pressed && !page().penIsDown()) {
                        act([&] { page().penDown(penSample(cursorX, cursorY, std::nullopt)); });
                        drawing = page().penIsDown();
                    } else if (!ev.pressed && drawing) {
                        drawing = false;
                        act([&] { studio.sketchStep([](auto& p) { p.penUp(); }); });
                    }
                } else if (ev.code == GLFW_MOUSE_BUTTON_LEFT && overCanvas && lassoMode) {
                    if (ev.pressed) {
                        lasso = {page().view().canvasFromView(viewMm(cursorX, cursorY))};
                    } else if (lasso.size() >= 3) {
                        act([&] {
                            message =
                                std::to_string(page().selectLasso(lasso).size()) + " selected";
                        });
                        lasso.clear();
                    } else {
                        lasso.clear();
                    }
                } else if (ev.code == GLFW_MOUSE_BUTTON_LEFT && !overCanvas) {
                    // Drawing on the model: pixels relative to the 3D view's area.
                    modelDrawing = ev.pressed;
                    if (ev.pressed) {
                        modelStroke = {glm::dvec2(cursorX - canvasW, cursorY)};
                    } else if (!modelStroke.empty()) {
                        act([&] {
                            const auto camera = render::ProjectionCamera::fromEye(
                                viewer->monoEye(), session->objectPose().matrix(),
                                glm::ivec2(W - canvasW, H));
                            const size_t n = studio.addSurfaceLines(
                                projectOnModel(*session, modelStroke, camera));
                            message = std::to_string(n) + " surface line(s)";
                        });
                        modelStroke.clear();
                    }
                }
                if (ev.code == GLFW_MOUSE_BUTTON_RIGHT) {
                    panning = ev.pressed && overCanvas;
                    rotating = ev.pressed && !overCanvas;
                }
            }
            if (ev.kind == K::Cursor) {
                lastX = cursorX;
                lastY = cursorY;
                cursorX = ev.x;
                cursorY = ev.y;
                if (uiLayer) {
                    uiPointer = viewer->windowToFramebuffer(cursorX, cursorY);
                    uiLayer->setPointer(uiPointer.x, uiPointer.y);
                }
                if (drawing)
                    act([&] { page().penMove(penSample(cursorX, cursorY, std::nullopt)); });
                if (!lasso.empty())
                    lasso.push_back(page().view().canvasFromView(viewMm(cursorX, cursorY)));
                if (modelDrawing) modelStroke.emplace_back(cursorX - canvasW, cursorY);
                if (panning)
                    page().pan(
                        glm::dvec2((cursorX - lastX) / kPxPerMm, -(cursorY - lastY) / kPxPerMm));
                if (rotating) {
                    core::RigidTransform pose = session->objectPose();
                    const double yaw = (cursorX - lastX) * cfg.interaction.rotateRadPerPixel;
                    const double pitch = (cursorY - lastY) * cfg.interaction.rotateRadPerPixel;
                    pose.rotation =
                        glm::normalize(glm::angleAxis(pitch, core::Vec3(1, 0, 0)) *
                                       glm::angleAxis(yaw, core::Vec3(0, 0, 1)) * pose.rotation);
                    studio.setObjectPose(pose);
                }
                if (overCanvas && !drawing) page().hover(viewMm(cursorX, cursorY));
            }
            if (ev.kind == K::Scroll && overCanvas && !overUi())
                act([&] { page().zoomAbout(viewMm(cursorX, cursorY), std::pow(1.1, ev.y)); });
        }
        if (switched) continue;
        // The panel: built and drawn into its texture now, composited over the window after
        // the canvas; what it asks for is applied like keys.
        render::UiImage uiImage;
        if (uiLayer) {
            uiLayer->beginFrame(W, H, std::max(1e-3, frameMs / 1000));
            SketchUiView view;
            view.page = page().name();
            view.plane = sketch::sketchPlaneName(studio.plane(studio.document().currentIndex()));
            view.pageIndex = studio.document().currentIndex();
            view.pageCount = studio.document().pageCount();
            view.cleanup = page().mode() == studio::SketchMode::Cleanup;
            view.curves = page().kind() == sketch::StrokeKind::Curve;
            view.lasso = lassoMode;
            view.strokes = page().liveStrokeIds().size();
            view.curvesDone = page().cleanCurves().size();
            view.steps = studio.stepCount();
            view.frameMs = frameMs;
            view.project = session->projectDir() ? session->projectDir()->filename().string()
                                                 : "no project (scratch)";
            view.message = message;
            view.bindings = &cfg.interaction.sketchBindings;
            uiState.importing = rig->studio().importStatus().value_or("");
            const std::vector<UiAction> actions = sketchUi(uiState, view, cfg, W, H);
            uiImage = uiLayer->endFrame();
            for (const UiAction& a : actions) {
                if (switched) break;
                if (a.name == "preferences_changed") {
                    uiLayer->setScale(fittedUiScale(cfg.render.uiScale, viewer->height()));
                } else if (applySharedUiAction(a, *rig, uiState, cfg, message, switched)) {
                    // Opening a dialog or the recent list says nothing new (found by QA: the
                    // last "saved DIR" was logged again).
                    if (!message.empty() && !opensPanel(a.name)) spdlog::info("{}", message);
                } else {
                    applyAction(a.name);
                }
            }
            if (switched) {
                drawing = modelDrawing = tabletTouching = false;
                lasso.clear();
                continue;
            }
        }
        if (auto exported = rig->pollBackgroundWork()) message = *exported;
        if (devices) {
            rig->pumpDevices();
            // The whole tablet maps onto the canvas; its pen draws with pressure.
            for (const devices::PenSample& s : devices->takePenSamples()) {
                if (!s.hasPosition && s.inProximity) continue;
                const double x = s.positionNormalized.x * canvasW;
                const double y = s.positionNormalized.y * H;
                studio::PenSample ps = penSample(x, y, s.pressure);
                if (s.hasTilt)
                    ps.tiltDeg =
                        glm::clamp(glm::degrees(s.tiltRad), glm::dvec2(-90), glm::dvec2(90));
                if (s.touching && !tabletTouching) act([&] { page().penDown(ps); });
                if (s.touching && tabletTouching) act([&] { page().penMove(ps); });
                if (!s.touching && tabletTouching)
                    act([&] { studio.sketchStep([&](auto& p) { p.penUp(ps); }); });
                tabletTouching = s.touching && page().penIsDown();
                if (s.inProximity && !s.touching) act([&] { page().hover(ps.view); });
                if (!s.inProximity) page().leaveProximity();
            }
        }
        // The clean-up pause trigger runs on the wall clock.
        if (!page().penIsDown())
            act([&] { studio.sketchStep([&](auto& p) { p.advanceTime(now()); }); });

        // The 3D view on the right, the canvas on the left.
        // The mesher's last published set: the frame never waits for a rebuild.
        const std::shared_ptr<const core::MeshChunks> shown = session->published();
        viewer->syncChunks(*shown);
        if (frame % 15 == 0 || frameBox.empty()) {
            const core::Aabb b = shown->bounds;
            if (!b.empty()) frameBox = b;
        }
        viewer->setViewArea(canvasW, W - canvasW);
        viewer->setSurfaceLines(studio.surfaceLines());
        const glm::dmat4 worldFromObject = session->objectPose().matrix();
        render::ToolDraw tool;
        tool.visible = false;
        render::StereoDisplay display;
        display.ipdMm = 0;
        viewer->draw(worldFromObject, frameBox, tool, render::StereoMode::Mono, display);
        render::CanvasOverlay overlay;
        if (const auto hover = page().hoverCanvas()) {
            overlay.penMm = *hover;
            overlay.penWidthMm = page().params().ink.maxWidth * page().view().scale;
            overlay.penTouching = page().penIsDown();
        }
        overlay.lassoMm = lasso;
        try {
            std::vector<render::InkStroke> ink = inkOf(page());
            if (showHistory) {
                std::vector<render::InkStroke> past = historyInk(page());
                ink.insert(ink.begin(), past.begin(), past.end());  // under today's ink
            }
            canvas.draw(ink, canvasView(page().view(), canvasPx), {0, 0}, overlay);
        } catch (const std::exception& e) {
            spdlog::error("{}", e.what());
            code = 1;
            break;
        }
        if (uiLayer) viewer->overlayUi(uiImage);
        ++frame;
        const bool last = o.frames > 0 && frame >= size_t(o.frames);
        if (last && !keepLastFrame(*viewer, o.shotPath, o.lastFrame)) {
            code = 1;
            break;
        }
        viewer->swap();
        if (headset) {
            headset->makeCurrent();
            headset->syncChunks(*shown);
            headset->setSurfaceLines(studio.surfaceLines());
            headset->setTrackedHead(devices ? devices->worldFromHead(devices::monotonicNowNs())
                                            : std::optional<glm::dmat4>());
            render::StereoDisplay eyes;
            eyes.ipdMm = cfg.render.ipdMm;
            eyes.verticalFovDeg = cfg.render.verticalFovDeg;
            const render::LensCorrection lens{cfg.render.lensK1, cfg.render.lensK2,
                                              cfg.render.lensRedScale, cfg.render.lensBlueScale};
            headset->draw(worldFromObject, frameBox, tool, render::StereoMode::SideBySide, eyes,
                          lens);
            if (last && o.lastHeadsetFrame) *o.lastHeadsetFrame = headset->readFrame();
            headset->swap();
            viewer->makeCurrent();
        }
        size_t strokes = page().liveStrokeIds().size();
        char title[320];
        std::snprintf(title, sizeof title,
                      "vsculpt sketch — page '%s' (%s view) · %s%s · %zu stroke(s), %zu "
                      "curve(s) · %zu step(s) · %s",
                      page().name().c_str(),
                      sketch::sketchPlaneName(studio.plane(studio.document().currentIndex())),
                      page().mode() == studio::SketchMode::Draft ? "draft" : "clean-up",
                      page().mode() == studio::SketchMode::Draft
                          ? ""
                          : (page().kind() == sketch::StrokeKind::Line ? " lines" : " curves"),
                      strokes, page().cleanCurves().size(), studio.stepCount(), message.c_str());
        viewer->setTitle(title);
        frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                      .count();
        if (last) running = false;
    }
    if (o.uiReport) *o.uiReport = uiState;
    if (o.messageReport) *o.messageReport = message;
    // Closing ends the stroke in flight (journaled like any other) and snapshots the project.
    if (code == 0) warnIfScriptUnfinished(script, commandIndex);
    rig->close();
    spdlog::info("{} frame(s), {} page(s), {} step(s), {} skeletons", frame,
                 rig->studio().document().pageCount(), rig->studio().stepCount(),
                 rig->session().sculpture().counts().total());
    return code;
}

}  // namespace vsculpt::app
