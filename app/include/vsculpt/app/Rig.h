// SPDX-License-Identifier: MIT
/// @file Rig.h
/// @brief What every session of the program is built from, built one way: the studio (with
/// its project), the interaction state machine, and the devices mapped onto them. The
/// sculpting window, the sketch window and `vsculpt play` all get theirs here, so a session
/// saves, recovers and sculpts the same whichever front end runs it.
#pragma once

#include "vsculpt/app/DeviceInput.h"
#include "vsculpt/app/ExportInBackground.h"
#include "vsculpt/app/LiveDevices.h"
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/render/ProjectStroke.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/Script.h"
#include "vsculpt/studio/Studio.h"

#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vsculpt::app {

/// Where a window's work goes when no --project is given.
enum class ProjectChoice {
    None,      ///< nothing saved (play without --project)
    Given,     ///< RigOptions::projectDir
    Autosave,  ///< the last project, or a new autosave project (windows' default)
};

struct RigOptions {
    ProjectChoice project = ProjectChoice::None;
    std::filesystem::path projectDir;  ///< ProjectChoice::Given
    studio::ProjectMode mode = studio::ProjectMode::ReadWrite;
    bool liveDevices = false;    ///< open the connected trackers, 3D mice, tablets, headsets
    bool alwaysEngaged = false;  ///< the thesis's always-engaged pen (Interaction.h)
    /// A given project goes on the recent projects list (the windows; not `vsculpt play`).
    bool rememberRecent = false;
    /// Mesh on the mesher thread (Session::setAsyncMeshing): the windows, whose frames must
    /// never wait for a rebuild. Playback meshes every edit before the next (the default).
    bool asyncMeshing = false;
    /// The windows: the tool, size, zoom, mirror and the sculpture's pose are written to the
    /// project's view.json on save, close and project switch (studio/ViewState.h)...
    bool keepViewState = false;
    /// ...and brought back from it when a project opens. Not for `vsculpt play`, nor for a
    /// window's --play script or a headset's --record: those start from the defaults, so they
    /// play (and replay) the same whoever left the project last.
    bool restoreViewState = false;
};

/// A window's rig: `projectDir` when given, no project with `noProject`, otherwise the last
/// project or a new autosave project (ProjectChoice::Autosave). `scripted`: the session runs a
/// --play script or records (--record), so it starts from the default tool and view.
RigOptions windowRigOptions(const std::string& projectDir, bool noProject, bool liveDevices,
                            bool scripted = false);

/// The folder projects live in by default: $XDG_DATA_HOME/vsculpt (~/.local/share/vsculpt).
std::filesystem::path dataDir();
/// The project the windows opened last, when it still exists.
std::optional<std::filesystem::path> lastProject();
/// The project the windows opened last as recorded, whether it still exists or not.
std::optional<std::filesystem::path> lastProjectRecorded();
/// Remembers `dir` as the last project and at the top of the recent projects (best effort:
/// a failure is only reported).
void rememberLastProject(const std::filesystem::path& dir);
/// Puts `dir` at the top of the recent projects without making it the last project (a window
/// opened with --project DIR; best effort: a failure is only reported).
void rememberRecentProject(const std::filesystem::path& dir);
/// The recent projects, most recent first (dataDir()/recent-projects, one absolute path a
/// line), only those whose folder still holds a project.
std::vector<std::filesystem::path> recentProjects();
/// `list` with `dir` moved (or added) to the front and cut to `max` entries.
std::vector<std::filesystem::path> withRecentProject(std::vector<std::filesystem::path> list,
                                                     const std::filesystem::path& dir,
                                                     size_t max = 10);
/// `folder`/YYYY-MM-DD-HHMMSS`extension` at the local time, with -1, -2, ... before the
/// extension while that name is taken.
std::filesystem::path unusedTimeName(const std::filesystem::path& folder,
                                     const std::string& extension);
/// A new, unused folder under dataDir()/`kind` named after the local time.
std::filesystem::path newProjectDir(const std::string& kind);

/// The camera of a `viewportPx` view framing the sculpture's current mesh from the front (the
/// window's camera at the start): what `model-line` script strokes are drawn over.
render::ProjectionCamera frontCamera(const studio::Session& session, glm::ivec2 viewportPx);
/// A stroke drawn over `camera`'s view projected onto the mesh on show with the ray tracer:
/// the pieces on the surface (object mm), points a third of the view's grid spacing apart.
std::vector<std::vector<core::Vec3>> projectOnModel(const studio::Session& session,
                                                    const std::vector<glm::dvec2>& strokePx,
                                                    const render::ProjectionCamera& camera);

/// Lets `studio` run `model-line` script commands: projectOnModel over frontCamera.
void installProjector(studio::Studio& studio);

/// A window's `--play` script runs one command per frame: applies the command at `index`
/// (if any is left) and advances it. On failure logs "FILE:LINE: why" and returns false;
/// the window then ends with exit code 2.
/// A window's --play script (studio::loadScript); a device recording given instead is refused
/// saying to replay it with `vsculpt play` (std::invalid_argument), not "unknown command".
studio::Script loadWindowScript(const std::string& path);

/// Runs a window's next --play command (one a frame). Returns the exit code the window ends with
/// when the command failed (logged with the script's file and line): 1 for an `expect` that
/// does not hold, 2 for a line the session refuses; 0 when it ran (or none is left).
int playNextScriptCommand(studio::Studio& studio, const studio::Script& script, size_t& index);
/// A window's run ended (--frames, its close box, a signal) before its --play script did:
/// warns naming the line it stopped at, so a partial run is not taken for the whole.
void warnIfScriptUnfinished(const studio::Script& script, size_t index);

class Rig {
  public:
    /// Opens the studio (and its project) and, when asked, the devices. Throws
    /// core::ProjectError (a project that cannot be opened, one open elsewhere),
    /// std::invalid_argument (a damaged sketch.json).
    Rig(const core::SculptConfig& cfg, const RigOptions& options);
    ~Rig();

    studio::Studio& studio() { return *mStudio; }
    const studio::Session& session() const { return mStudio->session(); }
    studio::Interaction& interaction() { return *mInteraction; }
    DeviceInput* devices() { return mDevices.get(); }
    /// Replayed device streams: a DeviceInput on this rig's studio for recorded rules.
    DeviceInput& replayDevices(std::vector<devices::DeviceRule> rules);

    /// Hands queued device events to the mapping; arrivals and departures are reported on
    /// the log. Device failures are reported, never thrown.
    void pumpDevices();

    /// A line for the user about the project: where it is, what was recovered.
    std::string projectSummary() const;
    /// The windows' panel line after opening: what was recovered from the journal and, when
    /// records could not be replayed, that some were lost and where the file was kept; empty
    /// when there was nothing to recover.
    std::string recoveryMessage() const;

    /// Save: a snapshot of the project (nothing to do without one), written on a thread of its
    /// own (Studio::saveInBackground) while the frame goes on; pollSave() says when it is done.
    /// Returns what was started, for the user. Throws studio::SessionError for a read-only
    /// project or while an earlier save is still being written.
    std::string save();
    /// What the save in flight did, once it is done ("saved DIR", or why not: the journal
    /// keeps every edit); nothing while it runs or without one; `wait` waits. Also logged.
    std::optional<std::string> pollSave(bool wait = false);
    /// Studio::pollStrokeFinish() (a smooth stroke whose pen-lift estimate is done becomes a
    /// step), pollImport(), pollSave() and pollExport() together (what the windows call every
    /// frame): the outcomes done, joined by "; ". `wait`: until all are done (close).
    std::optional<std::string> pollBackgroundWork(bool wait = false);
    /// What a window does as it closes: ends the stroke in flight (journaled like any other)
    /// and, when the journal holds edits the snapshot does not, writes a snapshot, so the
    /// next start reads the clay as it was instead of replaying every stroke (through the
    /// placement rules of whatever version opens it). A failed snapshot is logged as a
    /// warning: the journal still holds every edit.
    void close();
    /// Save as: the whole project copied to `dir` (a new folder) and continued there; the
    /// old project stays as it was at this moment. Returns what it did.
    std::string saveAs(const std::filesystem::path& dir);
    /// Starts exporting the whole sculpture, as it is now, to `path` (format from the
    /// extension, frame from `options`; ExportMesh.h) on its own thread: the frame goes on
    /// while it is meshed and written (pollExport() says when it is done). Returns what was
    /// started, for the user. Throws core::ExportError naming the path for a format or frame
    /// the file cannot have and file errors for a folder that cannot be made, before anything
    /// starts; std::runtime_error while an earlier export is still being written.
    std::string exportTo(const std::filesystem::path& path,
                         const core::ExportOptions& options = {});
    /// What the export in flight did, once it is done (nothing while it runs, or without
    /// one); `wait` waits for it. Also logged (a failed export as a warning). close() waits
    /// for it too.
    std::optional<std::string> pollExport(bool wait = false);
    /// Where the export key writes: exports/DATE-TIME.glb in the project (dataDir()/exports
    /// without a project).
    std::filesystem::path defaultExportPath() const;
    /// Saves this project and continues in the project in `dir` (opened and locked first: when
    /// that fails nothing changes and the error is thrown). Returns what it did.
    std::string openProject(const std::filesystem::path& dir);
    /// Saves this project and continues in a new autosave project (an empty sculpture).
    std::string newProject();
    /// The windows' project keys: "save", "save_as" (to a new folder under dataDir()/projects),
    /// "export" (a .glb in the project's exports/ folder), "new_project". Returns what was
    /// done, for the user; false from handles() for any other action.
    static bool handles(const std::string& action);
    std::string projectAction(const std::string& action);

  private:
    /// A snapshot written before returning (the studio is about to be replaced): "saved DIR".
    std::string saveNow();
    /// Studio::pollImport, its outcome logged. `wait` before the studio is saved elsewhere or
    /// replaced, so the import asked for lands in it and is not dropped with it.
    std::optional<std::string> pollImport(bool wait);
    void openStudio(const std::filesystem::path& dir);
    void rebuildInput();
    /// RigOptions::restoreViewState: the project's view.json onto the studio just opened. A
    /// file that cannot be used leaves the defaults and is returned (also a recovery warning
    /// of the session's, shown with the journal's).
    std::optional<std::string> restoreViewState();
    /// RigOptions::keepViewState: the session's tool and view to its project's view.json (a
    /// failure is a warning: it is not work).
    void keepViewState() const;

    core::SculptConfig mConfig;
    RigOptions mOptions;
    std::unique_ptr<studio::Studio> mStudio;
    std::unique_ptr<studio::Interaction> mInteraction;
    std::unique_ptr<LiveDevices> mLive;
    std::unique_ptr<DeviceInput> mDevices;
    std::unique_ptr<ExportInBackground> mExport;  // the export in flight
};

}  // namespace vsculpt::app
