// SPDX-License-Identifier: MIT
/// @file Studio.h
/// @brief Sculpting and sketching together: the session, the sketch document, and one undo
/// timeline across both (docs/sketch-mode.md). Playback scripts, the sketch window and tests
/// drive it; what a designer does in either mode is undone in the order it was done.
///
/// Ownership: the studio refers to a Session it does not own (the caller keeps it alive) and
/// owns the sketch document. In a project folder it writes the document and the timeline to
/// `sketch.json` (atomically) after every sketch step, so no sketch work is lost.
#pragma once

#include "vsculpt/app/Script.h"
#include "vsculpt/app/Session.h"
#include "vsculpt/render/ProjectStroke.h"
#include "vsculpt/sketch/SketchDocument.h"
#include "vsculpt/sketch/SketchSolid.h"

#include <filesystem>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace vsculpt::app {

/// Which view a page is drawn on: how its canvas millimetres map into object space (z up;
/// SketchSolid.h). Front: canvas (x, y) -> object (x, z); side: (y, z); top: (x, y).
using SketchPlane = sketch::SketchPlane;

/// The sketch settings vsculpt uses: the seed's, except feature points refined along bent
/// strokes (featureChordRatio 0.05) and overdrawn lines averaged (lineRunningMean), which
/// converge where the seed's three points per stroke do not (docs/sketch-cleanup.md).
sketch::SketchParams recommendedSketchParams();

class Studio {
  public:
    /// @param session kept by the caller; the studio reads its project folder, if any, and
    /// loads `sketch.json` from it (throws std::invalid_argument naming the file and field).
    explicit Studio(Session& session,
                    const sketch::SketchParams& params = recommendedSketchParams());

    Session& session() { return mSession; }
    const Session& session() const { return mSession; }
    sketch::SketchDocument& document() { return mDocument; }
    const sketch::SketchDocument& document() const { return mDocument; }
    sketch::SketchPage& page() { return mDocument.current(); }

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
    /// Call after sculpting through the session directly (the window's tools): the steps it
    /// added join the timeline.
    void syncSculptSteps();

    /// Builds a solid from the roles (the current page's first, then the other pages';
    /// docs/sketch-mode.md) and adds it to the sculpture as one step. When the last solid
    /// built is still the last sculpt step, building the same construction again (after
    /// editing its lines), a cut or an extrusion replaces it: one new step, whose undo brings
    /// the previous solid back. @param level 0: from its size. Returns the level used.
    int buildSolid(sketch::SolidConstruction construction, int level = 0);
    /// The last solid built (what cut and extrude change), if any.
    const std::optional<sketch::SketchSolid>& lastSolid() const { return mLastBuilt; }

    bool undo();
    bool redo();
    size_t stepCount() const { return mDone.size(); }
    size_t redoCount() const { return mUndone.size(); }

    SketchPlane plane(size_t pageIndex) const;
    void setPlane(size_t pageIndex, SketchPlane plane);

    /// Drawing on the model: a stroke drawn over the 3D view (pixels of a view of
    /// `camera.viewportPx`, origin top-left) is projected onto the sculpture's surface with
    /// Embree; each piece on the surface becomes a surface line (one step for the stroke).
    /// Returns the number of pieces (0: the stroke missed the sculpture; no step).
    size_t drawOnModel(const std::vector<glm::dvec2>& strokePx,
                       const render::ProjectionCamera& camera);
    /// The camera of a view of `viewportPx` framing the sculpture's current mesh from the
    /// front (the window's camera at the start), for scripts: `model-line`.
    render::ProjectionCamera frontCamera(glm::ivec2 viewportPx) const;
    /// Surface lines drawn on the model (object mm), oldest first.
    const std::vector<std::vector<core::Vec3>>& surfaceLines() const { return mSurfaceLines; }

    /// The document's clean curves and role strokes in object space (mm), then the surface
    /// lines, for exports (DXF polylines). Pages without a plane use the front plane.
    std::vector<std::vector<core::Vec3>> curvesInObjectSpace() const;

    /// Writes `sketch.json` now (projects only; done after every sketch step anyway).
    void save() const;

  private:
    struct Step {
        bool sketch = false;
        size_t page = 0;
        size_t surfaceLines = 0;  ///< > 0: a stroke drawn on the model, that many lines
        bool sculpt() const { return !sketch && surfaceLines == 0; }
        bool operator==(const Step&) const = default;
    };
    void noteSketchStep();
    void push(const Step& step);
    void applySketch(const ScriptCommand& c);
    core::Vec3 toObject(size_t page, const glm::dvec2& canvas) const;

    Session& mSession;
    sketch::SketchDocument mDocument;
    std::vector<Step> mDone, mUndone;
    size_t mSculptSteps = 0;  // session history length the timeline accounts for
    std::vector<SketchPlane> mPlanes;
    double mClock = 0;  // script pen time when samples give none, s
    // The last solid built from a page, for regeneration after editing its lines.
    struct BuiltSolid {
        sketch::SolidConstruction construction;
        size_t timelineIndex = 0;
    };
    std::optional<BuiltSolid> mLastSolid;
    std::optional<sketch::SketchSolid> mLastBuilt;
    std::vector<std::vector<core::Vec3>> mSurfaceLines, mUndoneSurfaceLines;
    std::optional<std::filesystem::path> mFile;
};

}  // namespace vsculpt::app
