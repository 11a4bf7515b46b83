// SPDX-License-Identifier: MIT
#include "vsculpt/app/RenderStill.h"

#include "vsculpt/app/CliChecks.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/render/RayTrace.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <tuple>

namespace vsculpt::app {

using namespace vsculpt::studio;

int runRenderStill(const RenderOptions& o, std::ostream& out, std::ostream& err) {
    int w = 0, h = 0;
    // Bad values and the output are checked before the (long) render.
    try {
        std::tie(w, h) = parseImageSize(o.size, "--size");
        requirePngPath(o.outPath, "--out");
        core::ensureWritable(o.outPath);
    } catch (const std::exception& e) {
        err << "vsculpt render: error: " << e.what() << "\n";
        return 2;
    }
    std::unique_ptr<Studio> studio;
    try {
        if (std::filesystem::is_directory(o.input)) {
            // Read-only: a still never changes the project (no journal truncation, no lock
            // file), works on read-only media and beside a window that has it open.
            studio = Studio::openProject(
                o.input,
                core::loadConfig(o.configPath.empty() ? core::defaultConfigPath()
                                                      : std::filesystem::path(o.configPath)),
                ProjectMode::ReadOnly);
            if (!studio->session().recoveryWarning().empty())
                err << "vsculpt render: warning: " << studio->session().recoveryWarning() << "\n";
        } else {
            const Script script = loadScript(o.input);
            // Through a studio, so sketch commands build their solids here too.
            studio = std::make_unique<Studio>(
                core::loadConfig(o.configPath.empty() ? core::defaultConfigPath()
                                                      : std::filesystem::path(o.configPath)));
            installProjector(*studio);
            for (const ScriptCommand& c : script.commands) {
                try {
                    studio->apply(c);
                } catch (const std::exception& e) {
                    err << "vsculpt render: error: " << script.source << ":" << c.line << ": "
                        << e.what() << "\n";
                    return 2;
                }
            }
        }
    } catch (const std::exception& e) {
        err << "vsculpt render: error: " << e.what() << "\n";
        return 2;
    }
    const Session* session = &studio->session();
    try {
        const auto t0 = std::chrono::steady_clock::now();
        const double spacing = o.spacingMm > 0
                                   ? o.spacingMm
                                   : core::zoomSpacing(session->sculpture().config(),
                                                       session->sculpture().levels(), 3);
        core::Mesh mesh = session->wholeMesh(spacing);
        // The camera looks from the front (-y, z up); yaw and pitch turn the sculpture.
        const core::RigidTransform turn{
            glm::angleAxis(glm::radians(o.pitchDeg), core::Vec3(1, 0, 0)) *
                glm::angleAxis(glm::radians(o.yawDeg), core::Vec3(0, 0, 1)),
            core::Vec3(0.0)};
        for (core::Vec3& p : mesh.positions)
            p = turn.apply(p);
        for (core::Vec3& n : mesh.normals)
            n = turn.applyToVector(n);
        render::RayTraceOptions ro;
        ro.width = w;
        ro.height = h;
        ro.aoSamples = o.samples;
        ro.shadowSamples = std::max(1, o.samples / 2);
        render::writePng(render::rayTrace(mesh, ro), o.outPath);
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        out << "vsculpt render: wrote " << o.outPath << " (" << w << "x" << h << ", "
            << mesh.triangleCount() << " triangles at " << spacing << " mm, " << s << " s)\n";
    } catch (const SessionError& e) {
        err << "vsculpt render: error: " << e.what() << "\n";  // e.g. a spacing too fine
        return 2;
    } catch (const std::exception& e) {
        err << "vsculpt render: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

}  // namespace vsculpt::app
