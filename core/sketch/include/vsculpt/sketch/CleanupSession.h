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
    /// Density of the output polylines.
    int samplesPerSpan = 16;
    /// Closed-loop detection for new curves.
    ClosednessParams closedness;
    /// Scribbles (ScribbleDetection.h) are kept as strokes but never cleaned up.
    bool ignoreScribbles = true;
    ScribbleParams scribble;
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
};

class CleanupSession {
  public:
    /// Throws std::invalid_argument for non-positive pauseSeconds, samplesPerSpan or spacing,
    /// or thresholds outside their ranges.
    explicit CleanupSession(CleanupParams params = {});

    /// Adds a finished stroke (pen up) and returns its id (0, 1, ... in call order). With
    /// PauseTime, a stroke that starts pauseSeconds or more after the previous stroke ended
    /// first cleans up the pending group; a change of kind always does. With Pressure, a stroke
    /// whose peak pressure reaches the threshold is added and then the group is cleaned up.
    /// Throws std::invalid_argument for an invalid stroke (validateStroke) or a stroke shorter
    /// than two distinct points; the session is unchanged then.
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
    void buildCurve(const std::vector<int>& strokeIds, Polyline2& knots, bool& closed) const;
    CleanCurve makeCurve(int id, StrokeKind kind, Polyline2 knots, bool closed,
                         std::vector<int> strokeIds) const;
    Polyline2 resampled(int strokeId) const;
    // The curve's knots plus points of the curve just outside where the strokes' ends land on
    // it, so a correction cannot pull the curve beyond the part it overlaps.
    Polyline2 anchoredKnots(const CleanCurve& cur, const std::vector<int>& strokeIds) const;

    CleanupParams params_;
    std::vector<Stroke> strokes_;
    std::vector<StrokeKind> kinds_;
    std::vector<int> pending_;
    double lastEnd_ = 0.0;
    std::vector<Entry> history_;
};

}  // namespace vsculpt::sketch
