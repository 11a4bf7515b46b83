// The model of the tablet sketch mode (issue #8): pages of strokes on an endless canvas, the
// view that maps pen input onto it, draft and clean-up modes, draft editing, roles for the 3D
// builders, undo/redo per page and a JSON file format. Pure C++: no GL, no devices, no clock;
// the window, playback scripts and tests drive it with calls and read draw data back.
//
// Frames and units: canvas space is millimetres, x right, y up, within +-1e6 mm (SketchLimits).
// View space is millimetres on the tablet/screen surface. canvasFromView is a uniform scale
// plus an offset. Times are seconds on the caller's clock, pressure 0..1, tilt in degrees.
//
// Undo model (docs/sketch-mode.md): every page keeps a log of actions. A new action is applied
// and appended; undo moves the last action to the redo stack and rebuilds the page by replaying
// the log from an empty page (the clean-up session is deterministic, so the replay is exact).
// Every stroke ever drawn stays in the page's history, including undone and deleted ones.
#pragma once

#include "vsculpt/sketch/CleanupSession.h"
#include "vsculpt/sketch/Polyline.h"
#include "vsculpt/sketch/Stroke.h"

#include <glm/vec2.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vsculpt::studio {

// The pure geometry the document is made of (core/sketch).
using sketch::CleanCurve;
using sketch::CleanupParams;
using sketch::CleanupSession;
using sketch::Polyline2;
using sketch::Stroke;
using sketch::StrokeKind;

// ---------------------------------------------------------------------------------------------
// Limits

/// Bounds on every number and size the model accepts, at the pen API and in files
/// (docs/sketch-mode.md, "Input bounds"). Each is far beyond real drawing; their point is that no
/// input can make the model allocate or compute without bound, or overflow to infinity. Input
/// beyond them is refused with std::invalid_argument naming the value.
struct SketchLimits {
    /// |x|, |y| of any canvas point (mm): 1 km, as for the sculpture (core::isUsablePoint).
    static constexpr double maxCanvasMm = sketch::kMaxStrokeCoordinate;
    /// |x|, |y| of a view point (mm on the tablet or screen): 1000 km, beyond any surface, so
    /// that a script drawing at the canvas edge through a view zoomed in 1000 times still
    /// works; the canvas bound is what limits ink.
    static constexpr double maxViewMm = 1e9;
    /// canvasFromView scale (canvas mm per view mm) and |offset| (canvas mm).
    static constexpr double minViewScale = 1e-9, maxViewScale = 1e9;
    static constexpr double maxViewOffsetMm = 1e9;
    /// |time| of a pen sample (s): seconds since the Unix epoch fit.
    static constexpr double maxTime = sketch::kMaxStrokeTime;
    /// Factor of one scale edit, and of a stroke's accumulated placement scale.
    static constexpr double minEditFactor = 1e-6, maxEditFactor = 1e6;
    /// Samples in one stroke: over 8 minutes of a 200 Hz tablet.
    static constexpr std::size_t maxStrokeSamples = 100'000;
    /// Strokes in one page's history, actions in its log plus redo stack, pages in a document.
    static constexpr std::size_t maxPageStrokes = 100'000;
    static constexpr std::size_t maxPageActions = 1'000'000;
    static constexpr std::size_t maxPages = 10'000;
    /// Samples in all strokes of a file (about 800 MB of JSON).
    static constexpr std::size_t maxDocumentSamples = 10'000'000;
    /// Bytes of a page name or group name.
    static constexpr std::size_t maxNameBytes = 1024;
};

// ---------------------------------------------------------------------------------------------
// Canvas view

/// canvasFromView: canvas = scale · view + offset. scale is canvas mm per view mm (1/zoom).
struct CanvasView {
    double scale = 1.0;
    glm::dvec2 offset{0.0};

    glm::dvec2 canvasFromView(glm::dvec2 view) const { return scale * view + offset; }
    glm::dvec2 viewFromCanvas(glm::dvec2 canvas) const { return (canvas - offset) / scale; }
    /// Magnifies the content by `factor` (> 1 zooms in) keeping the canvas point under
    /// `viewPoint` fixed. Throws std::invalid_argument (view unchanged) for a point outside
    /// SketchLimits::maxViewMm, a factor that is not finite and positive, or a resulting scale
    /// or offset outside SketchLimits.
    void zoomAbout(glm::dvec2 viewPoint, double factor);
    /// Drags the canvas with the pen: the content moves by `deltaView` view mm. Throws like
    /// zoomAbout.
    void pan(glm::dvec2 deltaView);
    void reset() { *this = CanvasView{}; }
    bool operator==(const CanvasView&) const = default;
};

// ---------------------------------------------------------------------------------------------
// Pen input and ink appearance

/// One pen report in view space.
struct PenSample {
    glm::dvec2 view{0.0};               // mm on the tablet surface
    std::optional<double> pressure;     // 0..1; absent for the mouse
    std::optional<glm::dvec2> tiltDeg;  // x/y tilt in degrees, [-90, 90]; absent if unknown
    double time = 0.0;                  // s
};

/// Ink from pressure (seed F-31: line weight shows importance). Widths are view mm at the
/// moment of drawing; a stroke keeps them in canvas mm (times the view scale at pen-down), so
/// zooming in draws finer lines and zooming never changes ink already drawn.
///   t = pressure^gamma, width = lerp(minWidth, maxWidth, t), darkness = lerp(minDarkness,
///   maxDarkness, t). Without pressure (mouse) every point gets the midpoints
///   (minWidth + maxWidth) / 2 and (minDarkness + maxDarkness) / 2.
struct InkParams {
    double minWidth = 0.15;     // mm at pressure 0
    double maxWidth = 1.2;      // mm at pressure 1
    double minDarkness = 0.25;  // 0..1 at pressure 0
    double maxDarkness = 1.0;   // 0..1 at pressure 1
    double gamma = 1.5;         // > 1: light pressure stays thin, pressing hard makes weight
    double cleanWidth = 0.6;    // mm on the view for clean lines and curves (drawn at any zoom)
};

/// Throws std::invalid_argument naming the bad parameter (0 < minWidth <= maxWidth,
/// 0 <= minDarkness <= maxDarkness <= 1, gamma > 0, cleanWidth > 0, all finite).
void validateInkParams(const InkParams& ink);
/// Monotone in pressure; exactly minWidth at 0 and maxWidth at 1. Pressure outside [0, 1] or
/// NaN throws std::invalid_argument.
double inkWidth(double pressure, const InkParams& ink);
double inkDarkness(double pressure, const InkParams& ink);

// ---------------------------------------------------------------------------------------------
// Page content

enum class SketchMode { Draft, Cleanup };

/// What a stroke or clean curve stands for when the sketch becomes a solid (seed F-22..F-24).
/// The three surface lines follow ThreeSection.h's frame: SurfaceLineX lies in the x-section
/// (transverse, the line across the belly, curve (c)), SurfaceLineY in the y-section (side
/// profile, the line along the back, curve (a)), SurfaceLineZ in the z-section (plan, the line
/// around the torso, curve (b)). The lower profile (d) comes from the outline.
enum class Role {
    None,
    Outline,
    SurfaceLineX,
    SurfaceLineY,
    SurfaceLineZ,
    SweepSection,
    SweepPath,
    Cut,
    Extrude
};
const char* roleName(Role role);  // "none", "outline", "surfaceLineX", ...

/// A stroke as drawn, kept forever in the page's history (canvas mm, seconds).
struct ArchivedStroke {
    int id = -1;
    Stroke stroke;                    // canvas positions as drawn
    std::vector<glm::dvec2> tiltDeg;  // empty, or one per sample
    double inkScale = 1.0;            // canvas mm per view mm at pen-down (ink widths)
    int reusedFrom = -1;              // the stroke this one copies (reuse), or -1
};

enum class StrokeStatus {
    Live,     // on the page now
    Deleted,  // removed by a delete action that is still in effect
    Undone,   // its stroke action was undone (it is in the redo stack or was dropped from it)
};

/// How the renderer draws a polyline.
enum class InkClass {
    Draft,     // draft-mode ink
    Selected,  // a selected draft stroke
    Pending,   // clean-up stroke waiting for its group to end (or being drawn in clean-up mode)
    Consumed,  // clean-up stroke already turned into a clean line/curve (seed: drawn dashed)
    Clean,     // clean line or curve (current version)
};

/// What the renderer consumes: canvas points with per-point width (canvas mm) and darkness.
struct DrawItem {
    InkClass ink = InkClass::Draft;
    int strokeId = -1;  // archive id for strokes, -1 for curves and the stroke being drawn
    int curveId = -1;   // clean curve id, -1 for strokes
    bool closed = false;
    Role role = Role::None;
    Polyline2 points;
    std::vector<double> width;
    std::vector<double> darkness;
};

/// One polyline for the solid builders.
struct RolePolyline {
    Role role = Role::None;
    bool fromCurve = false;  // true: clean curve samples; false: a raw stroke
    int id = -1;             // curve id or stroke id
    bool closed = false;
    Polyline2 points;  // canvas mm
};

/// The page's state as undo must restore it: live strokes (with their current placement and
/// role), the clean curves (current versions, version counts, roles) and the pending group.
/// Not included: the history of strokes ever drawn, undo/redo stacks, selection, hover, the
/// view and the mode/kind settings (none of them are actions). Compared exactly (operator==)
/// and hashed (contentHash) bit for bit.
struct PageContent {
    struct StrokeEntry {
        int id = -1;
        bool cleanup = false;
        StrokeKind kind = StrokeKind::Curve;
        Role role = Role::None;
        double scale = 1.0;  // placement: points = scale · drawn + offset
        glm::dvec2 offset{0.0};
        Polyline2 points;
        bool operator==(const StrokeEntry&) const = default;
    };
    struct CurveEntry {
        int id = -1;
        StrokeKind kind = StrokeKind::Curve;
        bool closed = false;
        int version = 0;
        int versionCount = 0;
        Role role = Role::None;
        Polyline2 knots, samples;
        std::vector<int> strokes;  // archive ids
        bool operator==(const CurveEntry&) const = default;
    };
    std::vector<StrokeEntry> strokes;  // by id
    std::vector<CurveEntry> curves;    // by curve id
    std::vector<int> pending;          // archive ids, drawing order
    bool operator==(const PageContent&) const = default;
};
/// FNV-1a over the content's bits (-0.0 hashed as 0.0, matching operator==).
std::uint64_t contentHash(const PageContent& content);

struct SketchParams {
    InkParams ink;
    /// Clean-up engine settings. trigger, pauseSeconds and pressureThreshold are applied by the
    /// page (so that each clean-up is its own undoable action); the rest go to CleanupSession.
    CleanupParams cleanup;
};

/// One action in a page's log (undo unit). Public for the file format and tests.
struct SketchAction {
    enum class Type { Stroke, EndGroup, Move, Scale, Delete, SetRole };
    Type type = Type::Stroke;
    int stroke = -1;       // Stroke: archive id
    bool cleanup = false;  // Stroke: fed to the clean-up session
    StrokeKind kind = StrokeKind::Curve;
    std::vector<int> strokes;  // Move, Scale, Delete: archive ids
    glm::dvec2 vec{0.0};       // Move: delta; Scale: pivot (canvas mm)
    double factor = 1.0;       // Scale
    bool curve = false;        // SetRole: target is a clean curve (else a stroke)
    int target = -1;           // SetRole: curve id or stroke id
    Role role = Role::None;    // SetRole
    bool operator==(const SketchAction&) const = default;
};

// ---------------------------------------------------------------------------------------------
// A page

class SketchPage {
  public:
    /// Throws std::invalid_argument for an empty name or bad params.
    SketchPage(std::string name, std::string group, const SketchParams& params = {});

    const std::string& name() const { return name_; }
    const std::string& group() const { return group_; }
    void setName(std::string name);  // non-empty
    void setGroup(std::string group);

    // View. Never moves strokes in canvas space.
    const CanvasView& view() const { return view_; }
    void zoomAbout(glm::dvec2 viewPoint, double factor) { view_.zoomAbout(viewPoint, factor); }
    void pan(glm::dvec2 deltaView) { view_.pan(deltaView); }
    void resetView() { view_.reset(); }
    /// Scale within [minViewScale, maxViewScale], |offset| <= maxViewOffsetMm (SketchLimits).
    void setView(const CanvasView& view);

    // Settings (not actions: undo never changes them).
    SketchMode mode() const { return mode_; }
    void setMode(SketchMode mode) { mode_ = mode; }
    StrokeKind kind() const { return kind_; }  // Line or Curve, for clean-up mode
    void setKind(StrokeKind kind) { kind_ = kind; }

    // Pen. Samples are converted to canvas with the view at each sample. Throws
    // std::invalid_argument (page unchanged) for non-finite values, a view or canvas position
    // or a time outside SketchLimits, pressure outside [0, 1], tilt outside [-90, 90], time
    // going backwards within the stroke, pressure or tilt present in some samples of a stroke
    // and not others, penDown while down or move/up while up, more than maxStrokeSamples
    // samples in the stroke, or penDown on a page whose history holds maxPageStrokes strokes.
    // In clean-up mode with the pause trigger, a penDown pauseSeconds after the pending group's
    // last stroke ended first ends that group (its own action).
    void penDown(const PenSample& sample);
    void penMove(const PenSample& sample);
    /// Ends the stroke (the sample, if given, is its last) and records it as an action. Returns
    /// its id, or nullopt when clean-up mode rejects it (fewer than two distinct points): then
    /// nothing is recorded.
    std::optional<int> penUp(const std::optional<PenSample>& last = std::nullopt);
    void cancelStroke();  // drops the stroke being drawn
    bool penIsDown() const { return drawing_.has_value(); }
    /// Proximity: remembered for a cursor, never ink. Non-finite throws.
    void hover(glm::dvec2 view);
    void leaveProximity() { hover_.reset(); }
    std::optional<glm::dvec2> hoverCanvas() const;

    // Clean-up mode.
    /// Pause trigger clock: ends the pending group when `now` is pauseSeconds after its last
    /// stroke ended (PauseTime trigger only, pen up). Returns true when a clean-up ran.
    bool advanceTime(double now);
    /// Ends the pending group now (any trigger). Returns false when nothing was pending.
    bool endGroup();
    const CleanupSession& cleanup() const { return session_; }
    /// For a live clean-up stroke: which clean-up limits it hit (StrokeReport::note), empty when
    /// none did. Throws std::invalid_argument for a stroke that is not a live clean-up stroke.
    std::string cleanupNote(int strokeId) const;
    std::vector<CleanCurve> cleanCurves() const { return session_.curves(); }
    std::vector<int> pendingStrokes() const;  // archive ids

    // Draft editing (draft strokes only; clean-up strokes belong to their curves).
    /// Selects exactly these strokes. Throws std::invalid_argument for an id that is not a
    /// live draft stroke (selection unchanged).
    void select(const std::vector<int>& strokeIds);
    /// Selects the live draft strokes whose points all lie inside `polygon` (canvas mm,
    /// closed, at least 3 points, even-odd rule). Returns them.
    std::vector<int> selectLasso(const Polyline2& polygon);
    /// Selects the draft stroke nearest to `point` if within `tolerance` (canvas mm) of it,
    /// otherwise clears the selection.
    std::optional<int> selectNearest(glm::dvec2 point, double tolerance);
    void clearSelection() { selection_.clear(); }
    const std::vector<int>& selection() const { return selection_; }
    /// Bounding box (min, max) of the selection in canvas mm; nullopt when empty.
    std::optional<std::pair<glm::dvec2, glm::dvec2>> selectionBounds() const;
    /// Each returns false (no action) when nothing is selected. Delta finite, factor within
    /// SketchLimits' edit factors, pivot on the canvas; an edit that would move a point off the
    /// canvas (SketchLimits::maxCanvasMm) throws std::invalid_argument and changes nothing.
    bool moveSelection(glm::dvec2 deltaCanvas);
    bool scaleSelection(double factor);  // about the selection's bounding-box centre
    bool scaleSelection(double factor, glm::dvec2 pivot);
    bool deleteSelection();

    // Roles. Return false when the role is already set (no action). Throw std::invalid_argument
    // for a stroke that is not live or a curve id that does not exist.
    bool setStrokeRole(int strokeId, Role role);
    bool setCurveRole(int curveId, Role role);
    Role strokeRole(int strokeId) const;
    Role curveRole(int curveId) const;
    /// Polylines per role for the solid builders: clean curves with a role first (by curve
    /// id), then strokes with a role (by id). A clean-up stroke with a role that has become part
    /// of a clean curve gives that curve's samples instead (once per curve and role).
    std::vector<RolePolyline> rolePolylines() const;

    // Undo / redo (per page). Immediate, no selection needed.
    bool undo();
    bool redo();
    std::size_t undoCount() const { return done_.size(); }
    std::size_t redoCount() const { return redo_.size(); }
    const std::vector<SketchAction>& actions() const { return done_; }
    const std::vector<SketchAction>& redoStack() const { return redo_; }  // back = next redo

    // History (seed F-04): every stroke ever drawn, by id.
    const std::vector<ArchivedStroke>& history() const { return archive_; }
    /// Throws std::out_of_range for an unknown id.
    StrokeStatus strokeStatus(int strokeId) const;
    /// Re-inserts a copy of a stroke as drawn (any status) as a new stroke in the current
    /// mode/kind; a new action. Returns the new id. Throws std::out_of_range for an unknown
    /// id, std::invalid_argument when clean-up mode rejects the stroke.
    int reuse(int strokeId);

    // Queries.
    std::vector<int> liveStrokeIds() const;
    /// Current canvas points of a live stroke. Throws std::invalid_argument when not live.
    Polyline2 strokePoints(int strokeId) const;
    /// Everything to draw, in order: live strokes by id, clean curves, the stroke being drawn.
    std::vector<DrawItem> drawList() const;
    PageContent content() const;
    const SketchParams& params() const { return params_; }

    /// Rebuilds a page from a saved history and log (the file loader). Throws
    /// std::invalid_argument naming "strokes[i]", "done[i]" or "redo[i]" for a stroke outside
    /// SketchLimits or an action that does not apply.
    static SketchPage restore(std::string name, std::string group, const SketchParams& params,
                              std::vector<ArchivedStroke> archive,
                              const std::vector<SketchAction>& done,
                              std::vector<SketchAction> redo);

  private:
    struct LiveStroke {
        bool cleanup = false;
        StrokeKind kind = StrokeKind::Curve;
        int sessionId = -1;
        double scale = 1.0;
        glm::dvec2 offset{0.0};
        Role role = Role::None;
    };
    struct Drawing {
        ArchivedStroke stroke;
        bool tilt = false;
    };

    void record(const SketchAction& action);  // apply + log + clear redo
    void apply(const SketchAction& action);   // strong guarantee
    void rebuild();
    void pruneSelection();
    bool pendingGroupPaused(double now) const;
    std::optional<int> addStrokeAction(ArchivedStroke stroke, bool allowPauseTrigger);
    const LiveStroke& liveDraft(int strokeId) const;
    glm::dvec2 toCanvas(const LiveStroke& s, glm::dvec2 drawn) const {
        return s.scale * drawn + s.offset;
    }

    std::string name_, group_;
    SketchParams params_;
    CanvasView view_;
    SketchMode mode_ = SketchMode::Draft;
    StrokeKind kind_ = StrokeKind::Curve;

    std::vector<ArchivedStroke> archive_;
    std::vector<SketchAction> done_, redo_;

    // Derived by replaying done_.
    std::map<int, LiveStroke> live_;
    CleanupSession session_;
    std::vector<int> sessionToArchive_;
    std::map<int, Role> curveRoles_;

    std::vector<int> selection_;
    std::optional<Drawing> drawing_;
    std::optional<glm::dvec2> hover_;  // view mm
};

// ---------------------------------------------------------------------------------------------
// The document: pages in groups (seed F-06)

class SketchDocument {
  public:
    /// Starts with one page "Sketch 1" in group "Sketches".
    explicit SketchDocument(const SketchParams& params = {});

    std::size_t pageCount() const { return pages_.size(); }
    SketchPage& page(std::size_t index);  // std::out_of_range for a bad index
    const SketchPage& page(std::size_t index) const;
    SketchPage& current() { return pages_[current_]; }
    const SketchPage& current() const { return pages_[current_]; }
    std::size_t currentIndex() const { return current_; }
    void selectPage(std::size_t index);
    /// Appends a page and makes it current; returns its index. Empty name throws.
    std::size_t addPage(std::string name, std::string group);
    void renamePage(std::size_t index, std::string name);
    void setPageGroup(std::size_t index, std::string group);
    /// Group names in order of first appearance.
    std::vector<std::string> groups() const;
    std::vector<std::size_t> pagesInGroup(const std::string& group) const;
    const SketchParams& params() const { return params_; }

    /// JSON text (format "vsculpt-sketch", version 1; docs/sketch-mode.md). A stroke being drawn
    /// is not saved.
    std::string toJson() const;
    /// Throws std::invalid_argument naming the field path of the first problem, e.g.
    /// "pages[1].strokes[3].samples[0].pressure: outside [0, 1]": malformed JSON, wrong types,
    /// missing fields, numbers that are not finite or lie outside SketchLimits, unknown names,
    /// ids that name nothing, sizes beyond SketchLimits, actions that do not replay.
    static SketchDocument fromJson(const std::string& text, const SketchParams& params = {});

  private:
    SketchParams params_;
    std::vector<SketchPage> pages_;
    std::size_t current_ = 0;
};

}  // namespace vsculpt::studio
