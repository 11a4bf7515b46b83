// SPDX-License-Identifier: MIT
#include "vsculpt/app/Play.h"

#include "vsculpt/app/CliChecks.h"
#include "vsculpt/app/ExportDetail.h"
#include "vsculpt/app/ExportInBackground.h"
#include "vsculpt/app/Log.h"
#include "vsculpt/app/ProgressBar.h"
#include "vsculpt/app/Rig.h"
#include "vsculpt/core/ExportDxf.h"
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/devices/Recording.h"
#include "vsculpt/render/Shot.h"

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <ostream>
#include <tuple>

namespace vsculpt::app {

using namespace vsculpt::studio;

using namespace vsculpt::core;

namespace {

namespace fs = std::filesystem;

// A path as the file system resolves it (links, "..", relative to the working folder), also
// for a file not made yet.
std::string hex(uint64_t v) {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(v));
    return b;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

nlohmann::json statsJson(const Studio& studio, const Mesh& mesh, const PlayOptions& o,
                         double exportSpacing) {
    const Session& s = studio.session();
    const Sculpture& sc = s.sculpture();
    const SkeletonCounts counts = sc.counts();
    const MeshTopology topo = analyzeTopology(mesh);
    const Aabb box = meshBounds(mesh);
    nlohmann::json j;
    j["script"] = o.script;
    j["skeletons"] = counts.total();
    j["skeletons_by_level"] = counts.byLevel;
    j["point_skeletons"] = counts.point;
    j["vertices"] = mesh.positions.size();
    j["triangles"] = mesh.triangleCount();
    j["watertight"] = topo.watertight();
    j["euler_characteristic"] = topo.eulerCharacteristic;
    j["components"] = topo.components;
    j["volume_mm3"] = meshVolume(mesh);
    if (!box.empty())
        j["bbox_mm"] = {{"min", {box.min.x, box.min.y, box.min.z}},
                        {"max", {box.max.x, box.max.y, box.max.z}}};
    j["mesh_hash"] = hex(canonicalMeshHash(mesh));
    const auto& ms = s.sampleMs();
    j["edit_ms"] = {{"p50", percentile(ms, 0.5)},
                    {"p99", percentile(ms, 0.99)},
                    {"max", ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end())},
                    {"samples", ms.size()}};
    j["undo_steps"] = studio.stepCount();
    j["redo_steps"] = studio.redoCount();
    j["sculpt_undo_steps"] = s.history().done().size();
    size_t strokes = 0, curves = 0, solids = 0;
    for (size_t i = 0; i < studio.document().pageCount(); ++i) {
        strokes += studio.document().page(i).liveStrokeIds().size();
        curves += studio.document().page(i).cleanCurves().size();
    }
    for (const StrokeRecord& r : s.history().done())
        solids += r.solid;
    j["sketch"] = {{"pages", studio.document().pageCount()},
                   {"strokes", strokes},
                   {"clean_curves", curves},
                   {"solids", solids}};
    j["history_bytes"] = s.history().memoryBytes();
    j["recovered_edits"] = s.recoveredEdits();
    if (!s.recoveryWarning().empty()) j["recovery_warning"] = s.recoveryWarning();
    nlohmann::json levels = nlohmann::json::array();
    for (int k = 1; k <= kLevelCount; ++k) {
        const ToolLevel& l = sc.levels().level(k);
        levels.push_back({{"level", k},
                          {"diameter_mm", l.diameterMm},
                          {"lattice_spacing_mm", l.spacingMm},
                          {"support_mm", l.supportMm}});
    }
    j["settings"] = {{"placement_mode", toString(sc.config().placement)},
                     {"grid_n", sc.config().polygonizer.gridN},
                     {"zoom", s.zoom()},
                     {"view_spacing_mm", s.region().spacingMm},
                     {"mesh_spacing_mm", exportSpacing},
                     {"levels", levels},
                     {"config", nlohmann::json::parse(configToJson(sc.config()))}};
    return j;
}

}  // namespace

int runPlay(const PlayOptions& o, std::ostream& out, std::ostream& err) {
    LogScope log(err, o.verbosity, "vsculpt play");
    const auto startTime = std::chrono::steady_clock::now();
    // Bad input first, before any work: script, config, output formats.
    Script script;
    std::optional<devices::Recording> recording;
    SculptConfig cfg;
    try {
        if (devices::isRecordingFile(o.script)) {
            recording = devices::readRecording(o.script);
            for (const std::string& w : recording->warnings)
                spdlog::warn("{}", w);
            // A recording replays with the config it was recorded with (calibration, mapping,
            // tools), unless the user names another.
            const auto stored = recording->meta.find("config");
            if (o.configPath.empty() && stored != recording->meta.end())
                cfg = parseStoredConfig(stored->second, o.script + " (recorded config)");
            else
                cfg = loadConfig(o.configPath.empty() ? defaultConfigPath()
                                                      : std::filesystem::path(o.configPath));
        } else {
            // Named as a recording but without its header (empty, or another file renamed):
            // not silently an empty script (found by QA: a 0-byte .vsrec "played").
            std::string ext = std::filesystem::path(o.script).extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(),
                           [](unsigned char c) { return char(std::tolower(c)); });
            // A missing file or a folder is named as such (loadScript says why), not as a
            // file without the recording's header (found by QA).
            std::error_code ec;
            if (ext == ".vsrec" && std::filesystem::is_regular_file(o.script, ec))
                throw std::invalid_argument(
                    o.script +
                    ": not a device recording (it does not start with \"vsculpt-recording\")");
            script = loadScript(o.script);
            cfg = loadConfig(o.configPath.empty() ? defaultConfigPath()
                                                  : std::filesystem::path(o.configPath));
        }
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    spdlog::debug("config: {}", cfg.source);
    ExportOptions exportFrameOptions;
    try {
        if (!o.up.empty()) exportFrameOptions.up = parseUpAxis(o.up);
        if (!o.units.empty()) exportFrameOptions.units = parseLengthUnit(o.units);
    } catch (const std::invalid_argument& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    for (const std::string& path : o.outputs) {
        std::string ext = std::filesystem::path(path).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        const auto& known = exportExtensions();
        if (std::error_code ec; std::filesystem::is_directory(path, ec)) {
            spdlog::error("--out {}: it is a folder (give a file name, such as {})", path,
                          (std::filesystem::path(path) / "sculpture.stl").string());
            return 2;
        }
        if (std::find(known.begin(), known.end(), ext) == known.end()) {
            spdlog::error(
                "--out {}: unknown format '{}' (use .obj, .stl, .ply, .glb, .dxf or .vdb)", path,
                ext);
            return 2;
        }
        // --up and --units serve every --out of the run, so one .glb among them is no reason
        // to refuse the run: it is written the one way glTF allows, and the user is told.
        if (formatFixesFrame(path) &&
            (exportFrameOptions.up.value_or(UpAxis::Y) != UpAxis::Y ||
             exportFrameOptions.units.value_or(LengthUnit::Metre) != LengthUnit::Metre))
            spdlog::info(
                "note: --out {}: glTF is always +Y up in metres (glTF 2.0); --up and "
                "--units apply to the other outputs",
                path);
    }
    render::ShotOptions shot;
    if (!o.shotPath.empty()) {
        try {
            shot.mode = render::parseStereoMode(o.stereo);
            std::tie(shot.width, shot.height) = parseImageSize(o.shotSize, "--shot-size");
            requirePngPath(o.shotPath, "--shot");
        } catch (const std::exception& e) {
            spdlog::error("{}", e.what());
            return 2;
        }
        // The shot is drawn after the whole run: a missing display must not cost it.
        try {
            render::requireDisplay();
        } catch (const render::RenderError& e) {
            spdlog::error("--shot {}: {}", o.shotPath, e.what());
            return 1;
        }
    }
    std::unique_ptr<tbb::global_control> threads;
    if (o.threads > 0)
        threads = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, size_t(o.threads));

    // Outputs are checked before the session runs: a typo in a folder name must not cost
    // the whole run.
    {
        std::vector<std::pair<std::string, std::string>> written;  // option, path
        for (const std::string& path : o.outputs)
            written.emplace_back("--out", path);
        if (!o.shotPath.empty()) written.emplace_back("--shot", o.shotPath);
        if (!o.statsPath.empty() && o.statsPath != "-")
            written.emplace_back("--stats", o.statsPath);
        if (const std::string clash = outputClash(written, o.script, o.configPath, o.projectDir);
            !clash.empty()) {
            spdlog::error("{}", clash);
            return 2;
        }
        for (const auto& [option, path] : written) {
            try {
                core::ensureWritable(path);
            } catch (const std::exception& e) {
                spdlog::error("{}", e.what());
                return 2;
            }
        }
    }

    if (!o.configPath.empty() && !o.projectDir.empty() &&
        std::filesystem::exists(core::snapshotPath(o.projectDir)))
        spdlog::info(
            "note: {} is an existing project: it keeps its sculpture settings (tools, "
            "field, zoom); --config gives the machine's (bindings, display, devices)",
            o.projectDir);
    RigOptions ro;
    ro.project = o.projectDir.empty() ? ProjectChoice::None : ProjectChoice::Given;
    ro.projectDir = o.projectDir;
    std::unique_ptr<Rig> rig;
    try {
        rig = std::make_unique<Rig>(cfg, ro);
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    Studio& studio = rig->studio();
    // Nothing looks at the mesh between edits unless --check compares it or --stats times it
    // (edit_ms includes the mesh update): the mesh is then brought up to date once, when the
    // shot, a sketch projection or the end asks for it.
    if (!o.check && o.statsPath.empty()) studio.setDeferredMeshing(true);
    const Session* session = &studio.session();
    if (!session->recoveryWarning().empty()) spdlog::warn("{}", session->recoveryWarning());
    if (session->recoveredEdits() > 0)
        spdlog::info("recovered {} edit(s) from the project journal", session->recoveredEdits());

    std::string deviceSummary;
    if (recording) {
        // Device replay: the same decoders and mapping as a live run, event by event.
        DeviceInput& input = rig->replayDevices(recording->devices);
        ProgressBar progress(err, o.progress && log.progressAllowed() && stderrIsTerminal(),
                             recording->events.size(), "event");
        size_t done = 0;
        for (const devices::DeviceEvent& e : recording->events) {
            const bool wasInStroke = session->inStroke();
            input.handle(e);
            if (o.check && wasInStroke && !session->inStroke()) {
                const std::string diff = session->verifyMesh();
                if (!diff.empty()) {
                    progress.clear();
                    spdlog::error("{}: event {}: --check failed: {}", o.script, done + 1, diff);
                    return 1;
                }
            }
            ++done;
            progress.update(done, long(done));
        }
        studio.endStroke();
        input.takeOutput();
        deviceSummary = input.summary();
    }
    if (!recording) {
        ProgressBar progress(err, o.progress && log.progressAllowed() && stderrIsTerminal(),
                             script.commands.size(), "line");
        size_t done = 0;
        for (const ScriptCommand& c : script.commands) {
            try {
                const size_t stepsBefore = studio.stepCount();
                const bool edited = studio.apply(c);
                // A solid or a mesh wholly inside the clay changes nothing and makes no step: say
                // so, as the sketch window does, rather than pass over the line in silence.
                const bool addsClay = c.kind == ScriptCommand::Kind::Import ||
                                      (c.kind == ScriptCommand::Kind::Sketch &&
                                       c.sketch.verb == SketchCommand::Verb::Solid);
                if (addsClay && studio.stepCount() == stepsBefore) {
                    progress.clear();
                    spdlog::warn("{}:{}: the {} lies inside the clay: nothing added", script.source,
                                 c.line, c.kind == ScriptCommand::Kind::Import ? "mesh" : "solid");
                }
                if (o.check && edited) {
                    const std::string diff = session->verifyMesh();
                    if (!diff.empty()) {
                        progress.clear();
                        spdlog::error("{}:{}: --check failed: {}", script.source, c.line, diff);
                        return 1;
                    }
                }
            } catch (const ExpectationError& e) {
                // The script ran, and the clay is not as it says: a failed check, not bad input.
                progress.clear();
                spdlog::error("{}:{}: {}", script.source, c.line, e.what());
                return 1;
            } catch (const SessionError& e) {
                progress.clear();
                spdlog::error("{}:{}: {}", script.source, c.line, e.what());
                return 2;
            } catch (const std::invalid_argument& e) {
                progress.clear();
                spdlog::error("{}:{}: {}", script.source, c.line, e.what());
                return 2;
            } catch (const std::out_of_range& e) {
                // A script naming what is not there (a stroke id to reuse, a page): its input.
                progress.clear();
                spdlog::error("{}:{}: {}", script.source, c.line, e.what());
                return 2;
            } catch (const std::exception& e) {
                progress.clear();
                spdlog::error("{}:{}: {}", script.source, c.line, e.what());
                return 1;
            }
            progress.update(++done, c.line);
        }
    }

    auto secondsSince = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    spdlog::debug("sculpted in {}", formatDuration(secondsSince(startTime)));
    try {
        if (!o.projectDir.empty()) {
            studio.save();
            spdlog::debug("saved {}", o.projectDir);
        }
        const double zoom1 = zoomSpacing(cfg, session->sculpture().levels(), 1);
        double spacing = o.exportSpacingMm > 0 ? o.exportSpacingMm : zoom1;
        if (o.exportSpacingMm == PlayOptions::kExportSpacingDetail) {
            const ExportDetail d = exportDetail(*session, zoom1);
            spacing = d.keepingMm;
            if (d.capped)
                spdlog::warn(
                    "the sculpture's finest detail (size {}, {:.3g} mm) needs a finer "
                    "grid than its {} cells per axis allow: meshing at {:.3g} mm",
                    d.finestSize, d.detailMm, Session::kWholeMeshMaxCells, spacing);
        } else {
            // The default spacing is zoom 1's; a sculpture too large for the grid at it is
            // meshed as finely as the grid allows, said; a given one too fine is refused,
            // before meshing, with the value that works.
            std::string coarser;
            spacing =
                wholeMeshSpacing(*session, spacing, o.exportSpacingMm > 0 ? "--export-spacing" : "",
                                 PlayOptions::kMaxExportSpacingMm, coarser);
            if (!coarser.empty())
                spdlog::warn("{}", coarser);
            else if (o.exportSpacingMm <= 0 && !o.outputs.empty())
                if (const std::string w = exportDetailWarning(*session, spacing); !w.empty())
                    spdlog::warn("{}", w);
        }
        const auto meshStart = std::chrono::steady_clock::now();
        const Mesh mesh = session->wholeMesh(spacing);
        spdlog::debug("meshed the whole sculpture at {:.3g} mm in {}", spacing,
                      formatDuration(secondsSince(meshStart)));
        for (const std::string& path : o.outputs) {
            ExportOptions eo = exportFrameOptions;
            eo.voxelSizeMm = spacing;
            if (formatFixesFrame(path)) {  // the note above said so
                eo.up.reset();
                eo.units.reset();
            }
            writeSculptureFile(mesh, path, eo, studio.curvesInObjectSpace());
            spdlog::info("wrote {}", path);
        }
        if (!o.shotPath.empty()) {
            // The final frame: the mesh on show at the current zoom.
            render::writePng(render::renderShot(session->view().mesh(), shot), o.shotPath);
            spdlog::info("wrote {} ({})", o.shotPath, o.stereo);
        }
        const nlohmann::json stats = statsJson(studio, mesh, o, spacing);
        if (o.statsPath == "-") {
            out << stats.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
        } else if (!o.statsPath.empty()) {
            // A script's path (or other names) with invalid UTF-8 is written with U+FFFD.
            core::writeFileAtomically(
                o.statsPath,
                stats.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n",
                /*durable=*/false);
        }
        // stdout carries machine output only (--stats -): what a person reads goes to stderr.
        if (recording) logLines(spdlog::level::info, deviceSummary);
        spdlog::info("{}{} skeletons, {} triangles, {}, mesh hash {}, {}",
                     recording ? std::to_string(recording->events.size()) + " device event(s), "
                               : std::to_string(script.commands.size()) + " command(s), ",
                     stats["skeletons"].get<size_t>(), mesh.triangleCount(),
                     stats["watertight"].get<bool>() ? "watertight" : "open",
                     stats["mesh_hash"].get<std::string>(),
                     formatDuration(secondsSince(startTime)));
    } catch (const SessionError& e) {
        // Refused input (an export spacing the grid cannot hold): the user's to change.
        spdlog::error("{}", e.what());
        return 2;
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 1;
    }
    return 0;
}

}  // namespace vsculpt::app
