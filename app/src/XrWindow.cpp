// SPDX-License-Identifier: MIT
#include "vsculpt/app/XrWindow.h"

#include "vsculpt/app/CliChecks.h"
#include "vsculpt/app/Interrupt.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/app/XrInput.h"
#include "vsculpt/app/XrPanelUi.h"
#include "vsculpt/core/DurationHistogram.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/devices/Recording.h"
#include "vsculpt/devices/XrBindings.h"
#include "vsculpt/devices/XrHeadset.h"
#include "vsculpt/render/Viewer.h"
#include "vsculpt/studio/PickTool.h"
#include "vsculpt/studio/Script.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes only

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <thread>

namespace vsculpt::app {

using namespace vsculpt::studio;

namespace {

// The haptic tick as the pen's ray comes onto a panel's button.
constexpr int64_t kButtonTickNs = 10'000'000;

// Clip planes of the headset's eyes, mm: the pen's tool a hand's width away, the room.
constexpr double kNearMm = 10, kFarMm = 20000;

render::EyeView eyeView(const devices::XrEyeView& e, const core::XrConfig& cfg) {
    const glm::dmat4 worldFromEye =
        devices::worldPoseFromXrLocal(e.localFromEye, cfg.sculptureInLocalM);
    render::EyeView v;
    v.viewFromWorld = glm::inverse(worldFromEye);
    v.clipFromView = devices::projectionFromXrFov(e.angleLeft, e.angleRight, e.angleUp, e.angleDown,
                                                  kNearMm, kFarMm);
    v.worldPosition = core::Vec3(worldFromEye[3]);
    return v;
}

devices::GlxBinding glxOf(const render::NativeGl& n) {
    return {n.display, n.visualId, n.fbConfig, n.drawable, n.context};
}

}  // namespace

int runXr(const WindowOptions& options, const core::SculptConfig& cfg, Script script,
          std::ostream& out, std::ostream& err) {
    LogScope log(err, options.verbosity, "vsculpt");
    const WindowOptions& o = options;
    // A recording written over the script played, the config or the project's own files would
    // lose them (found by QA: --record DIR/journal.vjl left a project that no longer opened).
    auto recordClash = [&](const std::string& projectDir) {
        return outputClash({{"--record", o.recordPath}}, o.playScript, o.configPath, projectDir);
    };
    try {
        if (!o.recordPath.empty()) {
            if (const std::string clash = recordClash(o.projectDir); !clash.empty())
                throw std::invalid_argument(clash);
            requireRecordingPath(o.recordPath, "--record");
            core::ensureWritable(o.recordPath);
            if (!script.commands.empty())
                // Said now, not found at replay (QA: the replay's hash differed, unexplained).
                spdlog::warn(
                    "--record holds the controllers only: the --play script's commands are not "
                    "in it, so its replay starts without their edits");
        }
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    if (!o.shotPath.empty()) spdlog::warn("--shot is not taken in a headset session");
    std::unique_ptr<devices::XrHeadset> xr;
    try {
        xr = std::make_unique<devices::XrHeadset>(devices::XrHeadset::Options{});
    } catch (const std::exception& e) {
        // XrUnavailable (no runtime, no headset) or a runtime that fails at once: the
        // desktop window is the way to go on sculpting.
        spdlog::warn("no headset: {}", e.what());
        spdlog::info("opening the desktop window instead (docs/xr.md){}",
                     o.recordPath.empty() ? "" : "; nothing is recorded");
        WindowOptions w = options;
        w.xr = false;
        w.recordPath.clear();  // said above: nothing is recorded
        return runWindow(w, out, err);
    }
    spdlog::info("openxr: {} on {} (OpenGL {})", xr->systemName(), xr->runtimeName(),
                 xr->glRequirements());
    std::unique_ptr<render::Viewer> viewer;
    try {
        // The GL context the swapchains live in; its window mirrors the left eye.
        viewer =
            std::make_unique<render::Viewer>(o.width, o.height, "vsculpt — headset", !o.hidden);
    } catch (const render::RenderError& e) {
        spdlog::error("no GL context for the headset: {}", e.what());
        return 1;
    }
    if (const int samples = viewer->setEyeSamples(cfg.render.xr.msaaSamples);
        samples != cfg.render.xr.msaaSamples)
        spdlog::warn("render.xr.msaa_samples {}: this GL offers {} at most; using {}",
                     cfg.render.xr.msaaSamples, samples, samples);
    std::unique_ptr<Rig> rig;
    try {
        // A --play script or a recording starts from the default tool and view, so the
        // recording replays to the same sculpture (found by QA: it started turned and
        // carving, from view.json, and its replay did not).
        rig = std::make_unique<Rig>(
            cfg, windowRigOptions(o.projectDir, o.noProject, o.devices,
                                  !o.playScript.empty() || !o.recordPath.empty()));
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    // The project chosen for the session (the last one, or a new autosave project).
    if (const auto& dir = rig->session().projectDir(); dir && !o.recordPath.empty()) {
        if (const std::string clash = recordClash(dir->string()); !clash.empty()) {
            spdlog::error("{}", clash);
            return 2;
        }
    }
    logLines(spdlog::level::info, rig->projectSummary());
    // What recovery dropped is a warning, as `play` says it (found by QA: info lines).
    logLines(spdlog::level::warn, rig->session().recoveryWarning());
    try {
        xr->startSession(glxOf(viewer->nativeGl()));
    } catch (const std::exception& e) {
        spdlog::error("openxr: {}", e.what());
        return 1;
    }
    XrInput input(cfg.render.xr, rig->interaction(), rig->studio());
    // The status and the palette as a panel beside the sculpture (an OpenXR quad layer),
    // pointed at with the pen: drawn with the window's UI layer into its own image, copied
    // into the panel's swapchain image.
    std::unique_ptr<XrPanelUi> panelUi;
    const devices::XrPanel panel;
    if (o.ui) {
        try {
            panelUi = std::make_unique<XrPanelUi>(*viewer, panel, cfg.render.xr,
                                                  float(cfg.render.uiScale));
            xr->createPanel(panel);
        } catch (const std::exception& e) {
            spdlog::warn("no panel in the headset: {}", e.what());
            panelUi.reset();
        }
    }
    // Buttons clicked on the panel, each handed to XrInput with the next frame's hands (so a
    // recording holds them), and what the last save or export said.
    std::vector<std::string> clicked;
    std::string message;
    ToolContact lastContact = ToolContact::Air;
    double frameMs = 0;
    // The controllers as a device of their own in a recording: `vsculpt play` maps the same
    // hands through DeviceInput (driver "openxr") with the same config.
    std::unique_ptr<devices::RecordingWriter> recording;
    const std::string recorded = "xr";
    if (!o.recordPath.empty()) {
        devices::DeviceRule rule;
        rule.name = recorded;
        rule.driver = devices::DeviceDriver::OpenXr;
        rule.access = devices::DeviceAccess::Hidraw;
        rule.products = {0};  // not a USB device: the format wants ids, 0000 says none
        try {
            recording = std::make_unique<devices::RecordingWriter>(
                o.recordPath, std::vector<devices::DeviceRule>{rule},
                std::map<std::string, std::string>{
                    {"config", nlohmann::json::parse(core::configToJson(cfg)).dump()},
                    {"vsculpt", "0.1.0"},
                    {"headset", xr->systemName() + " on " + xr->runtimeName()}});
            recording->write({devices::DeviceEventKind::Arrived, devices::monotonicNowNs(),
                              recorded, devices::arrivalBytes(0, 0)});
        } catch (const devices::RecordingError& e) {
            spdlog::error("{}", e.what());
            return 2;
        }
    }
    const auto pulseNs = int64_t(cfg.render.xr.hapticPulseMs * 1e6);
    size_t frames = 0, rendered = 0, commandIndex = 0, pulses = 0;
    double cpuMsTotal = 0;
    // Frame times and how far the mesh trailed the edits, in fixed memory for hours at 90 Hz.
    core::DurationHistogram frameTimes, meshLag;
    bool vibrating = false;
    std::string why;
    int code = 0;
    InterruptScope interrupts;
    try {
        while (xr->pollEvents(why)) {
            // Ctrl-C, SIGTERM or SIGHUP: the session ends as the runtime's exit would, so the
            // work is snapshotted and the next open has nothing to recover.
            if (const int sig = interruptSignal(); sig != 0 && xr->running()) {
                spdlog::info("closing: {}", ::strsignal(sig));
                xr->requestExit();
            }
            for (const render::InputEvent& ev : viewer->pollEvents()) {
                using K = render::InputEvent::Kind;
                if (ev.kind == K::Close ||
                    (ev.kind == K::Key && ev.pressed && ev.code == GLFW_KEY_ESCAPE))
                    xr->requestExit();
            }
            if (!xr->running()) {
                // Idle: the runtime has not made the session ready (or has stopped it).
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
                continue;
            }
            const devices::XrFrameTiming timing = xr->waitFrame();
            const auto t0 = std::chrono::steady_clock::now();
            xr->beginFrame();
            Studio& studio = rig->studio();
            const Session& session = rig->session();
            if (const int failed = playNextScriptCommand(studio, script, commandIndex)) {
                xr->requestExit();
                code = failed;
            }
            XrHands hands = handsInWorld(xr->syncInput(timing.predictedDisplayTime), cfg.render.xr);
            if (!clicked.empty()) {
                hands.panelAction = clicked.front();
                clicked.erase(clicked.begin());
            }
            // While the pen points at the panel its trigger clicks there and sculpts nothing.
            const bool onPanel =
                panelUi &&
                panelUi->point(hands, !input.engaged() && lastContact == ToolContact::Air);
            if (onPanel) hands.trigger = 0;
            if (recording)
                recording->write({devices::DeviceEventKind::Report, devices::monotonicNowNs(),
                                  recorded, xrHandsReport(hands)});
            input.handle(hands);
            if (auto refused = input.takeRefusal()) message = *refused;
            // Trackers and 3D mice keep working beside the controllers.
            rig->pumpDevices();
            if (auto done = rig->pollBackgroundWork()) message = *done;

            const glm::dmat4 worldFromObject = session.objectPose().matrix();
            const glm::dmat4 objectFromWorld = glm::inverse(worldFromObject);
            const double toolRadius =
                0.5 * session.sculpture().levels().level(session.size()).diameterMm;
            render::ToolDraw tool;
            tool.visible = input.toolWorld().has_value();
            tool.radiusMm = toolRadius;
            tool.selectBox = session.tool() == ToolKind::Select;
            // The pen's ray to the panel while it points there.
            if (const auto at = panelUi ? panelUi->pointerWorld() : std::nullopt;
                at && hands.worldFromPen) {
                tool.pointer = true;
                tool.pointerFrom = core::Vec3((*hands.worldFromPen)[3]);
                tool.pointerTo = *at;
            }
            ToolContact contact = ToolContact::Air;
            if (input.toolWorld()) {
                tool.worldPos = *input.toolWorld();
                const core::Vec3 down =
                    glm::normalize(core::Vec3(objectFromWorld * glm::dvec4(0, 0, -1, 0)));
                const ToolPick pick =
                    toolCues(session, core::Vec3(objectFromWorld * glm::dvec4(tool.worldPos, 1)),
                             toolRadius, down);
                contact = pick.contact;
                tool.contact = int(contact);
                if (pick.shadow) {
                    tool.shadow = true;
                    tool.shadowPos = core::Vec3(worldFromObject * glm::dvec4(*pick.shadow, 1));
                }
            }
            // Contact feedback on the pen hand: a pulse renewed every frame of contact, its
            // amplitude after the contact; stopped when the tool leaves the clay.
            const double amplitude = xr->focused() ? hapticAmplitude(contact, cfg.render.xr) : 0;
            if (amplitude > 0) {
                xr->vibrate(float(amplitude), pulseNs);
                ++pulses;
            } else if (onPanel && panelUi->enteredButton() && xr->focused()) {
                // A tick as the pen's ray comes onto a button of the panel.
                xr->vibrate(float(cfg.render.xr.hapticTouching), kButtonTickNs);
                ++pulses;
            } else if (vibrating) {
                xr->stopVibration();
            }
            vibrating = amplitude > 0;
            lastContact = contact;  // the next frame's panel takes the trigger only in the air

            // The one place the mesh reaches the GPU.
            // The mesher's last published set: the frame never waits for a rebuild.
            viewer->syncChunks(*session.published());
            if (timing.shouldRender) {
                std::array<devices::XrEyeView, 2> eyes =
                    xr->locateEyes(timing.predictedDisplayTime);
                for (int e = 0; e < 2; ++e) {
                    const unsigned texture = xr->acquireEye(e);
                    devices::XrEyeView& eye = eyes[size_t(e)];
                    viewer->drawEye(worldFromObject, tool, eyeView(eye, cfg.render.xr), texture,
                                    eye.width, eye.height);
                    if (e == 0 && !o.hidden) viewer->blitToWindow(texture, eye.width, eye.height);
                    xr->releaseEye(e);
                }
                if (panelUi) {
                    const unsigned texture = xr->acquirePanel();
                    SculptUiView view = sculptUiViewOf(session, rig->interaction());
                    view.frameMs = frameMs;
                    view.message = message;
                    const std::string handsLine =
                        std::string(onPanel           ? "pointing at the panel"
                                    : input.engaged() ? "sculpting"
                                                      : "pen up") +
                        (input.grabbing() ? ", holding the sculpture" : "");
                    for (const UiAction& a : panelUi->draw(view, handsLine, frameMs / 1000)) {
                        if (!Rig::handles(a.name)) {
                            clicked.push_back(a.name);
                            continue;
                        }
                        try {
                            message = rig->projectAction(a.name);  // save, export
                            spdlog::info("{}", message);
                        } catch (const std::logic_error&) {
                            throw;
                        } catch (const std::exception& e) {
                            message = e.what();
                            spdlog::warn("{}", message);
                        }
                    }
                    viewer->copyTexture(panelUi->texture(), texture, panel.widthPx, panel.heightPx);
                    xr->releasePanel();
                }
                xr->endFrame(timing, &eyes, panelUi != nullptr);
                ++rendered;
            } else {
                xr->endFrame(timing, nullptr);
            }
            if (!o.hidden) viewer->swap();
            if (recording) recording->flush();
            ++frames;
            frameMs =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
            cpuMsTotal += frameMs;
            frameTimes.add(frameMs);
            for (double ms : rig->studio().takePublishDelaysMs())
                meshLag.add(ms);
            if (o.frames > 0 && frames >= size_t(o.frames)) xr->requestExit();
            if (frames % 45 == 1) {
                char title[160];
                std::snprintf(title, sizeof title,
                              "vsculpt — headset · size %d · zoom %d · %zu skeletons",
                              session.size(), session.zoom(), session.sculpture().counts().total());
                viewer->setTitle(title);
            }
        }
        if (why.find("lost") != std::string::npos || why.find("loss") != std::string::npos) {
            spdlog::error("openxr: {}", why);
            code = 1;
        } else {
            spdlog::info("openxr: {}", why);
        }
    } catch (const devices::XrFailure& e) {
        spdlog::error("openxr: {}", e.what());
        code = 1;
    }
    // Closing ends the stroke in flight (journaled like any other) and snapshots the project.
    if (code == 0) warnIfScriptUnfinished(script, commandIndex);
    rig->close();
    if (recording) {
        recording->write({devices::DeviceEventKind::Left, devices::monotonicNowNs(), recorded, {}});
        recording->flush();
        spdlog::info("wrote {} ({} event(s))", o.recordPath, recording->eventsWritten());
    }
    const Session& s = rig->session();
    spdlog::info(
        "openxr: {} frame(s), {} with both eyes drawn, {:.2f} ms CPU per frame (p99 {:.2f} ms), "
        "{} haptic pulse(s), {} debug message(s)",
        frames, rendered, frames ? cpuMsTotal / double(frames) : 0.0, frameTimes.quantile(0.99),
        pulses, xr->debugMessages());
    if (meshLag.count())
        spdlog::info("the mesh followed {} edit(s) by p50 {:.1f} ms, p99 {:.1f} ms (mesher thread)",
                     meshLag.count(), meshLag.quantile(0.5), meshLag.quantile(0.99));
    const core::RigidTransform pose = s.objectPose();
    spdlog::info(
        "object pose: rotation ({:.6f} {:.6f} {:.6f} {:.6f}), translation ({:.3f} {:.3f} "
        "{:.3f}) mm",
        pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z, pose.translation.x,
        pose.translation.y, pose.translation.z);
    char hash[32];
    std::snprintf(hash, sizeof hash, "%016llx",
                  static_cast<unsigned long long>(core::canonicalMeshHash(s.wholeMesh())));
    spdlog::info("{} skeletons, {} step(s), tool {}, size {}, zoom {}, mesh hash {}",
                 s.sculpture().counts().total(), rig->studio().stepCount(),
                 studio::toString(s.tool()), s.size(), s.zoom(), hash);
    return code;
}

}  // namespace vsculpt::app
