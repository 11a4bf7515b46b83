// SPDX-License-Identifier: MIT
/// @file Studio.h
/// @brief The one editing entry: the session (sculpture, view, history, project journal), the
/// sketch document, and ONE undo timeline across sculpt and sketch steps
/// (docs/sketch-mode.md). Playback, the sculpting window, the sketch window, device input and
/// tests all change the sculpture through a Studio and nothing else; they read it through
/// `session()`, which is const. What a designer does in either mode is undone in the order
/// it was done, and every step reaches the timeline when it is made (nothing is polled).
///
/// Ownership: the studio owns its Session. In a project folder it writes the document and
/// the timeline to `sketch.json` (atomically) after every step, so no sketch work is lost;
/// the session journals every sculpt step before it counts as done.
#pragma once

#include "vsculpt/sketch/SketchSolid.h"
#include "vsculpt/studio/Script.h"
#include "vsculpt/studio/Session.h"
#include "vsculpt/studio/SketchDocument.h"
#include "vsculpt/studio/SketchSolids.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace vsculpt::studio {

class ImportInBackground;
class SketchFileWriter;

/// Which view a page is drawn on: how its canvas millimetres map into object space (z up;
/// SketchSolid.h). Front: canvas (x, y) -> object (x, z); side: (y, z); top: (x, y).
using SketchPlane = sketch::SketchPlane;

/// The sketch settings vsculpt uses: the seed's, except feature points refined along bent
/// strokes (featureChordRatio 0.05) and overdrawn lines averaged (lineRunningMean), which
/// converge where the seed's three points per stroke do not (docs/sketch-cleanup.md).
studio::SketchParams recommendedSketchParams();

/// Turns a stroke drawn over a `viewportPx` front view of the sculpture (pixels, origin top
/// left; framed from the front as the window starts) into polylines on the sculpture's surface
/// (object mm). The app installs one built on its ray tracer; the studio itself has no renderer.
using SurfaceProjector = std::function<std::vector<std::vector<core::Vec3>>(
    const Session& session, const std::vector<glm::dvec2>& strokePx, glm::ivec2 viewportPx)>;

class Studio {
  public:
    /// A studio without a project (nothing is written to disk).
    explicit Studio(const core::SculptConfig& cfg,
                    const SketchParams& params = recommendedSketchParams());
    /// Takes over a session (with or without a project); loads the project's `sketch.json`.
    /// A sketch.json that cannot be read (named with the file and field) costs the sketch
    /// pages, never the sculpture: the studio opens with empty pages, the file is set aside
    /// as sketch.json.damaged (core::setAsideAsDamaged; left alone in a read-only session)
    /// and the reason is added to session().recoveryWarning(). Throws std::invalid_argument
    /// only when the file cannot be set aside.
    explicit Studio(std::unique_ptr<Session> session,
                    const SketchParams& params = recommendedSketchParams());
    /// Writes the sketch file's last state (waitForSketchFile) before it goes.
    ~Studio();
    Studio(const Studio&) = delete;
    Studio& operator=(const Studio&) = delete;
    /// Opens the project in `dir` (Session::openProject: created when the folder holds none,
    /// locked while the studio lives, read-only with `mode`).
    static std::unique_ptr<Studio> openProject(
        const std::filesystem::path& dir, const core::SculptConfig& cfg,
        ProjectMode mode = ProjectMode::ReadWrite,
        const SketchParams& params = recommendedSketchParams());

    const Session& session() const { return *mSession; }
    studio::SketchDocument& document() { return mDocument; }
    const studio::SketchDocument& document() const { return mDocument; }
    studio::SketchPage& page() { return mDocument.current(); }

    /// Session::setAsyncMeshing (the windows turn it on).
    void setAsyncMeshing(bool on) { mSession->setAsyncMeshing(on); }
    /// Session::setAsyncStrokeFinish (the windows turn it on with async meshing).
    void setAsyncStrokeFinish(bool on) { mSession->setAsyncStrokeFinish(on); }
    /// Session::pollStrokeFinish; a completed stroke becomes a step of the timeline. The
    /// windows call it every frame (Rig::pollBackgroundWork).
    bool pollStrokeFinish(bool wait = false);
    /// Session::setDeferredMeshing (`vsculpt play` when nothing looks at the mesh per edit).
    void setDeferredMeshing(bool on) { mSession->setDeferredMeshing(on); }
    /// Session::takePublishDelaysMs (how far the mesh trailed the edits).
    std::vector<double> takePublishDelaysMs() { return mSession->takePublishDelaysMs(); }

    // Tool state (Session.h). Changing tool, size or zoom ends a stroke in progress.
    void setTool(ToolKind tool);
    void setMirror(core::MirrorAxis axis);
    void setSize(int level);
    void setZoom(int zoom, const core::Vec3& center);
    void setObjectPose(const core::RigidTransform& worldFromObject);

    // Sculpting: one stroke is one step of the timeline, journaled when it ends.
    void beginStroke();
    void strokeSample(const core::Vec3& point, bool world);
    void endStroke();
    void stroke(const std::vector<core::Vec3>& points, bool world);
    /// Session::addSolid as one step.
    int addSolid(const core::Mesh& solid, int level = 0);
    /// Imports a mesh file (core::importMesh: OBJ, STL, PLY, glTF; object mm, Z up after
    /// `options`) and adds it as clay: one step, journaled as the clay it made, so a project
    /// reopens without the file (docs/import.md). @param level 0: core::importLevelFor.
    /// Returns the level used. Notes (a repaired mesh, rewound triangles) go to the notice
    /// sink. Throws core::ImportError naming the file, std::invalid_argument for a solid
    /// placeSolid refuses (too fine a level); the sculpture is unchanged then.
    int importMesh(const std::filesystem::path& file, const core::ImportOptions& options = {},
                   int level = 0, core::ImportReport* report = nullptr);
    /// importMesh without the wait (the windows): the file is read, cleaned and placed on a
    /// thread of its own against a copy of the sculpture (ImportInBackground.h), while the
    /// frame and sculpting go on; pollImport() commits it. Throws SessionError while another
    /// import runs, and core::ImportError at once for what core::checkImportFile refuses (a
    /// missing file, an unknown extension); errors found while reading come from pollImport.
    void importMeshInBackground(const std::filesystem::path& file,
                                const core::ImportOptions& options = {}, int level = 0);
    /// The import under way, for a status line ("importing scan.stl: placing (3 s)..."), or
    /// nothing.
    std::optional<std::string> importStatus() const;
    /// Once the import in the background is done: commits it as one step (as importMesh
    /// does: journaled, notes to the notice sink) and returns what happened, for the user
    /// ("imported FILE as clay (level L)...", or why it failed, naming the file); `failed`
    /// tells which. Returns nothing while it runs or when none was started, and also when the
    /// sculpture changed since its copy was taken: the mesh is then placed again on a fresh
    /// copy (not read again), so the clay is what importMesh would make now. A stroke in
    /// progress is finished first (its samples all count). `wait`: until it is committed
    /// (a window's close, a project switch).
    std::optional<std::string> pollImport(bool wait = false, bool* failed = nullptr);
    /// Drops the import under way at once (nothing is added; its thread ends with the phase
    /// under way, beside the frame); false when there was none.
    bool cancelImport();
    /// Where notes for the user go (one line each, no newline); by default spdlog warnings
    /// (stderr in the program, app/Log.h). Playback and the windows may route them elsewhere.
    void setNoticeSink(std::function<void(const std::string&)> sink) { mNotice = std::move(sink); }

    /// Runs one playback-script command: sketch commands here, the rest through the session
    /// (undo/redo through the shared timeline). Returns true when the sculpture changed.
    /// Errors as Session::apply, plus std::invalid_argument for a sketch command that does
    /// not apply (unknown stroke id, missing role, bad solid).
    bool apply(const ScriptCommand& command);

    /// Runs `action` on the current page and records a sketch step when it added one to the
    /// page's log. Returns what the action returned, when it returns something.
    /// Pen input, editing and roles go through here; undo and redo must not (use the
    /// studio's).
    template <class F>
    auto sketchStep(F&& action) {
        const size_t before = page().undoCount();
        if constexpr (std::is_void_v<decltype(action(page()))>) {
            action(page());
            if (page().undoCount() > before) noteSketchStep();
        } else {
            auto result = action(page());
            if (page().undoCount() > before) noteSketchStep();
            return result;
        }
    }

    /// Builds a solid from the roles (the current page's first, then the other pages';
    /// docs/sketch-mode.md) and adds it to the sculpture as one step. When the last solid
    /// built is still the last sculpt step, building the same construction again (after
    /// editing its lines), a cut or an extrusion replaces it: one new step, whose undo brings
    /// the previous solid back. @param level 0: from its size. Returns the level used.
    int buildSolid(sketch::SolidConstruction construction, int level = 0);
    /// The last solid built (what cut and extrude change), if any.
    /// The solid a cut or an extrusion would change: the last one built in this session and not
    /// undone (null when none).
    const sketch::SketchSolid* lastSolid() const {
        const BuiltSolid* b = currentSolid();
        return b ? b->solid.get() : nullptr;
    }

    /// One step of the timeline back or forward (nothing when there is none: stepCount() says).
    /// True when it was a sculpt step (the mesh changes), false for a sketch step or none.
    bool undo();
    bool redo();
    size_t stepCount() const { return mDone.size(); }
    size_t redoCount() const { return mUndone.size(); }
    /// Writes a snapshot of the sculpture and `sketch.json` (projects only), and waits for
    /// both: throws when either could not be written.
    void save();
    /// Session::saveCopyTo, and the sketch beside it (`dir`/sketch.json).
    void saveCopyTo(const std::filesystem::path& dir);
    /// The same without waiting for the snapshot (Session::saveInBackground) or sketch.json
    /// (its writer thread). Returns false without a project; pollSave() finishes it.
    bool saveInBackground();
    /// The background save's outcome once it is done (Session::pollSave). A sketch.json write
    /// that failed since is part of it: the save then counts as failed.
    std::optional<std::string> pollSave(bool wait = false, bool* failed = nullptr);

    SketchPlane plane(size_t pageIndex) const;
    void setPlane(size_t pageIndex, SketchPlane plane);
    /// Session::addRecoveryWarning: a line about what opening the project had to leave aside
    /// (the windows' view.json), shown where the journal's recovery is.
    void addRecoveryWarning(const std::string& line) { mSession->addRecoveryWarning(line); }

    /// Drawing on the model: polylines already on the sculpture's surface (object mm) become
    /// surface lines, one step for all of them. Pieces with fewer than two points are
    /// skipped. Returns the number of lines added (0: no step).
    size_t addSurfaceLines(std::vector<std::vector<core::Vec3>> lines);
    /// Installs what `model-line` script commands project their strokes with; without one
    /// they are refused (std::invalid_argument).
    void setSurfaceProjector(SurfaceProjector projector) { mProjector = std::move(projector); }
    /// Surface lines drawn on the model (object mm), oldest first.
    const std::vector<std::vector<core::Vec3>>& surfaceLines() const { return mSurfaceLines; }

    /// The document's clean curves and role strokes in object space (mm), then the surface
    /// lines, for exports (DXF polylines). Pages without a plane use the front plane.
    std::vector<std::vector<core::Vec3>> curvesInObjectSpace() const;

    /// One step of the shared undo timeline.
    struct Step {
        bool sketch = false;
        size_t page = 0;
        size_t surfaceLines = 0;  ///< > 0: a stroke drawn on the model, that many lines
        bool sculpt() const { return !sketch && surfaceLines == 0; }
        bool operator==(const Step&) const = default;
    };
    /// The steps done, oldest first, and those that can be redone, the next one last.
    /// sketch.json is written on a thread of its own after each sketch step (the latest state
    /// first; a sketch step never waits for it). Returns once what the steps so far left is
    /// in the file; throws core::FileWriteError when the last write failed (also logged, and
    /// told to the notice sink at the next step).
    void waitForSketchFile() const;
    const std::vector<Step>& timeline() const { return mDone; }
    const std::vector<Step>& redoTimeline() const { return mUndone; }

  private:
    void noteSketchStep();
    void push(const Step& step);
    /// Runs a session call that may complete sculpt steps (ending a stroke, adding a solid)
    /// and puts each completed step on the timeline at once.
    template <class F>
    auto sculpt(F&& call) {
        try {
            if constexpr (std::is_void_v<decltype(call(std::declval<Session&>()))>) {
                call(*mSession);
                noteSculptSteps();
            } else {
                auto result = call(*mSession);
                noteSculptSteps();
                return result;
            }
        } catch (...) {
            // A stroke ended (journaled) before the call failed is still a step.
            noteSculptSteps();
            throw;
        }
    }
    void noteSculptSteps();
    /// Each page's sketch plane by name, as sketch.json stores them.
    std::vector<std::string> planeNames() const;
    /// A note for the user: to the notice sink, else logged as a warning.
    void tell(const std::string& note) const;
    /// An import's notes (a repaired mesh, rewound triangles) to the notice sink.
    void tellNotes(const core::ImportReport& report) const;
    void loadSketchFile();
    /// After loadSketchFile failed with `why`: the studio as if there were no file.
    void openWithoutSketchFile(const std::string& why, std::vector<Step> sculptDone,
                               std::vector<Step> sculptUndone);
    void writeSketchFile() const;
    /// After a sculpt step, undo or redo: writes the file only where the journal alone would
    /// not give the timeline back on opening (reconciledTimeline).
    void writeSketchFileUnlessJournalTellsIt() const;
    struct ReconciledTimeline {
        std::vector<Step> done, undone;
        bool undoneSurfaceLinesKept = true;
    };
    /// The timeline a project opens with: the file's lists reconciled with the journal's
    /// sculpt step counts (done and redo).
    static ReconciledTimeline reconciledTimeline(std::vector<Step> done, std::vector<Step> undone,
                                                 size_t sculptDone, size_t sculptUndone);
    void applySketch(const ScriptCommand& c);
    core::Vec3 toObject(size_t page, const glm::dvec2& canvas) const;

    std::unique_ptr<Session> mSession;
    studio::SketchDocument mDocument;
    std::vector<Step> mDone, mUndone;
    // The timeline as sketch.json last had it (written or read).
    mutable std::vector<Step> mWrittenDone, mWrittenUndone;
    size_t mSculptSteps = 0;  // sculpt steps in mDone == the session's done history
    std::vector<SketchPlane> mPlanes;
    double mClock = 0;  // script pen time when samples give none, s
    // The last solid built from a page, for regeneration after editing its lines.
    struct BuiltSolid {
        sketch::SolidConstruction construction;
        std::vector<PolylineRef> sources;  // the polylines it was built from
        size_t timelineIndex = 0;          // its step in mDone (or mUndone, when undone)
        std::shared_ptr<const sketch::SketchSolid> solid;
    };
    // Every solid built this session, in timeline order; those at or past mDone.size() are
    // undone (a redo brings them back, a new step drops them), so undoing a cut gives the
    // uncut solid back to the next cut.
    std::vector<BuiltSolid> mBuilt;
    const BuiltSolid* currentSolid() const {
        for (auto it = mBuilt.rbegin(); it != mBuilt.rend(); ++it)
            if (it->timelineIndex < mDone.size()) return &*it;
        return nullptr;
    }
    std::vector<std::vector<core::Vec3>> mSurfaceLines, mUndoneSurfaceLines;
    std::optional<std::filesystem::path> mFile;
    SurfaceProjector mProjector;
    std::function<void(const std::string&)> mNotice;
    bool mSaidNothingToUndo = false, mSaidNothingToRedo = false;  // once a session each
    std::unique_ptr<ImportInBackground> mImport;  // the import in the background, if any
    std::vector<std::unique_ptr<ImportInBackground>> mEndingImports;  // done or cancelled, ending
    // Last: destroyed first, writing what is pending while the rest still stands.
    std::unique_ptr<SketchFileWriter> mSketchWriter;
};

}  // namespace vsculpt::studio
