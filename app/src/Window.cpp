// SPDX-License-Identifier: MIT
#include "vsculpt/app/Window.h"

#include "KeyNames.h"
#include "vsculpt/app/CliChecks.h"
#include "vsculpt/app/Interrupt.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/app/SculptAction.h"
#include "vsculpt/app/XrWindow.h"
#include "vsculpt/core/DurationHistogram.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/render/UiLayer.h"
#include "vsculpt/render/Viewer.h"
#include "vsculpt/studio/PickTool.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key and button codes only
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <ostream>

namespace vsculpt::app {

using namespace vsculpt::studio;

using namespace vsculpt::core;

int runWindow(const WindowOptions& options, std::ostream& out, std::ostream& err) {
    (void)out;  // nothing here is data: every message is a log line on `err`
    LogScope log(err, options.verbosity, "vsculpt");
    WindowOptions o = options;
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
    SculptConfig cfg;
    render::StereoMode mode;
    Script script;
    try {
        cfg = loadConfig(o.configPath.empty() ? defaultConfigPath()
                                              : std::filesystem::path(o.configPath));
        mode = render::parseStereoMode(o.stereo.empty() ? cfg.render.stereo : o.stereo);
        if (!o.playScript.empty()) script = loadWindowScript(o.playScript);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    spdlog::debug("config: {}", cfg.source);
    if (o.xr.value_or(cfg.render.output == "xr")) return runXr(o, cfg, std::move(script), out, err);
    if (!o.recordPath.empty()) {
        // Not silently ignored (found by QA): the user expects a file that would never come.
        spdlog::error(
            "--record {}: records a headset session's controllers; it needs --xr (or "
            "render.output \"xr\" in the config). `vsculpt record --out FILE` records "
            "trackers, 3D mice and tablets",
            o.recordPath);
        return 2;
    }
    std::map<int, std::string> actionOfKey;
    if (!bindingsByKey(cfg, cfg.interaction.bindings, "bindings", actionOfKey)) return 2;
    std::unique_ptr<render::Viewer> viewer;
    std::unique_ptr<render::UiLayer> uiLayer;
    try {
        viewer = std::make_unique<render::Viewer>(o.width, o.height, "vsculpt", !o.hidden,
                                                  cfg.render.msaaSamples);
        // Asked for explicitly and not given (auto, 0, says nothing).
        if (const int got = viewer->windowSamples(); got < cfg.render.msaaSamples)
            spdlog::info("render.msaa_samples {}: this display offers {}", cfg.render.msaaSamples,
                         got);
        if (o.ui) uiLayer = std::make_unique<render::UiLayer>(*viewer);
    } catch (const render::RenderError& e) {
        spdlog::warn("no sculpting window: {}", e.what());
        spdlog::info("for a headless session run `vsculpt play SCRIPT` (docs/playback.md)");
        return 1;
    }

    // The studio, its project and the devices, built as for every session (Rig.h). By
    // default the window continues the last project, or starts a new autosave project, so
    // work sculpted here is journaled as it is made and survives a crash.
    const RigOptions ro =
        windowRigOptions(o.projectDir, o.noProject, o.devices, !o.playScript.empty());
    std::unique_ptr<Rig> rig;
    try {
        rig = std::make_unique<Rig>(cfg, ro);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    // Recovery is reported where the user looks: on the terminal and in the title bar.
    logLines(spdlog::level::info, rig->projectSummary());
    // What recovery dropped is a warning, as `play` says it (found by QA: info lines).
    logLines(spdlog::level::warn, rig->session().recoveryWarning());
    std::string message = rig->recoveryMessage();
    // The rig's studio can change (save as, new project): these always fetch the current one.
    auto studioNow = [&]() -> Studio& { return rig->studio(); };
    auto sessionNow = [&]() -> const Session& { return rig->session(); };
    auto worldFromObjectMatrix = [&] { return sessionNow().objectPose().matrix(); };
    glm::dmat4 worldFromObject = worldFromObjectMatrix();
    double cursorX = o.width / 2.0, cursorY = o.height / 2.0, lastX = cursorX, lastY = cursorY;
    bool rotating = false, moving = false;
    // How far the scroll wheel pushed the tool along the pointer ray, in tool diameters: the
    // same share of any size, so a depth set for size 7 does not bury a size-5 tool out of
    // sight (found by QA: a hidden cavity); from a diameter out to one in (the tool's top at
    // the surface).
    double depthInDiameters = 0;
    size_t commandIndex = 0, frame = 0;
    double frameMs = 0;
    // For the closing summary: frame wall times and how far the mesh trailed each edit, in
    // fixed memory however long the session runs.
    core::DurationHistogram frameTimes, meshLag;
    bool running = true;
    Vec3 toolWorld(0.0);
    // The preferences panel shows and edits the mode in use (--stereo included).
    cfg.render.stereo = mode == render::StereoMode::SideBySide ? "sbs"
                        : mode == render::StereoMode::Anaglyph ? "anaglyph"
                                                               : "mono";
    render::StereoDisplay display;
    display.ipdMm = cfg.render.ipdMm;
    display.verticalFovDeg = cfg.render.verticalFovDeg;
    if (uiLayer) uiLayer->setScale(fittedUiScale(cfg.render.uiScale, viewer->height()));
    UiState uiState;
    glm::dvec2 uiPointer(-1.0);  // the pointer on the UI texture
    bool uiOwnsButton[3] = {};   // a press the UI took: its release is the UI's too
    double uiMsTotal = 0;
    const render::LensCorrection lens{cfg.render.lensK1, cfg.render.lensK2, cfg.render.lensRedScale,
                                      cfg.render.lensBlueScale};
    if (cfg.render.fullscreenMonitor >= 0 && !viewer->goFullscreen(cfg.render.fullscreenMonitor))
        spdlog::warn("monitor {} not found (render.fullscreen_monitor); staying in a window",
                     cfg.render.fullscreenMonitor);
    // What the camera frames: the mesh on show, refreshed now and then (and on zoom).
    Aabb frameBox = sessionNow().published()->bounds;
    // The region of the mesh framed last: the camera reframes when the mesh on show moves to
    // another region (after a zoom change, once the mesher has published the new region's
    // preview), not when the zoom is asked for (the old mesh is still on show then).
    core::GridRegion framedRegion = sessionNow().published()->region;
    // Where the object stood when the camera last framed it: moving the object (the middle
    // drag, a 3D mouse) moves it in the view, where framing its current pose took the camera
    // along and nothing seemed to move (found by QA). Rotations still turn it in place.
    Vec3 framedTranslation = sessionNow().objectPose().translation;

    // The region to zoom into: the surface point under the pointer, picked with Embree on the
    // mesh on show (built only when a zoom is asked for); the tool centre when nothing is hit.
    auto zoomTargetAt = [&](double x, double y, const Vec3& fallback) {
        Vec3 origin, dir;
        viewer->pixelRay(x, y, origin, dir);
        const glm::dmat4 objectFromWorld = glm::inverse(worldFromObject);
        const ToolPick pick = pickTool(sessionNow(), Vec3(objectFromWorld * glm::dvec4(origin, 1)),
                                       glm::normalize(Vec3(objectFromWorld * glm::dvec4(dir, 0))),
                                       0, 0, Vec3(0, 0, -1));
        return pick.surfaceHit ? *pick.surfaceHit : fallback;
    };
    auto zoomTarget = [&](const Vec3& fallback) {
        return zoomTargetAt(cursorX, cursorY, fallback);
    };
    // The last surface point the tool touched outside the UI: the palette's zoom centre. Only
    // a surface point: the pointer crosses empty space on its way to the palette, and a zoom
    // centred there showed a clipped or empty view (found by QA). Until the tool touches the
    // clay, the surface point at the middle of the view.
    std::optional<Vec3> lastSculptPoint;
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
        Studio& studio = studioNow();
        const Session& session = sessionNow();
        Interaction& ui = rig->interaction();
        const auto t0 = std::chrono::steady_clock::now();
        // Scripted commands first (one per frame), then live input.
        // A script line refused stops the script; the work before it is closed as usual.
        if (const int failed = playNextScriptCommand(studio, script, commandIndex)) {
            code = failed;
            break;
        }
        const ToolLevel& level = session.sculpture().levels().level(session.size());
        bool switched = false;
        // One action, from a key binding or the UI (the same names): applied the same way.
        auto doAction = [&](const std::string& a) {
            const Vec3 toolObject = glm::inverse(worldFromObject) * glm::dvec4(toolWorld, 1);
            try {
                // The palette's actions, as the headset's panel applies them.
                if (!lastSculptPoint)
                    lastSculptPoint = zoomTargetAt(0.5 * viewer->width(), 0.5 * viewer->height(),
                                                   0.5 * (frameBox.min + frameBox.max));
                if (applySculptAction(a, studio, ui, *lastSculptPoint)) return;
                if (a == "quit")
                    running = false;
                else if (a == "help")
                    uiState.help = !uiState.help;
                else if (a == "step")
                    ui.step(session.tool() == ToolKind::Select ? zoomTarget(toolObject)
                                                               : toolObject);
                else if (a == "zoom_in")
                    ui.jumpToZoom(std::min(5, session.zoom() + 1), zoomTarget(toolObject));
                else if (a == "zoom_out")
                    ui.jumpToZoom(std::max(1, session.zoom() - 1), toolObject);
                else if (a == "recenter") {
                    // The head-tracked view looks toward what the camera frames.
                    if (!rig->devices())
                        throw std::runtime_error("recenter: the devices are not open");
                    message = rig->devices()->recenterHeadOn(frameBox, worldFromObject);
                    spdlog::info("{}", message);
                } else if (Rig::handles(a)) {
                    message = rig->projectAction(a);
                    spdlog::info("{}", message);
                    // Save as and new project replace the studio: this frame's
                    // references are gone, start the next frame with the new one.
                    switched = a == "save_as" || a == "new_project";
                }
            } catch (const std::logic_error&) {
                throw;  // a broken invariant: not a refused command
            } catch (const std::exception& e) {
                message = e.what();
                spdlog::warn("{}", e.what());
            }
        };
        std::vector<render::InputEvent> injected;
        if (o.onFrame) o.onFrame(frame, uiState, injected);
        for (const render::InputEvent& ev : injected)
            viewer->injectEvent(ev);
        for (const render::InputEvent& ev : viewer->pollEvents()) {
            if (switched) break;
            using K = render::InputEvent::Kind;
            if (uiLayer) uiLayer->feed(ev);
            if (ev.kind == K::Close) running = false;
            // Keys typed into a text field (or with a dialog open) are the UI's only.
            if (ev.kind == K::Key && ev.pressed && actionOfKey.count(ev.code) &&
                !(uiLayer && uiLayer->wantsKeyboard()) &&
                !(actionOfKey[ev.code] == "quit" && closeOpenPanel(uiState)))
                doAction(actionOfKey[ev.code]);
            if (ev.kind == K::MouseButton) {
                // A press on the UI is the UI's (and so is its release): it never sculpts.
                const int b = ev.code;
                if (b >= 0 && b < 3) {
                    if (ev.pressed && overUi()) {
                        uiOwnsButton[b] = true;
                        continue;
                    }
                    if (!ev.pressed && uiOwnsButton[b]) {
                        uiOwnsButton[b] = false;
                        continue;
                    }
                }
                if (ev.code == GLFW_MOUSE_BUTTON_LEFT) ui.setEngaged(ev.pressed);
                if (ev.code == GLFW_MOUSE_BUTTON_RIGHT) rotating = ev.pressed;
                if (ev.code == GLFW_MOUSE_BUTTON_MIDDLE) moving = ev.pressed;
            }
            if (ev.kind == K::Cursor) {
                lastX = cursorX;
                lastY = cursorY;
                cursorX = ev.x;
                cursorY = ev.y;
                if (uiLayer) {
                    uiPointer =
                        viewer->pointerOnUi(cursorX, cursorY, mode, viewer->eyeImageSize(mode));
                    uiLayer->setPointer(uiPointer.x, uiPointer.y);
                }
                if (rotating || moving) {
                    RigidTransform pose = session.objectPose();
                    if (rotating) {
                        // Turn about world axes through the object's centre: horizontal drags
                        // about the vertical (z), vertical drags about x.
                        const double yaw = (cursorX - lastX) * cfg.interaction.rotateRadPerPixel;
                        const double pitch = (cursorY - lastY) * cfg.interaction.rotateRadPerPixel;
                        pose.rotation =
                            glm::normalize(glm::angleAxis(pitch, Vec3(1, 0, 0)) *
                                           glm::angleAxis(yaw, Vec3(0, 0, 1)) * pose.rotation);
                    }
                    if (moving) {
                        // In the view plane (x right, z up), scaled to the framed sculpture.
                        const double mmPerPixel = glm::length(frameBox.max - frameBox.min) /
                                                  std::max(1, viewer->height());
                        pose.translation += Vec3((cursorX - lastX) * mmPerPixel, 0,
                                                 -(cursorY - lastY) * mmPerPixel);
                    }
                    studio.setObjectPose(pose);
                }
            }
            if (ev.kind == K::Scroll && !overUi())
                depthInDiameters = std::clamp(
                    depthInDiameters + ev.y * cfg.interaction.depthStepOverDiameter, -1.0, 1.0);
        }
        if (switched) continue;
        // The UI: drawn into its texture now, composited into each eye by the draw below;
        // what it asks for is applied like keys.
        render::UiImage uiImage;
        if (uiLayer) {
            const auto u0 = std::chrono::steady_clock::now();
            const glm::ivec2 uiSize = viewer->eyeImageSize(mode);
            uiLayer->beginFrame(uiSize.x, uiSize.y, std::max(1e-3, frameMs / 1000));
            SculptUiView view = sculptUiViewOf(session, ui);
            view.frameMs = frameMs;
            view.message = message;
            view.bindings = &cfg.interaction.bindings;
            view.marginPx = float(
                std::ceil(std::abs(viewer->lastUiShiftNdc(render::Eye::Left)) * uiSize.x / 2));
            uiState.importing = rig->studio().importStatus().value_or("");
            const std::vector<UiAction> actions = sculptUi(uiState, view, cfg, uiSize.x, uiSize.y);
            uiImage = uiLayer->endFrame();
            uiImage.depthMm = cfg.render.uiDepthMm;
            uiMsTotal +=
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - u0)
                    .count();
            for (const UiAction& a : actions) {
                if (switched) break;
                if (a.name == "preferences_changed") {
                    mode = render::parseStereoMode(cfg.render.stereo);
                    display.ipdMm = cfg.render.ipdMm;
                    uiLayer->setScale(fittedUiScale(cfg.render.uiScale, viewer->height()));
                } else if (applySharedUiAction(a, *rig, uiState, cfg, message, switched)) {
                    // Opening a dialog or the recent list says nothing new (found by QA: the
                    // last "saved DIR" was logged again).
                    if (!message.empty() && !opensPanel(a.name)) spdlog::info("{}", message);
                } else {
                    doAction(a.name);
                }
            }
            if (switched) continue;
        }
        rig->pumpDevices();
        if (auto exported = rig->pollBackgroundWork()) message = *exported;
        worldFromObject = worldFromObjectMatrix();
        // A tracker pen, when one reports, places the tool; the pointer does otherwise.
        DeviceInput* devices = rig->devices();
        const std::optional<Vec3> penWorld = devices ? devices->toolWorld() : std::nullopt;

        // The tool follows the surface under the pointer (plus the scroll depth), touching
        // it (PickTool.h); a tracked pen places it wherever the pen is.
        Vec3 origin, dir;
        viewer->pixelRay(cursorX, cursorY, origin, dir);
        const glm::dmat4 objectFromWorld = glm::inverse(worldFromObject);
        const Vec3 oObj = Vec3(objectFromWorld * glm::dvec4(origin, 1));
        const Vec3 dObj = glm::normalize(Vec3(objectFromWorld * glm::dvec4(dir, 0)));
        const Vec3 downObj = glm::normalize(Vec3(objectFromWorld * glm::dvec4(0, 0, -1, 0)));
        const double toolRadius = 0.5 * level.diameterMm;
        ToolPick pick =
            pickTool(session, oObj, dObj, toolRadius, depthInDiameters * level.diameterMm, downObj);
        if (!overUi() && pick.surfaceHit) lastSculptPoint = *pick.surfaceHit;
        if (penWorld) {
            toolWorld = *penWorld;  // DeviceInput already moved the tool with every sample
            pick = toolCues(session, Vec3(objectFromWorld * glm::dvec4(toolWorld, 1)), toolRadius,
                            downObj);
        } else {
            toolWorld = Vec3(worldFromObject * glm::dvec4(pick.toolCentre, 1));
            try {
                ui.moveTool(toolWorld);
            } catch (const SessionError& e) {
                spdlog::warn("{}", e.what());
            }
        }
        render::ToolDraw tool;
        tool.worldPos = toolWorld;
        tool.radiusMm = toolRadius;
        tool.selectBox = session.tool() == ToolKind::Select;
        tool.contact = int(pick.contact);
        if (pick.shadow) {
            tool.shadow = true;
            tool.shadowPos = Vec3(worldFromObject * glm::dvec4(*pick.shadow, 1));
        }
        // The mesher's last published set: the frame never waits for a rebuild.
        const std::shared_ptr<const core::MeshChunks> shown = session.published();
        viewer->syncChunks(*shown);
        if (!(shown->region == framedRegion) || frame % 30 == 29) {
            const Aabb b = shown->bounds;
            if (!b.empty()) frameBox = b;
            // A new region (a zoom) is framed where the object is now.
            if (!(shown->region == framedRegion))
                framedTranslation = session.objectPose().translation;
            framedRegion = shown->region;
        }
        // The box the camera frames, in object space: shifted back by how far the object was
        // moved since, so that the camera stays where it was.
        Aabb cameraBox = frameBox;
        if (const Vec3 moved = session.objectPose().translation - framedTranslation;
            moved != Vec3(0) && !cameraBox.empty()) {
            const Vec3 back = glm::inverse(session.objectPose().rotation) * moved;
            cameraBox.min -= back;
            cameraBox.max -= back;
        }
        // A headset with a tracked head station moves the eyes; otherwise the camera frames
        // the sculpture.
        viewer->setTrackedHead(devices ? devices->worldFromHead(devices::monotonicNowNs())
                                       : std::optional<glm::dmat4>());
        const render::FrameStats st = viewer->draw(worldFromObject, cameraBox, tool, mode, display,
                                                   lens, uiLayer ? &uiImage : nullptr);
        ++frame;
        const bool last = o.frames > 0 && frame >= size_t(o.frames);
        if (last && !keepLastFrame(*viewer, o.shotPath, o.lastFrame)) {
            code = 1;
            break;
        }
        viewer->swap();
        frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                      .count();
        frameTimes.add(frameMs);
        for (double ms : rig->studio().takePublishDelaysMs())
            meshLag.add(ms);
        char title[256];
        std::snprintf(
            title, sizeof title,
            "vsculpt — %s%s%s · size %d (%.1f mm) · zoom %d · %zu skeletons · %zu triangles · "
            "%.1f ms/frame · %s%s%s",
            studio::toString(session.tool()),
            session.mirror() == core::MirrorAxis::None ? "" : " · mirror ",
            session.mirror() == core::MirrorAxis::None ? "" : core::toString(session.mirror()),
            session.size(), level.diameterMm, session.zoom(), session.sculpture().counts().total(),
            st.triangles, frameMs,
            session.projectDir() ? session.projectDir()->filename().c_str() : "no project",
            message.empty() ? "" : " · ", message.c_str());
        viewer->setTitle(title);
        if (last) running = false;
    }
    // Closing ends the stroke in flight (journaled like any other) and snapshots the project.
    // The status line's last word on an export still being written is how it ended.
    if (auto exported = rig->pollBackgroundWork(true)) message = *exported;
    if (code == 0) warnIfScriptUnfinished(script, commandIndex);
    rig->close();
    if (o.report) {
        WindowOptions::Report& r = *o.report;
        const Session& s = rig->session();
        r.tool = s.tool();
        r.mirror = s.mirror();
        r.size = s.size();
        r.zoom = s.zoom();
        {
            const core::Aabb box = s.region().box();
            r.zoomCentreMm = 0.5 * (box.min + box.max);
        }
        r.skeletons = s.sculpture().counts().lattice;
        r.steps = rig->studio().stepCount();
        r.message = message;
        r.ui = uiState;
        r.display = viewer->lastDisplay();
        r.uiShiftNdc[0] = viewer->lastUiShiftNdc(render::Eye::Left);
        r.uiShiftNdc[1] = viewer->lastUiShiftNdc(render::Eye::Right);
        r.meanUiMs = frame > 0 ? uiMsTotal / double(frame) : 0;
    }
    if (rig->devices() && !rig->devices()->counters().empty())
        logLines(spdlog::level::info, rig->devices()->summary());
    spdlog::info("{} frame(s), {} skeletons, frame p50 {}, p99 {}", frame,
                 rig->session().sculpture().counts().total(),
                 formatDuration(frameTimes.quantile(0.5) / 1000),
                 formatDuration(frameTimes.quantile(0.99) / 1000));
    if (meshLag.count())
        spdlog::info("the mesh followed {} edit(s) by p50 {}, p99 {} (mesher thread)",
                     meshLag.count(), formatDuration(meshLag.quantile(0.5) / 1000),
                     formatDuration(meshLag.quantile(0.99) / 1000));
    return code;
}

}  // namespace vsculpt::app
