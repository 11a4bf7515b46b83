// SPDX-License-Identifier: MIT
#include "vsculpt/app/Rig.h"

#include "vsculpt/app/ExportDetail.h"
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/HomeFolder.h"
#include "vsculpt/core/PrintableText.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/core/Zoom.h"
#include "vsculpt/devices/Recording.h"
#include "vsculpt/render/StereoCamera.h"
#include "vsculpt/studio/ViewState.h"

#include <glm/gtc/quaternion.hpp>

#include <unistd.h>

#include <cstdlib>
#include <ctime>
#include <fstream>
#include <ostream>
#include <sstream>

#include <spdlog/spdlog.h>

namespace vsculpt::app {

using namespace vsculpt::studio;

RigOptions windowRigOptions(const std::string& projectDir, bool noProject, bool liveDevices,
                            bool scripted) {
    RigOptions ro;
    ro.project = noProject            ? ProjectChoice::None
                 : projectDir.empty() ? ProjectChoice::Autosave
                                      : ProjectChoice::Given;
    ro.projectDir = projectDir;
    ro.liveDevices = liveDevices;
    ro.rememberRecent = true;
    ro.asyncMeshing = true;
    ro.keepViewState = true;
    ro.restoreViewState = !scripted;
    return ro;
}

std::filesystem::path dataDir() {
    const char* xdg = std::getenv("XDG_DATA_HOME");
    if (xdg && *xdg == '/') return std::filesystem::path(xdg) / "vsculpt";
    if (const std::filesystem::path home = core::homeFolder(); !home.empty())
        return home / ".local" / "share" / "vsculpt";
    // No home folder at all: one of this user's own, never one that users share.
    return std::filesystem::temp_directory_path() / ("vsculpt-" + std::to_string(::getuid()));
}

std::optional<std::filesystem::path> lastProjectRecorded() {
    std::ifstream in(dataDir() / "last-project");
    std::string line;
    if (!std::getline(in, line) || line.empty()) return std::nullopt;
    return std::filesystem::path(line);
}

std::optional<std::filesystem::path> lastProject() {
    const auto dir = lastProjectRecorded();
    std::error_code ec;
    if (!dir || !std::filesystem::exists(core::snapshotPath(*dir), ec)) return std::nullopt;
    return dir;
}

namespace {

/// The recent-projects file as written, existing or not.
std::vector<std::filesystem::path> readRecent() {
    std::vector<std::filesystem::path> list;
    std::ifstream in(dataDir() / "recent-projects");
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) list.emplace_back(line);
    return list;
}

}  // namespace

namespace {

void remember(const std::filesystem::path& dir, bool asLast) {
    try {
        std::filesystem::create_directories(dataDir());
        const std::filesystem::path absolute = std::filesystem::absolute(dir);
        if (asLast)
            core::writeFileAtomically(dataDir() / "last-project", absolute.string() + "\n", false);
        std::string text;
        for (const auto& p : withRecentProject(readRecent(), absolute))
            text += p.string() + "\n";
        core::writeFileAtomically(dataDir() / "recent-projects", text, false);
    } catch (const std::exception& e) {
        spdlog::warn("cannot remember the {} project: {}", asLast ? "last" : "recent", e.what());
    }
}

}  // namespace

void rememberLastProject(const std::filesystem::path& dir) {
    remember(dir, true);
}

void rememberRecentProject(const std::filesystem::path& dir) {
    remember(dir, false);
}

std::vector<std::filesystem::path> withRecentProject(std::vector<std::filesystem::path> list,
                                                     const std::filesystem::path& dir, size_t max) {
    std::erase(list, dir);
    list.insert(list.begin(), dir);
    if (list.size() > max) list.resize(max);
    return list;
}

std::vector<std::filesystem::path> recentProjects() {
    std::vector<std::filesystem::path> list;
    for (const auto& p : readRecent()) {
        std::error_code ec;
        // A folder deleted since is not offered; the file keeps it (a disk unplugged for now
        // may come back) until ten newer projects push it out.
        if (std::filesystem::exists(core::snapshotPath(p), ec)) list.push_back(p);
    }
    return list;
}

std::filesystem::path unusedTimeName(const std::filesystem::path& folder,
                                     const std::string& extension) {
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%d-%H%M%S", &local);
    for (int i = 0;; ++i) {
        std::filesystem::path p =
            folder / (std::string(stamp) + (i ? "-" + std::to_string(i) : "") + extension);
        std::error_code ec;
        if (!std::filesystem::exists(std::filesystem::symlink_status(p, ec))) return p;
    }
}

std::filesystem::path newProjectDir(const std::string& kind) {
    return unusedTimeName(dataDir() / kind, "");
}

render::ProjectionCamera frontCamera(const Session& session, glm::ivec2 viewportPx) {
    if (viewportPx.x <= 0 || viewportPx.y <= 0)
        throw std::invalid_argument("model view size must be positive");
    const core::Aabb box = session.published()->bounds;
    if (box.empty()) throw std::invalid_argument("nothing to draw on: the sculpture is empty");
    const glm::dmat4 worldFromObject = session.objectPose().matrix();
    // As the window frames it: the box after the object's pose, seen from the front.
    const glm::dvec3 c = glm::dvec3(worldFromObject * glm::dvec4(0.5 * (box.min + box.max), 1));
    const glm::dvec3 half = 0.5 * (box.max - box.min);
    render::StereoDisplay d;
    const glm::dmat4 head =
        render::frameFromFront(c - half, c + half, double(viewportPx.x) / viewportPx.y, d);
    d.ipdMm = 0;
    return render::ProjectionCamera::fromEye(render::stereoEyes(head, d)[0], worldFromObject,
                                             viewportPx);
}

std::vector<std::vector<core::Vec3>> projectOnModel(const Session& session,
                                                    const std::vector<glm::dvec2>& strokePx,
                                                    const render::ProjectionCamera& camera) {
    // The mesh on show (in the windows it may lag the last edit by a rebuild).
    const core::Mesh mesh = session.published()->merged();
    if (mesh.triangleCount() == 0 || strokePx.empty()) return {};
    render::StrokeProjectionOptions o;
    // Points about a third of the finest lattice spacing on show apart: smooth at any zoom.
    o.spacingMm = std::max(0.05, session.region().spacingMm / 3);
    o.maxDepthJumpMm = std::max(o.spacingMm, 10 * session.region().spacingMm);
    std::vector<std::vector<core::Vec3>> lines;
    for (const auto& piece : render::projectStroke(mesh, camera, strokePx, o)) {
        std::vector<core::Vec3> line;
        for (const render::SurfacePoint& p : piece)
            line.push_back(p.position);
        lines.push_back(std::move(line));
    }
    return lines;
}

studio::Script loadWindowScript(const std::string& path) {
    if (devices::isRecordingFile(path))
        throw std::invalid_argument(path + ": a device recording: replay it with `vsculpt play " +
                                    path + "` (--play takes a playback script)");
    return studio::loadScript(path);
}

int playNextScriptCommand(Studio& studio, const studio::Script& script, size_t& index) {
    if (index >= script.commands.size()) return 0;
    const studio::ScriptCommand& c = script.commands[index++];
    try {
        studio.apply(c);
    } catch (const std::exception& e) {
        spdlog::error("{}:{}: {}", script.source, c.line, e.what());
        // A check that does not hold is the run's failure, as `vsculpt play` says it.
        return dynamic_cast<const studio::ExpectationError*>(&e) ? 1 : 2;
    }
    return 0;
}

void warnIfScriptUnfinished(const studio::Script& script, size_t index) {
    if (index >= script.commands.size()) return;
    spdlog::warn(
        "the window closed before the script ended: {}:{} and the {} command(s) after it were "
        "not run (a window runs one command a frame: --frames {} runs them all)",
        script.source, script.commands[index].line, script.commands.size() - index - 1,
        script.commands.size() + 1);
}

void installProjector(Studio& studio) {
    studio.setSurfaceProjector(
        [](const Session& s, const std::vector<glm::dvec2>& px, glm::ivec2 viewport) {
            return projectOnModel(s, px, frontCamera(s, viewport));
        });
}

namespace {

// What every studio a rig opens gets: the model-line projector and, for the windows, meshing
// on the mesher thread.
void setUpStudio(Studio& studio, const RigOptions& options) {
    if (options.asyncMeshing) {
        studio.setAsyncMeshing(true);
        // A smooth stroke's pen-lift estimate too: the frame never waits for it.
        studio.setAsyncStrokeFinish(true);
    }
    installProjector(studio);
}

}  // namespace

Rig::Rig(const core::SculptConfig& cfg, const RigOptions& options)
    : mConfig(cfg), mOptions(options) {
    switch (options.project) {
        case ProjectChoice::None:
            mStudio = std::make_unique<Studio>(cfg);
            setUpStudio(*mStudio, mOptions);
            break;
        case ProjectChoice::Given:
            openStudio(options.projectDir);
            break;
        case ProjectChoice::Autosave: {
            // The last project, unless it cannot be opened (open in another vsculpt, damaged
            // beyond recovery): then a new one, so the session always has somewhere to save.
            if (const auto last = lastProject()) {
                try {
                    openStudio(*last);
                } catch (const std::exception& e) {
                    spdlog::warn("the last project cannot be opened: {}", e.what());
                }
            } else if (const auto gone = lastProjectRecorded()) {
                // Moved, renamed or deleted: say so, or the user thinks the work is lost when
                // it is only elsewhere (found by QA: a new empty project opened in silence).
                // The file's bytes are shown escaped: it may hold anything (found by QA: a
                // terminal escape sequence reached the terminal raw).
                std::error_code ec;
                const bool folder = std::filesystem::is_directory(*gone, ec);
                spdlog::warn(
                    "the last project, {}, {}; starting a new one. Open a moved "
                    "project with --project DIR",
                    core::printableText(gone->string(), 300),
                    folder ? "holds no project (no snapshot.vsnap)"
                           : "is no longer there (moved or deleted?)");
            }
            if (!mStudio) openStudio(newProjectDir("autosave"));
            break;
        }
    }
    if (mStudio->session().projectDir() && options.mode == ProjectMode::ReadWrite) {
        if (options.project == ProjectChoice::Autosave)
            rememberLastProject(*mStudio->session().projectDir());
        else if (options.rememberRecent)  // --project DIR: recent, but not what opens next
            rememberRecentProject(*mStudio->session().projectDir());
    }
    if (options.liveDevices) mLive = std::make_unique<LiveDevices>(cfg.devices);
    rebuildInput();
}

Rig::~Rig() = default;

void Rig::openStudio(const std::filesystem::path& dir) {
    mStudio = Studio::openProject(dir, mConfig, mOptions.mode);
    setUpStudio(*mStudio, mOptions);
    restoreViewState();
}

std::optional<std::string> Rig::restoreViewState() {
    const auto& dir = mStudio->session().projectDir();
    if (!dir) return std::nullopt;
    if (!mOptions.restoreViewState) {
        if (mOptions.keepViewState && std::filesystem::exists(studio::viewStatePath(*dir)))
            spdlog::info(
                "{} is not read: a --play script or a --record starts from the "
                "default tool and view, as `vsculpt play` does",
                studio::viewStatePath(*dir).string());
        return std::nullopt;
    }
    const studio::ViewState opened = studio::viewStateOf(mStudio->session());
    std::string why;
    try {
        if (const auto v = studio::readViewState(*dir)) studio::applyViewState(*mStudio, *v);
        return std::nullopt;
    } catch (const studio::SessionError& e) {
        // The file's values are each in range (readViewState); what the session can still
        // refuse is a size this config's zoom does not offer (found by QA: the warning named
        // neither the file nor the field, as if the user had just asked for it).
        why = studio::viewStatePath(*dir).string() + ": field 'size': " + e.what();
    } catch (const std::exception& e) {
        why = e.what();
    }
    // Only the view is lost: the clay and its history are in the snapshot and journal. Half a
    // view (a pose without its zoom) would mislead more than none.
    studio::applyViewState(*mStudio, opened);
    why += "; starting at the default tool and view";
    mStudio->addRecoveryWarning(why);
    return why;
}

void Rig::keepViewState() const {
    const Session& s = mStudio->session();
    if (!mOptions.keepViewState || !s.projectDir() || s.readOnly()) return;
    try {
        studio::writeViewState(*s.projectDir(), studio::viewStateOf(s));
    } catch (const std::exception& e) {
        spdlog::warn("{}: the tool and view are not kept (the work is)", e.what());
    }
}

DeviceInput& Rig::replayDevices(std::vector<devices::DeviceRule> rules) {
    mDevices = std::make_unique<DeviceInput>(mConfig.devices, std::move(rules), *mInteraction,
                                             *mStudio, mConfig.render.xr);
    return *mDevices;
}

void Rig::pumpDevices() {
    if (!mLive) return;
    try {
        mLive->pump([&](const devices::DeviceEvent& e) {
            if (e.kind == devices::DeviceEventKind::Arrived ||
                e.kind == devices::DeviceEventKind::Left)
                spdlog::info(
                    "{} {}", e.device,
                    e.kind == devices::DeviceEventKind::Arrived ? "connected" : "disconnected");
            mDevices->handle(e);
        });
        mLive->send(mDevices->takeOutput());
    } catch (const std::logic_error&) {
        throw;  // a broken invariant is a bug, not a device failure
    } catch (const std::exception& e) {
        spdlog::warn("{}", e.what());
    }
}

std::string Rig::projectSummary() const {
    const Session& s = mStudio->session();
    if (!s.projectDir()) return "no project: nothing is saved (use --project DIR)";
    std::ostringstream o;
    o << "project " << s.projectDir()->string();
    if (s.readOnly()) o << " (read-only)";
    if (s.recoveredEdits() > 0)
        o << ": recovered " << s.recoveredEdits()
          << " edit(s) from the journal since the last save";
    return o.str();
}

std::string Rig::recoveryMessage() const {
    const Session& s = mStudio->session();
    std::string m;
    if (s.recoveredEdits() > 0)
        m = "recovered " + std::to_string(s.recoveredEdits()) + " edit(s); F8 starts a new project";
    if (const std::string& w = s.recoveryWarning(); !w.empty()) {
        // Its first line names what was lost and where the damaged file is kept.
        m += (m.empty() ? "" : "; ") + std::string("warning: ") + w.substr(0, w.find('\n'));
    }
    return m;
}

std::string Rig::save() {
    if (!mStudio->saveInBackground()) return "nothing saved: no project";
    keepViewState();
    return "saving " + mStudio->session().projectDir()->string() + "...";
}

std::string Rig::saveNow() {
    // The studio is about to be replaced: an import asked for lands in it, and the snapshot
    // is written before it goes, and said.
    pollImport(true);
    pollSave(true);
    mStudio->save();
    keepViewState();
    return "saved " + mStudio->session().projectDir()->string();
}

std::optional<std::string> Rig::pollSave(bool wait) {
    return mStudio->pollSave(wait);  // logged by the session
}

std::optional<std::string> Rig::pollImport(bool wait) {
    bool failed = false;
    std::optional<std::string> said = mStudio->pollImport(wait, &failed);
    if (said) failed ? spdlog::warn("{}", *said) : spdlog::info("{}", *said);
    return said;
}

std::optional<std::string> Rig::pollBackgroundWork(bool wait) {
    // A stroke whose pen-lift estimate is done becomes a step first
    // (Session::setAsyncStrokeFinish), then the import: once in, the save and export that
    // follow hold them. (The save and the export log their own outcomes.)
    std::optional<std::string> said;
    auto join = [&](const std::optional<std::string>& done) {
        if (done) said = said ? *said + "; " + *done : *done;
    };
    try {
        mStudio->pollStrokeFinish(wait);
    } catch (const std::exception& e) {
        join(std::string("the stroke was not kept: ") + e.what());
        spdlog::warn("{}", *said);
    }
    for (std::optional<std::string> done : {pollImport(wait), pollSave(wait), pollExport(wait)})
        join(done);
    return said;
}

void Rig::close() {
    // An export or save asked for is written before the window goes.
    pollBackgroundWork(true);
    mStudio->endStroke();
    // Also when nothing was sculpted: turning the piece or zooming in is worth finding again.
    keepViewState();
    if (!mStudio->session().hasJournaledEdits()) return;
    try {
        mStudio->save();
        spdlog::info("saved {}", mStudio->session().projectDir()->string());
    } catch (const std::exception& e) {
        spdlog::warn("closing without a new snapshot ({}); the journal keeps every edit", e.what());
    }
}

std::string Rig::saveAs(const std::filesystem::path& dir) {
    if (std::filesystem::exists(dir) && !std::filesystem::is_empty(dir))
        throw core::ProjectError(dir.string() + ": save as needs a new or empty folder");
    // Written from memory, not by saving the old project and copying it (found by QA: on a
    // full disk the old project's save failed and so did save as, the way out of it). The old
    // project keeps its journal, which holds every edit; a scratch session gets a project.
    pollImport(true);
    mStudio->saveCopyTo(dir);
    // "Continuing there": with the tool as it was, not the defaults (found by QA: the next
    // stroke came out unmirrored at another size).
    const studio::ViewState was = studio::viewStateOf(mStudio->session());
    mDevices.reset();
    mInteraction.reset();
    mStudio.reset();  // unlocks the old project
    openStudio(dir);
    studio::applyViewState(*mStudio, was);
    keepViewState();
    rebuildInput();
    rememberLastProject(dir);
    return "saved as " + dir.string() + " (continuing there)";
}

void Rig::rebuildInput() {
    mInteraction = std::make_unique<Interaction>(*mStudio, mOptions.alwaysEngaged);
    if (mLive)
        mDevices =
            std::make_unique<DeviceInput>(mConfig.devices, mLive->rules(), *mInteraction, *mStudio);
}

std::string Rig::newProject() {
    std::string saved;
    if (mStudio->session().projectDir() && !mStudio->session().readOnly()) saved = saveNow() + "; ";
    const std::filesystem::path dir = newProjectDir("autosave");
    mDevices.reset();
    mInteraction.reset();
    mStudio.reset();
    openStudio(dir);
    rebuildInput();
    rememberLastProject(dir);
    return saved + "new project " + dir.string();
}

bool Rig::handles(const std::string& action) {
    return action == "save" || action == "save_as" || action == "export" || action == "new_project";
}

std::string Rig::openProject(const std::filesystem::path& dir) {
    const auto& current = mStudio->session().projectDir();
    std::error_code ec;
    if (current && std::filesystem::equivalent(*current, dir, ec))
        return "already open: " + dir.string();
    if (!std::filesystem::exists(core::snapshotPath(dir), ec))
        throw core::ProjectError(dir.string() + ": no project there (no snapshot)");
    // Opened (and locked) before anything changes here: a refusal leaves this session as it is.
    std::unique_ptr<Studio> next = Studio::openProject(dir, mConfig, mOptions.mode);
    std::string saved;
    if (current && !mStudio->session().readOnly()) saved = saveNow() + "; ";
    mDevices.reset();
    mInteraction.reset();
    mStudio = std::move(next);
    setUpStudio(*mStudio, mOptions);
    const std::optional<std::string> viewLost = restoreViewState();
    if (viewLost) spdlog::warn("{}", *viewLost);
    rebuildInput();
    rememberLastProject(dir);
    return saved + "opened " + dir.string() + (viewLost ? "; warning: " + *viewLost : "");
}

std::filesystem::path Rig::defaultExportPath() const {
    const auto& dir = mStudio->session().projectDir();
    const std::filesystem::path folder = dir ? *dir / "exports" : dataDir() / "exports";
    // Named after the time, and never after a file already there: two exports within a
    // second each keep their own file.
    return unusedTimeName(folder, ".glb");
}

std::string Rig::projectAction(const std::string& action) {
    if (action == "save") return save();
    if (action == "save_as") return saveAs(newProjectDir("projects"));
    if (action == "new_project") return newProject();
    if (action == "export") return exportTo(defaultExportPath());
    throw std::logic_error("not a project action: " + action);
}

std::string Rig::exportTo(const std::filesystem::path& path, const core::ExportOptions& options) {
    if (mExport && !mExport->done())
        throw std::runtime_error("still writing " + mExport->path().string() +
                                 ": export again once it is done");
    // Whatever an earlier export did was already said (pollExport) or is said now.
    pollExport();
    // Refusals come before anything starts, while the dialog can still show them.
    (void)core::exportFrame(path, options);
    if (!path.parent_path().empty()) std::filesystem::create_directories(path.parent_path());
    core::ensureWritable(path);
    // A stroke ended but not yet completed is in the file (Session::setAsyncStrokeFinish).
    mStudio->pollStrokeFinish(true);
    const Session& s = mStudio->session();
    // The spacing that keeps the finest detail sculpted (the export runs beside the frame,
    // so a finer grid costs the sculptor nothing but the wait for the file).
    const ExportDetail detail =
        exportDetail(s, core::zoomSpacing(mConfig, s.sculpture().levels(), 1));
    const double spacing = detail.keepingMm;
    // The sketch's curves too, for a .dxf, as `play --out` writes them (found by QA: the sketch
    // window's .dxf held the sculpture only).
    mExport = std::make_unique<ExportInBackground>(s.sculpture().clone(), spacing, path, options,
                                                   mStudio->curvesInObjectSpace());
    char said[200];
    if (detail.finestSize == 0)
        std::snprintf(said, sizeof said, " at %.3g mm...", spacing);
    else if (!detail.capped)
        std::snprintf(said, sizeof said, " at %.3g mm (the size-%d detail's spacing)...", spacing,
                      detail.finestSize);
    else
        std::snprintf(said, sizeof said,
                      " at %.3g mm, the finest its grid's %d cells per axis allow: coarser than "
                      "the size-%d detail's %.3g mm, which it loses...",
                      spacing, Session::kWholeMeshMaxCells, detail.finestSize, detail.detailMm);
    return "exporting " + path.string() + said;
}

std::optional<std::string> Rig::pollExport(bool wait) {
    if (!mExport || (!wait && !mExport->done())) return std::nullopt;
    bool failed = false;
    std::string outcome = mExport->wait(&failed);
    mExport.reset();
    if (failed)
        spdlog::warn("{}", outcome);
    else
        spdlog::info("{}", outcome);
    return outcome;
}

}  // namespace vsculpt::app
