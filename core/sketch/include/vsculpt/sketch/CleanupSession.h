// Incremental clean-up of overdrawn strokes (seed 000 chapter 5, 逐次清書法) as an engine for a
// tablet sketch mode. Strokes arrive one at a time and gather in a pending group; a trigger
// (pause, pen pressure, or an explicit call) turns the group into clean lines or curves. A group
// drawn over an existing clean curve corrects it. Every stroke and every version of every curve
// is kept, so the UI can go back to an older one.
//
// Units: millimetres on the canvas, seconds on the caller's clock (stroke sample times),
// pressure 0..1. Deterministic: the same calls in the same order give the same curves.
#pragma once

#include "vsculpt/sketch/JoinFeaturePoints.h"
#include "vsculpt/sketch/KnotDivision.h"
#include "vsculpt/sketch/LineMixing.h"
#include "vsculpt/sketch/Polyline.h"
#include "vsculpt/sketch/ScribbleDetection.h"
#include "vsculpt/sketch/Stroke.h"
#include "vsculpt/sketch/StrokeClosedness.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace vsculpt::sketch {

/// What ends a group of strokes and runs the clean-up.
enum class CleanupTrigger {
    PauseTime,  // seed: no drawing for pauseSeconds ("thinking time")
    Pressure,   // a stroke pressed harder than pressureThreshold ends the group (seed's proposal)
    Explicit,   // only endGroup() (a button, a gesture)
};

/// The user says whether a stroke is a straight line or a curve (seed: no automatic choice).
enum class StrokeKind { Line, Curve };

/// Bounds on the work one stroke, one curve and one group can cost, so that no input (a stroke
/// of 1e6 mm zigzags, thousands of overdrawn strokes) makes the session allocate or compute
/// without bound. Normal drawing stays far below every one of them, and then the results are
/// exactly those without limits. Beyond a limit the session simplifies its working copy of the
/// input and says so (StrokeReport::note, CleanCurve::limitNote); it never refuses a stroke.
/// docs/sketch-cleanup.md, "Limits", has the reasoning and measurements.
struct CleanupLimits {
    /// Points per stroke after arc-length resampling (>= 16). A stroke longer than about
    /// maxStrokePoints * resampleSpacing (2 m of ink at 0.5 mm) is resampled at a wider step.
    std::size_t maxStrokePoints = 4096;
    /// Feature points per stroke (>= 4; only featureChordRatio > 0 gives more than three).
    /// Beyond, the pieces farthest off their chords are split first.
    std::size_t maxFeaturePoints = 64;
    /// Knots per curve (>= 8). Joining beyond it re-chooses the knots by knot division and, if
    /// still too many, keeps evenly spaced ones.
    std::size_t maxCurveKnots = 256;
    /// Ink points of one group tested against existing curves to find the one it corrects
    /// (>= 16); beyond, every k-th point is tested.
    std::size_t maxGroupInkPoints = 8192;
};

struct CleanupParams {
    CleanupTrigger trigger = CleanupTrigger::PauseTime;
    /// Pause that ends a group (s). The seed uses a fixed window without stating it; 1 s.
    double pauseSeconds = 1.0;
    /// Peak pressure (0..1) of a stroke that ends its group under CleanupTrigger::Pressure.
    double pressureThreshold = 0.85;
    /// Straight-line grouping and mixing (seed 5.2).
    LineMixParams line;
    /// Not in the seed: mix each new line stroke with weight 1 / (strokes so far + 1), for angle
    /// and offset alike, so the clean line is the plain mean of all its strokes and converges
    /// as more are drawn. Off: line.angleWeight / line.offsetWeight (seed: later strokes win).
    bool lineRunningMean = false;
    /// Feature points per curve stroke: 0 is the seed's three; > 0 refines bent strokes (see
    /// strokeFeaturePoints).
    double featureChordRatio = 0.0;
    /// Feature-point joining (seed 5.3 (2)).
    JoinParams join;
    /// Knot-division smoothing (seed 5.3 (3)); disable to keep the raw joined feature points.
    /// A correction pins the old curve with knots 2 and 6 times join.mergeDistance outside where
    /// its stroke ends land on it and re-smooths only between the old knots next to its new points,
    /// so the rest of the curve keeps its knots (not in the seed).
    KnotDivisionParams knots;
    bool smooth = true;
    /// A curve group corrects an existing curve when at least `attachFraction` of its ink lies
    /// within attachDistance (mm) of it; otherwise it starts a new curve.
    double attachDistance = 4.0;
    double attachFraction = 0.5;
    /// Resampling step (mm) of strokes before feature extraction and fitting.
    double resampleSpacing = 0.5;
    /// Density of the output polylines (1..256; join.samplesPerSpan has the same range).
    int samplesPerSpan = 16;
    /// Closed-loop detection for new curves.
    ClosednessParams closedness;
    /// Scribbles (ScribbleDetection.h) are kept as strokes but never cleaned up.
    bool ignoreScribbles = true;
    ScribbleParams scribble;
    CleanupLimits limits;
};

/// What the session made of one stroke, and which limits (CleanupLimits) it hit.
struct StrokeReport {
    std::size_t samples = 0;        // as drawn
    double length = 0.0;            // mm
    double spacing = 0.0;           // resampling step used (mm)
    std::size_t points = 0;         // after resampling, <= limits.maxStrokePoints
    std::size_t featurePoints = 0;  // curve strokes, drawn open; <= limits.maxFeaturePoints
    bool scribble = false;          // never cleaned up when ignoreScribbles
    bool coarsened = false;         // spacing > resampleSpacing (maxStrokePoints)
    bool featuresCapped = false;    // more feature points qualified (maxFeaturePoints)
    /// The limits that applied, in words; empty when none did.
    std::string note;
};

/// One version of a clean line or curve.
struct CleanCurve {
    int id = -1;
    StrokeKind kind = StrokeKind::Curve;
    bool closed = false;
    /// Lines: the two endpoints. Curves: the spline knots (smoothed feature points).
    Polyline2 knots;
    /// The curve to draw: lines as their two endpoints, curves sampled from the natural
    /// (periodic when closed) spline through the knots, samplesPerSpan points per span.
    Polyline2 samples;
    /// Ids of the strokes this version was built from, in drawing order.
    std::vector<int> strokes;
    /// Empty, or why this version has fewer knots than its strokes asked for
    /// (limits.maxCurveKnots).
    std::string limitNote;
};

class CleanupSession {
  public:
    /// Throws std::invalid_argument for non-positive pauseSeconds, samplesPerSpan or spacing,
    /// or thresholds and limits outside their ranges.
    explicit CleanupSession(CleanupParams params = {});

    /// Adds a finished stroke (pen up) and returns its id (0, 1, ... in call order). With
    /// PauseTime, a stroke that starts pauseSeconds or more after the previous stroke ended
    /// first cleans up the pending group; a change of kind always does. With Pressure, a stroke
    /// whose peak pressure reaches the threshold is added and then the group is cleaned up.
    /// Throws std::invalid_argument for an invalid stroke (validateStroke) or a stroke shorter
    /// than two distinct points; the session is unchanged then. Any valid stroke is accepted:
    /// params().limits bound what it costs, and strokeReport(id) says which limits applied.
    int addStroke(const Stroke& stroke, StrokeKind kind);

    /// Clock tick for PauseTime: cleans up when `now` is pauseSeconds or more after the last
    /// stroke's end. Returns true when a clean-up ran. Other triggers ignore the clock.
    bool advanceTime(double now);

    /// Cleans up the pending group now, whatever the trigger. Returns false when it was empty.
    bool endGroup();

    /// What endGroup() would produce for the pending group, without changing the session: the
    /// new or corrected curves (current versions of untouched curves are not included).
    std::vector<CleanCurve> previewPending() const;

    /// Every stroke ever added, indexed by stroke id.
    const std::vector<Stroke>& strokes() const { return strokes_; }
    /// Sizes of a stroke's working copies and the limits it hit. Throws std::out_of_range for a
    /// bad id.
    const StrokeReport& strokeReport(int strokeId) const;
    StrokeKind strokeKind(int strokeId) const;
    /// Stroke ids waiting for the trigger, in drawing order.
    const std::vector<int>& pendingStrokes() const { return pending_; }

    /// Current version of every curve, by curve id (0, 1, ... in creation order); a copy.
    std::vector<CleanCurve> curves() const;
    /// Current version of one curve, without copying. The reference stays valid for the
    /// session's lifetime, but a later group or selectVersion may make another version current.
    /// Throws std::out_of_range for a bad id.
    const CleanCurve& curve(int curveId) const;
    std::size_t curveCount() const { return history_.size(); }
    /// Versions of one curve, oldest first; version 0 is the one that created it. References
    /// stay valid for the session's lifetime (versions are immutable and never removed).
    /// Throw std::out_of_range for bad indices.
    std::size_t versionCount(int curveId) const;
    const CleanCurve& version(int curveId, int version) const;
    int currentVersion(int curveId) const;

    /// Makes an older (or newer) version current again; later corrections build on it and are
    /// appended as new versions, so nothing is lost. Throws std::out_of_range for bad indices.
    void selectVersion(int curveId, int version);

    /// Rebuilds the curve from one earlier stroke alone (the designer prefers an old line) and
    /// appends it as a new current version. Returns the version index. Throws std::out_of_range
    /// for bad ids, std::invalid_argument when the stroke's kind differs from the curve's.
    int restartFromStroke(int curveId, int strokeId);

    const CleanupParams& params() const { return params_; }

  private:
    // Versions are shared and immutable, so copying the history for a trial clean-up (strong
    // exception guarantee, previewPending) copies pointers, not polylines.
    struct Entry {
        std::vector<std::shared_ptr<const CleanCurve>> versions;
        const CleanCurve& cur() const { return *versions[std::size_t(current)]; }
        int current = 0;
    };

    // Applies a group of strokes to `history`; returns the ids of the curves it changed.
    std::vector<int> cleanGroup(const std::vector<int>& group, std::vector<Entry>& history) const;
    void cleanLineStroke(int strokeId, std::vector<Entry>& history,
                         std::vector<int>& touched) const;
    // Joins the strokes' feature points onto `knots` (empty for a new curve) and smooths.
    // Returns CleanCurve::limitNote.
    std::string buildCurve(const std::vector<int>& strokeIds, Polyline2& knots, bool& closed) const;
    CleanCurve makeCurve(int id, StrokeKind kind, Polyline2 knots, bool closed,
                         std::vector<int> strokeIds) const;
    Polyline2 resampled(int strokeId) const;
    Polyline2 featurePoints(const Polyline2& poly, std::size_t maxPoints) const;
    // Brings a curve's knots within limits.maxCurveKnots; returns the note, empty when they were
    // within it.
    std::string capKnots(Polyline2& knots, bool closed) const;
    std::string knotCapNote(std::size_t before, std::size_t after) const;
    // The curve's knots plus points of the curve just outside where the strokes' ends land on
    // it, so a correction cannot pull the curve beyond the part it overlaps.
    Polyline2 anchoredKnots(const CleanCurve& cur, const std::vector<int>& strokeIds) const;

    CleanupParams params_;
    std::vector<Stroke> strokes_;
    std::vector<StrokeReport> reports_;
    std::vector<StrokeKind> kinds_;
    std::vector<int> pending_;
    double lastEnd_ = 0.0;
    std::vector<Entry> history_;
};

}  // namespace vsculpt::sketch
