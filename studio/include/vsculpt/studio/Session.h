// SPDX-License-Identifier: MIT
/// @file Session.h
/// @brief A sculpting session: the sculpture, its polygonized view at the current zoom,
/// the tool state, undo history and (optionally) the crash-safe project it writes to.
/// Applications change it only through a Studio (Studio.h), which keeps the one undo
/// timeline; the session's own mutators are for the studio and for tests.
#pragma once

#include "vsculpt/core/AsyncMesher.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/core/History.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/core/MeshChunks.h"
#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/ProjectLock.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/studio/Script.h"

#include <array>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace vsculpt::studio {

/// A refused operation (size not offered at this zoom, stroke with the select tool, a tool
/// sample the lattices cannot hold, ...): the user's input, not a bug. Invariant failures
/// are std::logic_error and are never reported as refusals.
class SessionError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A script's `expect` that does not hold (the clay is not there, or is where it should not
/// be): the run's failure, not a bad input (`vsculpt play` exits 1).
class ExpectationError : public SessionError {
  public:
    using SessionError::SessionError;
};

/// The field at a point, as a script's `probe` and `expect` read it (object space, mm).
struct FieldReading {
    core::Vec3 objectPos{0.0};
    double value = 0;  ///< f - c: positive inside the clay
    core::Vec3 gradient{0.0};
    /// Only when asked for (readField's `findSurface`): the nearest surface found along 28 rays
    /// (the 26 directions to a cube's neighbours and both ways along the gradient), each marched in
    /// 0.25 mm steps up to kSurfaceSearchMm and bisected: exact along its ray, so an upper bound on
    /// the distance to the surface (within a few per cent of it for a surface curved less than the
    /// rays are apart).
    std::optional<double> surfaceMm;
    core::Vec3 surfaceDirection{0.0};  ///< the ray it was found along (unit)
    static constexpr double kSurfaceSearchMm = 200;
    bool inside() const { return value > 0; }
    /// "(0, 0, 37): outside the clay (f - c = -0.04826); the surface 1.26 mm away towards
    /// (0.00, 0.00, -1.00); outward normal (0.00, 0.00, 1.00)", the normal the field's (out of
    /// the clay: against its gradient).
    std::string describe() const;
};

/// How a project is opened. ReadOnly never writes to the folder (no journal truncation, no
/// snapshot, no lock file; works on read-only media): `vsculpt render PROJECT`.
enum class ProjectMode { ReadWrite, ReadOnly };

/// The sections of a config that belong to the machine, not the sculpture (key bindings,
/// display and lens, USB tables, tracker calibration): a project does not store them and a
/// reopened project takes them from the config in use.
void takeMachineSettings(core::SculptConfig& projectConfig, const core::SculptConfig& machine);
/// The config as a project stores it: without the machine's sections.
std::string projectConfigJson(const core::SculptConfig& cfg);

class Session {
  public:
    /// A session without a project (nothing is written to disk).
    explicit Session(const core::SculptConfig& cfg);
    /// Opens the project in `dir`, or creates it with `cfg` when the folder holds none (not in
    /// ReadOnly mode: then a missing project is a ProjectError). The sculpture's settings
    /// come from the project, the machine's (takeMachineSettings) from `cfg`. Recovers the
    /// journal tail (and a damaged snapshot from its backup); what was dropped is in
    /// recoveryWarning(). ReadWrite locks the project while the session lives: a second
    /// process gets a ProjectError naming the holder.
    static std::unique_ptr<Session> openProject(const std::filesystem::path& dir,
                                                const core::SculptConfig& cfg,
                                                ProjectMode mode = ProjectMode::ReadWrite);
    ~Session();

    // Tool state ------------------------------------------------------------------------
    /// Changing tool, size or zoom ends a stroke in progress.
    void setTool(ToolKind tool) {
        endStroke();
        mTool = tool;
    }
    ToolKind tool() const { return mTool; }
    /// Mirror symmetry for the following strokes (core::MirrorAxis: the object-space plane
    /// x = 0, y = 0 or z = 0); changing it ends a stroke in progress.
    void setMirror(core::MirrorAxis axis) {
        endStroke();
        mMirror = axis;
    }
    core::MirrorAxis mirror() const { return mMirror; }
    /// Throws SessionError when level is not offered at the current zoom.
    void setSize(int level);
    int size() const { return mSize; }
    /// Zoom level z (1..5) centred on an object-space point (ignored at zoom 1). If the
    /// current size is not offered at the new zoom, the nearest offered size is taken.
    /// Throws SessionError, changing nothing, for a level outside 1..5 or a centre that is not
    /// a usable point (core::isUsablePoint: a device's garbage pose, a script's 1e300).
    void setZoom(int zoom, const core::Vec3& center);
    int zoom() const { return mZoom; }
    /// The object-space point setZoom centred the region on (the sphere's centre at zoom 1).
    const core::Vec3& zoomCentre() const { return mZoomCenter; }
    void setObjectPose(const core::RigidTransform& worldFromObject);
    const core::RigidTransform& objectPose() const { return mWorldFromObject; }

    /// Runs one playback-script command. Returns true when it changed the sculpture (a
    /// stroke, or an undo/redo that had something to do). Errors as the methods below.
    bool apply(const ScriptCommand& command);
    /// The field at a point (in world space when `world`, through the object's pose), with
    /// every ended stroke completed first (pollStrokeFinish); `findSurface` also searches for
    /// the nearest surface (FieldReading::surfaceMm: a few thousand evaluations more).
    FieldReading readField(const core::Vec3& point, bool world, bool findSurface);

    // Edits -----------------------------------------------------------------------------
    /// One stroke (one undo step) through the given points, in world space when `world`.
    /// Every sample updates the mesh; the stroke is journaled (and flushed) at its end.
    void stroke(const std::vector<core::Vec3>& points, bool world);

    /// The same, one sample at a time (interactive tools): begin, samples, end. A sample the
    /// lattices cannot hold cancels the whole stroke and rethrows. end() journals it.
    void beginStroke();
    void strokeSample(const core::Vec3& point, bool world);
    void endStroke();
    bool inStroke() const { return mStroke != nullptr; }
    /// A smooth stroke's pen-lift volume estimate (core::StrokeBuilder::beginFinish; 12 ms on
    /// 2 cores over a bumpy arm) off the caller's thread, so the frame does not wait for it:
    /// endStroke() then returns once the estimate has started, the clay the samples previewed
    /// stays on show, and the stroke is completed (its corrected weights written and meshed,
    /// journaled, made an undo step) by pollStrokeFinish() once the estimate is done, or by
    /// the next call that begins a stroke, edits, undoes, saves or closes, which waits for it.
    /// Off (the default: playback, tests), endStroke() completes every stroke before it
    /// returns. The clay and the journal are the same bits either way. The windows and the
    /// headset turn it on with async meshing. Turning it off completes a pending stroke.
    void setAsyncStrokeFinish(bool on);
    bool asyncStrokeFinish() const { return mAsyncFinish; }
    /// Completes a stroke whose estimate is done; `wait`: waits for it. Returns whether a
    /// stroke was completed. Errors as endStroke() (the stroke is then taken back).
    bool pollStrokeFinish(bool wait = false);
    /// A stroke has ended and its estimate is still to be completed (pollStrokeFinish).
    bool strokeFinishing() const { return mFinishing != nullptr; }
    /// f - c at `objectPos` as it was before the stroke in progress (the live field when
    /// none is): positive inside that clay (core::StrokeBuilder::preStrokeValueAt).
    double preStrokeValueAt(const core::Vec3& objectPos) const;
    /// Adds a closed solid (object space, mm; PlaceSolid.h) as clay on one level's lattice:
    /// one undo step, journaled. @param level 1..7, or 0 to choose from the solid's size.
    /// Returns the level used. Throws std::invalid_argument for a bad mesh or level and
    /// SessionError when the solid is too large to journal; the sculpture is unchanged then.
    /// @param replaceLast the last step is a solid (else SessionError): this step takes its
    /// clay away and adds the new solid, so undoing it brings the previous solid back
    /// (regenerating a solid after its sketch was edited).
    int addSolid(const core::Mesh& solid, int level = 0, bool replaceLast = false);
    /// addSolid for a solid placed on a copy of this sculpture (core::placeSolid on
    /// Sculpture::clone(), as Studio's import in the background does): sets the copy's
    /// after-states here (core::replaySolid), one step, journaled. The same clay as addSolid
    /// only when the copy was taken from the sculpture as it is now (the caller compares
    /// SkeletonStore::writeCount()). Errors as addSolid.
    int addPlacedSolid(int level, std::span<const core::SkeletonChange> placedChanges);
    bool undo();
    bool redo();
    /// Writes a snapshot and starts a new journal, keeping the previous pair as a backup
    /// (projects only; no-op otherwise). Throws SessionError for a read-only project.
    void save();
    /// Writes this session's sculpture and history, from memory, as the snapshot of a new
    /// project in `dir` (created; it must not hold a project): save as. The session's own
    /// project is not written, so a full disk or a read-only folder there does not stop it,
    /// and a scratch session's work gets a project. The session itself goes on as it was.
    void saveCopyTo(const std::filesystem::path& dir);
    /// Saves as save() does, without the caller waiting for the file (F5 in the windows): the
    /// snapshot holds the clay and history as they are now (copies: Sculpture::clone), written
    /// on a thread of its own while editing goes on, every edit journaled as always. pollSave()
    /// finishes it. Returns false without a project (nothing to save). Throws SessionError for
    /// a read-only project or while an earlier background save is still being written.
    bool saveInBackground();
    /// Finishes a background save once its snapshot is written: the journal restarts holding
    /// the edits made meanwhile. Returns what happened, for the user: "saved DIR", or why it
    /// failed (the journal keeps every edit either way); nothing while the file is being written
    /// or when no save was started. `wait` waits for it; `failed` tells whether it failed (or
    /// the journal did not restart). Also logged (a failure as a warning). save() and the
    /// destructor wait too.
    std::optional<std::string> pollSave(bool wait = false, bool* failed = nullptr);
    /// A background save is under way (its outcome not yet taken by pollSave).
    bool saving() const { return mSaving != nullptr; }
    bool readOnly() const { return mReadOnly; }
    /// A writable project whose journal holds edits its snapshot does not: what the windows
    /// save when they close, so that reopening reads a snapshot instead of replaying every
    /// stroke through the placement rules of the version that opens it.
    bool hasJournaledEdits() const {
        return mProjectDir && !mReadOnly && mSequence != mSnapshotSequence;
    }

    /// `--check`: empty when the incremental mesh equals a full rebuild (in async mode: once
    /// the mesher has caught up with every edit).
    std::string verifyMesh() const;

    // Meshing ---------------------------------------------------------------------------
    /// Meshing on its own thread (core::AsyncMesher, docs/async-mesher.md): an edit returns
    /// once placed and journaled, the mesher thread re-polygonizes, the windows draw
    /// published(). Off (the default), every edit updates view() before it returns (playback,
    /// tests, exports). Switching keeps the mesh.
    void setAsyncMeshing(bool on);
    bool asyncMeshing() const { return mMesher != nullptr; }
    /// Without async meshing: edits only mark what they dirty, and the mesh is brought up to
    /// date when something asks for it (view(), published(), verifyMesh()), in one rebuild of
    /// every block dirtied since (the same mesh: partial == full). For headless runs that
    /// look at the mesh once, at the end (`vsculpt play` without --check or --stats): a
    /// sample then costs its placement only. Off: every edit updates view() before it
    /// returns. Ignored while async meshing is on.
    void setDeferredMeshing(bool on);
    bool deferredMeshing() const { return mDeferred; }
    /// What to draw (never null). Async: the mesher's last published set, which may lag the
    /// edits by a rebuild (or show a coarse preview after a zoom change). Otherwise view()'s
    /// chunks, current with every edit.
    std::shared_ptr<const core::MeshChunks> published() const;
    /// The grid region of the current zoom (in async mode, the one being built).
    const core::GridRegion& region() const { return mRegion; }
    /// Async mode: waits until published() holds every edit made so far. No-op otherwise.
    void waitForMesh() const;
    /// Async mode: ms from each edit to the first published set holding it, since the last
    /// call (docs/benchmarks.md). Empty otherwise.
    std::vector<double> takePublishDelaysMs();

    // Results ---------------------------------------------------------------------------
    const core::Sculpture& sculpture() const { return *mSculpture; }
    const core::History& history() const { return mHistory; }
    /// The live polygonizer: only without async meshing (std::logic_error otherwise; use
    /// published()).
    const core::Polygonizer& view() const;
    /// Wall time of each tool sample (placement + mesh update), ms.
    const std::vector<double>& sampleMs() const { return mSampleMs; }
    const std::string& recoveryWarning() const { return mRecoveryWarning; }
    /// Adds a line to recoveryWarning(): what opening the project had to drop or set aside
    /// (the studio's sketch.json too), shown wherever the journal's recovery is.
    void addRecoveryWarning(const std::string& line) {
        mRecoveryWarning += (mRecoveryWarning.empty() ? "" : "\n") + line;
    }
    /// The project folder, when the session has one.
    const std::optional<std::filesystem::path>& projectDir() const { return mProjectDir; }
    size_t recoveredEdits() const { return mRecovered; }
    /// Edits (strokes, undos, redos) recorded in the project over its life: the sequence
    /// number of the last one. 0 without a project.
    uint64_t editSequence() const { return mSequence; }

    /// The most cells per axis wholeMesh's grid may have.
    static constexpr int kWholeMeshMaxCells = 1024;
    /// The whole sculpture polygonized at `spacingMm` (0: the zoom-1 spacing), for exports
    /// and statistics: wholeMeshOf(sculpture(), spacingMm).
    core::Mesh wholeMesh(double spacingMm = 0) const;

  private:
    Session(const core::SculptConfig& cfg, bool);
    void rebuildView();
    void journal(const core::JournalRecord& r);
    /// The end of addSolid and addPlacedSolid: `placed` is on the sculpture; checks its size,
    /// updates the mesh, journals it and makes it one undo step (undoing it all on failure).
    int commitSolid(core::SolidPlacement placed, const core::Aabb& takenBox);
    /// The mesh follows an edit: f changed within `radius` of the points, or in the box.
    /// `focus`: where the tool is (the async mesher rebuilds around it first).
    void meshChanged(std::span<const core::Vec3> points, double radius,
                     std::optional<core::AsyncMesher::Focus> focus = std::nullopt);
    void meshChanged(const core::Aabb& box);
    /// Deferred meshing: an edit dirtied these blocks of mView (sorted).
    void markDirty(std::vector<std::array<int, 3>> blocks);
    /// A stroke's edit (a sample, or its held-back changes at the end) reaches the mesh; the
    /// time since t0 (placement included) is recorded as a sample time.
    void strokeEdited(const core::EditResult& r, std::chrono::steady_clock::time_point t0,
                      std::optional<core::AsyncMesher::Focus> focus = std::nullopt);
    /// Takes the stroke in progress back (a refused sample, an error): nothing is journaled.
    void cancelStroke();
    /// The end of endStroke(): finishes mStroke (the estimate done or made now), meshes,
    /// journals it and makes it an undo step.
    void completeStroke();

    core::SculptConfig mConfig;
    std::unique_ptr<core::Sculpture> mSculpture;
    core::GridRegion mRegion;
    /// The mesh is brought up to date (deferred meshing) before view() and published().
    void catchUpView() const;
    mutable std::unique_ptr<core::Polygonizer> mView;  // without async meshing
    std::unique_ptr<core::AsyncMesher> mMesher;        // with it
    std::vector<core::SkeletonWrite> mWrites;          // writes not yet given to the mesher or view
    mutable uint64_t mViewChanges = 0;                 // sync: view() updates so far
    bool mDeferred = false;
    // Deferred meshing: blocks of mView dirtied since it was last brought up to date (sorted),
    // or the whole region when it changed (zoom).
    mutable std::vector<std::array<int, 3>> mDirtyBlocks;
    mutable bool mViewRegionStale = false;
    mutable std::shared_ptr<const core::MeshChunks> mSyncPublished;
    mutable uint64_t mSyncPublishedAt = ~uint64_t(0);
    core::History mHistory;
    ToolKind mTool = ToolKind::Add;
    core::MirrorAxis mMirror = core::MirrorAxis::None;
    int mSize = 6;
    int mZoom = 1;
    core::Vec3 mZoomCenter{0.0};
    core::RigidTransform mWorldFromObject;
    bool mWorldSpace = false;  // script `space`: stroke points are world coordinates
    std::vector<double> mSampleMs;
    std::unique_ptr<core::StrokeBuilder> mStroke;  // the stroke in progress
    core::StrokeRecord mStrokeRecord;
    bool mAsyncFinish = false;
    struct PendingFinish;  // an ended stroke whose estimate runs on a thread of its own
    std::unique_ptr<PendingFinish> mFinishing;

    std::optional<std::filesystem::path> mProjectDir;
    std::unique_ptr<core::ProjectLock> mLock;
    std::unique_ptr<core::JournalWriter> mJournal;
    bool mReadOnly = false;
    uint64_t mSequence = 0;
    uint64_t mSnapshotSequence = 0;  // the last edit the project's snapshot holds
    struct BackgroundSave;
    std::unique_ptr<BackgroundSave> mSaving;  // saveInBackground's, until pollSave takes it
    /// pollSave's work once the thread is done: joins it, restarts the journal.
    std::string finishSave(bool& failed);
    std::string mRecoveryWarning;
    size_t mRecovered = 0;
};

/// The whole of `sculpture` polygonized at `spacingMm` (0: its zoom-1 spacing) to its
/// config's export root tolerance, for exports and statistics; reads nothing but `sculpture`
/// (an export thread runs it on a snapshot, Sculpture::clone), its parallel loops on
/// `workers` when given (oneTBB otherwise). Throws SessionError for a spacing that is not
/// finite and positive, or when the grid would exceed Session::kWholeMeshMaxCells per axis.
core::Mesh wholeMeshOf(const core::Sculpture& sculpture, double spacingMm = 0,
                       core::WorkerPool* workers = nullptr);

}  // namespace vsculpt::studio
