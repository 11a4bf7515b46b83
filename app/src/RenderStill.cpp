// SPDX-License-Identifier: MIT
#include "vsculpt/app/RenderStill.h"

#include "vsculpt/app/CliChecks.h"
#include "vsculpt/app/ExportDetail.h"
#include "vsculpt/app/ProgressBar.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/devices/Recording.h"
#include "vsculpt/render/RayTrace.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <tuple>

namespace vsculpt::app {

using namespace vsculpt::studio;

std::string turntablePath(const std::string& outPath, int index, int count) {
    const size_t slash = outPath.find_last_of('/');
    const size_t nameStart = slash == std::string::npos ? 0 : slash + 1;
    const size_t hashes = outPath.find('#', nameStart);
    if (hashes != std::string::npos) {
        size_t end = hashes;
        while (end < outPath.size() && outPath[end] == '#')
            ++end;
        std::string number = std::to_string(index);
        if (number.size() < end - hashes) number.insert(0, end - hashes - number.size(), '0');
        return outPath.substr(0, hashes) + number + outPath.substr(end);
    }
    const int digits = std::max(3, int(std::to_string(std::max(count - 1, 0)).size()));
    char number[32];
    std::snprintf(number, sizeof number, "-%0*d", digits, index);
    const size_t dot = outPath.find_last_of('.');
    const size_t at = dot == std::string::npos || dot < nameStart ? outPath.size() : dot;
    return outPath.substr(0, at) + number + outPath.substr(at);
}

namespace {

// The box that holds the mesh turned by any angle about the vertical axis through `axisXY`
// and then tilted by `tilt`: every turntable frame fits it, so all frames share one framing.
core::Aabb turntableBox(const core::Mesh& mesh, const glm::dvec2& axisXY, const glm::dquat& tilt) {
    const core::Aabb box = core::meshBounds(mesh);
    if (box.empty()) return box;
    double r = 0;
    for (const core::Vec3& p : mesh.positions)
        r = std::max(r, glm::length(glm::dvec2(p) - axisXY));
    core::Aabb out;
    for (int i = 0; i < 8; ++i) {
        const core::Vec3 corner(axisXY.x + ((i & 1) ? r : -r), axisXY.y + ((i & 2) ? r : -r),
                                (i & 4) ? box.max.z : box.min.z);
        const core::Vec3 q = tilt * (corner - core::Vec3(axisXY, 0.0)) + core::Vec3(axisXY, 0.0);
        out.expand(q);
    }
    return out;
}

}  // namespace

int runRenderStill(const RenderOptions& o, std::ostream& out, std::ostream& err) {
    (void)out;  // stdout stays free for machine output; every message is a log line
    LogScope log(err, o.verbosity, "vsculpt render");
    const auto t0 = std::chrono::steady_clock::now();
    int w = 0, h = 0;
    const int frames = std::max(1, o.turntable);
    // Bad values and the outputs are checked before the (long) render.
    try {
        std::tie(w, h) = parseImageSize(o.size, "--size");
        if (o.turntable < 0 || o.turntable > 3600)
            throw std::invalid_argument("--turntable: " + std::to_string(o.turntable) +
                                        " frames: give 1 to 3600");
        requirePngPath(o.outPath, "--out");
        // Every frame goes to the same folder: the first one tells whether they can.
        core::ensureWritable(o.turntable > 0 ? turntablePath(o.outPath, 0, frames) : o.outPath);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    std::unique_ptr<Studio> studio;
    try {
        const core::SculptConfig cfg = core::loadConfig(
            o.configPath.empty() ? core::defaultConfigPath() : std::filesystem::path(o.configPath));
        spdlog::debug("config: {}", cfg.source);
        if (std::filesystem::is_directory(o.input)) {
            // Read-only: a still never changes the project (no journal truncation, no lock
            // file), works on read-only media and beside a window that has it open.
            studio = Studio::openProject(o.input, cfg, ProjectMode::ReadOnly);
            // The still shows the recovered edits; the project is left as it is.
            if (const size_t n = studio->session().recoveredEdits(); n > 0)
                spdlog::info(
                    "{}: {} edit(s) since the last save replayed from the journal "
                    "(read-only: the project is not changed)",
                    o.input, n);
            if (!studio->session().recoveryWarning().empty())
                spdlog::warn("{}", studio->session().recoveryWarning());
        } else {
            if (devices::isRecordingFile(o.input))
                throw std::invalid_argument(
                    o.input +
                    ": a device recording; render takes a playback script or a project "
                    "folder (replay the recording into one: vsculpt play " +
                    o.input + " --project DIR, then vsculpt render DIR)");
            const Script script = loadScript(o.input);
            // Through a studio, so sketch commands build their solids here too.
            studio = std::make_unique<Studio>(cfg);
            // The still is ray-traced from a mesh of its own: the view is never looked at,
            // unless a sketch projects onto it (then it is caught up).
            studio->setDeferredMeshing(true);
            installProjector(*studio);
            for (const ScriptCommand& c : script.commands) {
                try {
                    studio->apply(c);
                } catch (const std::exception& e) {
                    spdlog::error("{}:{}: {}", script.source, c.line, e.what());
                    return 2;
                }
            }
        }
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    const Session* session = &studio->session();
    try {
        double spacing = o.spacingMm > 0 ? o.spacingMm
                                         : core::zoomSpacing(session->sculpture().config(),
                                                             session->sculpture().levels(), 3);
        // A sculpture too large for the whole-sculpture grid at that spacing: by default the
        // finest the grid allows, said; a given --spacing is refused with the value that works.
        std::string coarser;
        spacing = wholeMeshSpacing(*session, spacing, o.spacingMm > 0 ? "--spacing" : "",
                                   RenderOptions::kMaxSpacingMm, coarser);
        if (!coarser.empty())
            spdlog::warn("{}", coarser);
        else if (o.spacingMm <= 0)
            // As play says of its exports (found by QA: size-2 dots came out square, unsaid).
            if (const std::string w =
                    exportDetailWarning(*session, spacing, "the still's mesh spacing", "--spacing");
                !w.empty())
                spdlog::warn("{}", w);
        const auto meshStart = std::chrono::steady_clock::now();
        const core::Mesh mesh = session->wholeMesh(spacing);
        spdlog::debug("meshed at {:.3g} mm: {} triangles in {}", spacing, mesh.triangleCount(),
                      formatDuration(std::chrono::duration<double>(
                                         std::chrono::steady_clock::now() - meshStart)
                                         .count()));
        // The camera looks from the front (-y, z up); yaw turns the sculpture about the
        // vertical axis through its centre, pitch then tilts it about the horizontal (x).
        const core::Aabb bounds = core::meshBounds(mesh);
        const glm::dvec2 axisXY =
            bounds.empty() ? glm::dvec2(0.0) : 0.5 * glm::dvec2(bounds.min + bounds.max);
        const glm::dquat tilt = glm::angleAxis(glm::radians(o.pitchDeg), core::Vec3(1, 0, 0));
        render::RayTraceOptions ro;
        ro.width = w;
        ro.height = h;
        ro.aoSamples = o.samples;
        ro.shadowSamples = std::max(1, o.samples / 2);
        if (o.turntable > 0) ro.frameBox = turntableBox(mesh, axisXY, tilt);

        ProgressBar progress(err, o.progress && log.progressAllowed() && stderrIsTerminal(),
                             size_t(frames) * size_t(h), o.turntable > 0 ? "frame" : "row");
        for (int i = 0; i < frames; ++i) {
            const double yaw = o.yawDeg + 360.0 * i / frames;
            const glm::dquat turn = tilt * glm::angleAxis(glm::radians(yaw), core::Vec3(0, 0, 1));
            core::Mesh turned = mesh;
            const core::Vec3 pivot(axisXY, 0.0);
            for (core::Vec3& p : turned.positions)
                p = turn * (p - pivot) + pivot;
            for (core::Vec3& n : turned.normals)
                n = turn * n;
            ro.progress = [&, i](int rows) {
                progress.update(size_t(i) * size_t(h) + size_t(rows),
                                o.turntable > 0 ? long(i + 1) : long(rows));
            };
            const std::string path =
                o.turntable > 0 ? turntablePath(o.outPath, i, frames) : o.outPath;
            render::writePng(render::rayTrace(turned, ro), path);
            if (o.turntable > 0) {
                progress.clear();
                spdlog::debug("wrote {} (yaw {} degrees)", path, yaw);
            }
        }
        progress.clear();
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (o.turntable > 0)
            spdlog::info("wrote {} frames {} ... {} ({}x{}, {} triangles at {:.3g} mm, {})", frames,
                         turntablePath(o.outPath, 0, frames),
                         turntablePath(o.outPath, frames - 1, frames), w, h, mesh.triangleCount(),
                         spacing, formatDuration(s));
        else
            spdlog::info("wrote {} ({}x{}, {} triangles at {:.3g} mm, {})", o.outPath, w, h,
                         mesh.triangleCount(), spacing, formatDuration(s));
    } catch (const SessionError& e) {
        spdlog::error("{}", e.what());  // e.g. a spacing too fine
        return 2;
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 1;
    }
    return 0;
}

}  // namespace vsculpt::app
