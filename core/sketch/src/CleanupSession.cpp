#include "vsculpt/sketch/CleanupSession.h"

#include "CleanupGeometry.h"
#include "vsculpt/sketch/FeaturePoints.h"
#include "vsculpt/sketch/NaturalSpline.h"
#include "vsculpt/sketch/ResampleStroke.h"
#include "vsculpt/sketch/ScribbleDetection.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <utility>

namespace vsculpt::sketch {

namespace {

// Output polylines hold knots x samplesPerSpan points per curve version; beyond this the
// density is invisible and only costs memory.
constexpr int kMaxSamplesPerSpan = 256;

bool contains(const std::vector<int>& v, int x) {
    return std::find(v.begin(), v.end(), x) != v.end();
}

// A loop stroke closes on itself, often with an overshoot: cut it where it comes back nearest
// to its start (searched in its last third) so the loop is traced once.
Polyline2 trimLoop(const Polyline2& poly) {
    std::size_t best = poly.size() - 1;
    for (std::size_t k = poly.size() - 1; k >= poly.size() * 2 / 3 && k > 0; --k)
        if (glm::distance(poly[k], poly[0]) < glm::distance(poly[best], poly[0])) best = k;
    return Polyline2(poly.begin(), poly.begin() + std::ptrdiff_t(best) + 1);
}

// Every k-th point (and the last) so that at most maxPoints remain; evenly spread by index.
Polyline2 thinEvenly(const Polyline2& points, std::size_t maxPoints, bool closed) {
    const std::size_t n = points.size();
    if (n <= maxPoints) return points;
    Polyline2 out;
    out.reserve(maxPoints);
    // Open: both ends stay. Closed: the loop has n spans and the first point stands for both.
    const std::size_t last = closed ? maxPoints : maxPoints - 1;
    const std::size_t span = closed ? n : n - 1;
    for (std::size_t i = 0; i < maxPoints; ++i)
        out.push_back(points[i * span / last]);
    return out;
}

// Knot division keeping at most maxKeep points: epsilon grows until it does, so the most
// significant shape survives; evenly thinned indices are the last resort. `wanted` is how many
// the plain division keeps.
std::vector<std::size_t> divideWithin(const Polyline2& curve, bool closed, KnotDivisionParams p,
                                      std::size_t maxKeep, std::size_t& wanted) {
    std::vector<std::size_t> keep = knotDivision(curve, closed, p);
    wanted = keep.size();
    // Growing by sqrt(2) overshoots the limit less than doubling; 80 steps multiply epsilon by
    // 1e12, beyond which every curve is one straight span.
    for (int round = 0; round < 80 && keep.size() > maxKeep; ++round) {
        p.epsilon *= std::sqrt(2.0);
        keep = knotDivision(curve, closed, p);
    }
    if (keep.size() > maxKeep) {
        std::vector<std::size_t> thinned;
        const std::size_t last = closed ? maxKeep : maxKeep - 1;
        const std::size_t span = closed ? keep.size() : keep.size() - 1;
        for (std::size_t i = 0; i < maxKeep; ++i)
            thinned.push_back(keep[i * span / last]);
        keep = std::move(thinned);
    }
    return keep;
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

}  // namespace

CleanupSession::CleanupSession(CleanupParams params) : params_(std::move(params)) {
    const CleanupParams& p = params_;
    if (!(p.pauseSeconds > 0.0)) throw std::invalid_argument("CleanupSession: pauseSeconds <= 0");
    if (!(p.pressureThreshold >= 0.0 && p.pressureThreshold <= 1.0))
        throw std::invalid_argument("CleanupSession: pressureThreshold outside [0, 1]");
    if (p.samplesPerSpan < 1 || p.samplesPerSpan > kMaxSamplesPerSpan ||
        p.join.samplesPerSpan < 1 || p.join.samplesPerSpan > kMaxSamplesPerSpan)
        throw std::invalid_argument("CleanupSession: samplesPerSpan outside [1, 256]");
    if (!(p.resampleSpacing > 0.0))
        throw std::invalid_argument("CleanupSession: resampleSpacing <= 0");
    if (!(p.attachDistance >= 0.0) || !(p.attachFraction > 0.0 && p.attachFraction <= 1.0))
        throw std::invalid_argument("CleanupSession: attach parameters out of range");
    if (!(p.knots.epsilon > 0.0)) throw std::invalid_argument("CleanupSession: epsilon <= 0");
    const CleanupLimits& l = p.limits;
    if (l.maxStrokePoints < 16 || l.maxFeaturePoints < 4 || l.maxCurveKnots < 8 ||
        l.maxGroupInkPoints < 16)
        throw std::invalid_argument("CleanupSession: limits below their minimums");
    // Checked here so that addStroke's scribble test cannot throw for a bad parameter later.
    if (p.ignoreScribbles) isScribble(Polyline2{{0.0, 0.0}, {1.0, 0.0}, {2.0, 1.0}}, p.scribble);
}

int CleanupSession::addStroke(const Stroke& stroke, StrokeKind kind) {
    validateStroke(stroke);
    StrokeReport report;
    report.samples = stroke.samples.size();
    report.length = strokeLength(stroke);
    if (!(report.length > 0.0))
        throw std::invalid_argument("CleanupSession::addStroke: stroke has zero length");
    const CleanupLimits& limits = params_.limits;
    report.spacing = boundedSpacing(report.length, params_.resampleSpacing, limits.maxStrokePoints);
    report.coarsened = report.spacing > params_.resampleSpacing;
    const Polyline2 poly =
        strokePositions(resampleBySpacing(stroke, report.spacing, limits.maxStrokePoints));
    report.points = poly.size();
    if (kind == StrokeKind::Curve) {
        // Asking for one more than the cap tells whether the cap cut anything off.
        const std::size_t features = featurePoints(poly, limits.maxFeaturePoints + 1).size();
        report.featuresCapped = features > limits.maxFeaturePoints;
        report.featurePoints = std::min(features, limits.maxFeaturePoints);
    }
    report.scribble = params_.ignoreScribbles && isScribble(stroke, params_.scribble);
    if (report.coarsened)
        report.note = "resampled every " + number(report.spacing) + " mm instead of " +
                      number(params_.resampleSpacing) + " mm: " + number(report.length) +
                      " mm of ink exceeds the " + std::to_string(limits.maxStrokePoints) +
                      "-point limit";
    if (report.featuresCapped)
        report.note += std::string(report.note.empty() ? "" : "; ") + "feature points cut to " +
                       std::to_string(limits.maxFeaturePoints) + " (limit), the largest kept";
    if (!pending_.empty()) {
        const bool kindChange = kinds_[std::size_t(pending_.front())] != kind;
        const bool paused = params_.trigger == CleanupTrigger::PauseTime &&
                            stroke.samples.front().time - lastEnd_ >= params_.pauseSeconds;
        if (kindChange || paused) endGroup();
    }
    const int id = int(strokes_.size());
    reports_.reserve(reports_.size() + 1);
    kinds_.reserve(kinds_.size() + 1);
    pending_.reserve(pending_.size() + 1);
    strokes_.push_back(stroke);
    reports_.push_back(std::move(report));
    kinds_.push_back(kind);
    pending_.push_back(id);
    lastEnd_ = stroke.samples.back().time;
    if (params_.trigger == CleanupTrigger::Pressure &&
        peakPressure(stroke) >= params_.pressureThreshold)
        endGroup();
    return id;
}

bool CleanupSession::advanceTime(double now) {
    if (params_.trigger != CleanupTrigger::PauseTime || pending_.empty()) return false;
    if (now - lastEnd_ < params_.pauseSeconds) return false;
    return endGroup();
}

bool CleanupSession::endGroup() {
    if (pending_.empty()) return false;
    // Work on a copy so that a failure leaves the session as it was (strong guarantee).
    std::vector<Entry> next = history_;
    cleanGroup(pending_, next);
    history_ = std::move(next);
    pending_.clear();
    return true;
}

std::vector<CleanCurve> CleanupSession::previewPending() const {
    std::vector<Entry> copy = history_;
    std::vector<CleanCurve> out;
    for (int id : cleanGroup(pending_, copy)) {
        const Entry& e = copy[std::size_t(id)];
        out.push_back(e.cur());
    }
    return out;
}

const StrokeReport& CleanupSession::strokeReport(int strokeId) const {
    return reports_.at(std::size_t(strokeId));
}

StrokeKind CleanupSession::strokeKind(int strokeId) const {
    return kinds_.at(std::size_t(strokeId));
}

std::vector<CleanCurve> CleanupSession::curves() const {
    std::vector<CleanCurve> out;
    out.reserve(history_.size());
    for (const Entry& e : history_)
        out.push_back(e.cur());
    return out;
}

const CleanCurve& CleanupSession::curve(int curveId) const {
    return history_.at(std::size_t(curveId)).cur();
}

std::size_t CleanupSession::versionCount(int curveId) const {
    return history_.at(std::size_t(curveId)).versions.size();
}

const CleanCurve& CleanupSession::version(int curveId, int version) const {
    const Entry& e = history_.at(std::size_t(curveId));
    if (version < 0 || std::size_t(version) >= e.versions.size())
        throw std::out_of_range("CleanupSession::version: no such version");
    return *e.versions[std::size_t(version)];
}

int CleanupSession::currentVersion(int curveId) const {
    return history_.at(std::size_t(curveId)).current;
}

void CleanupSession::selectVersion(int curveId, int version) {
    Entry& e = history_.at(std::size_t(curveId));
    if (version < 0 || std::size_t(version) >= e.versions.size())
        throw std::out_of_range("CleanupSession::selectVersion: no such version");
    e.current = version;
}

int CleanupSession::restartFromStroke(int curveId, int strokeId) {
    Entry& e = history_.at(std::size_t(curveId));
    const StrokeKind kind = kinds_.at(std::size_t(strokeId));
    if (kind != e.versions.front()->kind)
        throw std::invalid_argument("CleanupSession::restartFromStroke: stroke kind differs");
    CleanCurve curve;
    if (kind == StrokeKind::Line) {
        const Segment2 s = fitSegment(resampled(strokeId));
        curve = makeCurve(curveId, kind, {s.a, s.b}, false, {strokeId});
    } else {
        Polyline2 knots;
        bool closed = false;
        std::string note = buildCurve({strokeId}, knots, closed);
        curve = makeCurve(curveId, kind, std::move(knots), closed, {strokeId});
        curve.limitNote = std::move(note);
    }
    e.versions.push_back(std::make_shared<const CleanCurve>(std::move(curve)));
    e.current = int(e.versions.size()) - 1;
    return e.current;
}

Polyline2 CleanupSession::resampled(int strokeId) const {
    const std::size_t i = std::size_t(strokeId);
    return strokePositions(
        resampleBySpacing(strokes_[i], reports_[i].spacing, params_.limits.maxStrokePoints));
}

Polyline2 CleanupSession::featurePoints(const Polyline2& poly, std::size_t maxPoints) const {
    return strokeFeaturePoints(poly, params_.featureChordRatio, maxPoints);
}

std::string CleanupSession::capKnots(Polyline2& knots, bool closed) const {
    const std::size_t cap = params_.limits.maxCurveKnots;
    if (knots.size() <= cap) return {};
    const std::size_t before = knots.size();
    Polyline2 kept;
    try {
        // Knot division is what smoothing does anyway; it keeps the shape better than thinning.
        const Polyline2 curve = sampleNaturalSpline(knots, closed, params_.samplesPerSpan);
        std::size_t wanted = 0;
        for (std::size_t i : divideWithin(curve, closed, params_.knots, cap, wanted))
            kept.push_back(curve[i]);
    } catch (const std::invalid_argument&) {
        kept.clear();  // coincident knots: no spline through them, thin them instead
    }
    knots = kept.size() >= (closed ? 3u : 2u) ? std::move(kept) : thinEvenly(knots, cap, closed);
    return knotCapNote(before, knots.size());
}

std::string CleanupSession::knotCapNote(std::size_t before, std::size_t after) const {
    return "curve simplified from " + std::to_string(before) + " to " + std::to_string(after) +
           " knots (limit " + std::to_string(params_.limits.maxCurveKnots) + ")";
}

CleanCurve CleanupSession::makeCurve(int id, StrokeKind kind, Polyline2 knots, bool closed,
                                     std::vector<int> strokeIds) const {
    CleanCurve c;
    c.id = id;
    c.kind = kind;
    c.closed = closed;
    c.strokes = std::move(strokeIds);
    if (kind == StrokeKind::Curve && knots.size() >= (closed ? 3u : 2u))
        c.samples = sampleNaturalSpline(knots, closed, params_.samplesPerSpan);
    else
        c.samples = knots;
    c.knots = std::move(knots);
    return c;
}

std::string CleanupSession::buildCurve(const std::vector<int>& strokeIds, Polyline2& knots,
                                       bool& closed) const {
    std::string note = capKnots(knots, closed);
    const auto cap = [&] {
        std::string n = capKnots(knots, closed);
        if (!n.empty()) note = std::move(n);
    };
    const Polyline2 original = knots;
    // A loop's two halves share the feature-point limit.
    const std::size_t halfCap = params_.limits.maxFeaturePoints / 2 + 1;
    // A loop in one stroke: three points cannot describe it, so take the feature points of its
    // two halves (split at the point farthest from the start).
    auto loopKnots = [&](Polyline2 poly) {
        poly = trimLoop(poly);
        std::size_t far = 1;
        for (std::size_t k = 1; k < poly.size(); ++k)
            if (glm::distance(poly[k], poly[0]) > glm::distance(poly[far], poly[0])) far = k;
        const Polyline2 first(poly.begin(), poly.begin() + std::ptrdiff_t(far) + 1);
        const Polyline2 second(poly.begin() + std::ptrdiff_t(far), poly.end());
        Polyline2 out = featurePoints(first, halfCap);
        const Polyline2 f2 = featurePoints(second, halfCap);
        // f2's first point is the split point, its last returns to the start.
        out.insert(out.end(), f2.begin() + 1, f2.end() - 1);
        return out;
    };
    for (int id : strokeIds) {
        Polyline2 poly = resampled(id);
        if (poly.size() < 2) continue;
        if (closed && knots.size() >= 3 && poly.size() >= 6 &&
            isClosedStroke(poly, params_.closedness)) {
            // A whole loop drawn over a loop overlaps all of it, so the newer loop wins
            // everywhere (seed rule (a)); joining it at one place would go round twice.
            // With newStrokeWeight < 1 the loops are blended point by point instead.
            Polyline2 newer = loopKnots(poly);
            const double w = params_.join.newStrokeWeight;
            if (w < 1.0) {
                const Polyline2 older = sampleNaturalSpline(knots, true, params_.samplesPerSpan);
                for (glm::dvec2& q : newer) {
                    glm::dvec2 best = older.front();
                    for (const glm::dvec2& o : older)
                        if (glm::distance(o, q) < glm::distance(best, q)) best = o;
                    q = best + w * (q - best);
                }
            }
            knots = std::move(newer);
            cap();
            continue;
        }
        if (knots.size() < 2) {
            if (poly.size() >= 6 && isClosedStroke(poly, params_.closedness)) {
                knots = loopKnots(poly);
                closed = true;
            } else {
                knots = featurePoints(poly, params_.limits.maxFeaturePoints);
                closed = false;
            }
            cap();
            continue;
        }
        JoinResult joined = joinFeaturePoints(
            knots, closed, featurePoints(poly, params_.limits.maxFeaturePoints), params_.join);
        knots = std::move(joined.points);
        if (joined.overlap == Overlap::Closes) closed = true;
        // Chained strokes add their points each time; without the cap a long group would make
        // every later join and the final smoothing ever more expensive.
        cap();
    }
    if (!closed && knots.size() >= 4) {
        const Polyline2 curve = sampleNaturalSpline(knots, false, params_.samplesPerSpan);
        if (glm::distance(knots.front(), knots.back()) <=
            params_.closedness.maxGapRatio * length(curve, false)) {
            closed = true;
            if (glm::distance(knots.front(), knots.back()) < params_.join.mergeDistance)
                knots.pop_back();
        }
    }
    if (!params_.smooth || knots.size() < (closed ? 4u : 3u)) return note;
    const Polyline2 curve = sampleNaturalSpline(knots, closed, params_.samplesPerSpan);
    const std::size_t sps = std::size_t(params_.samplesPerSpan);
    const bool unmerged =
        curve.size() == (closed ? knots.size() * sps : (knots.size() - 1) * sps + 1);
    if (!original.empty() && unmerged) {
        // A correction: re-smooth only from the old knot before its first new knot to the old
        // knot after its last one, so the untouched part keeps its knots exactly.
        std::size_t lo = knots.size(), hi = 0;
        for (std::size_t i = 0; i < knots.size(); ++i)
            if (std::find(original.begin(), original.end(), knots[i]) == original.end()) {
                lo = std::min(lo, i);
                hi = std::max(hi, i);
            }
        if (lo > hi) return note;  // nothing new survived
        lo = lo > 0 ? lo - 1 : 0;
        hi = std::min(hi + 1, knots.size() - 1);
        if (!closed || lo > 0 || hi < knots.size() - 1) {
            const Polyline2 stretch(curve.begin() + std::ptrdiff_t(lo * sps),
                                    curve.begin() + std::ptrdiff_t(hi * sps) + 1);
            Polyline2 result(knots.begin(), knots.begin() + std::ptrdiff_t(lo));
            for (std::size_t i : knotDivision(stretch, false, params_.knots))
                result.push_back(stretch[i]);
            result.insert(result.end(), knots.begin() + std::ptrdiff_t(hi) + 1, knots.end());
            // Too many: smooth the whole curve below, where the limit can be applied evenly.
            if (result.size() <= params_.limits.maxCurveKnots) {
                if (result.size() >= (closed ? 3u : 2u)) knots = std::move(result);
                return note;
            }
        }
    }
    // Knot division picks among the spline samples, up to samplesPerSpan per knot on a wavy
    // curve, so it can return more knots than it was given.
    std::size_t wanted = 0;
    Polyline2 kept;
    for (std::size_t i :
         divideWithin(curve, closed, params_.knots, params_.limits.maxCurveKnots, wanted))
        kept.push_back(curve[i]);
    if (wanted > kept.size()) note = knotCapNote(wanted, kept.size());
    if (kept.size() >= (closed ? 3u : 2u)) knots = std::move(kept);
    return note;
}

Polyline2 CleanupSession::anchoredKnots(const CleanCurve& cur, const std::vector<int>& ids) const {
    const std::size_t sps = std::size_t(params_.samplesPerSpan);
    const std::size_t n = cur.knots.size();
    Polyline2 path = cur.samples;
    if (cur.closed) path.push_back(path.front());
    if (path.size() != (cur.closed ? n : n - 1) * sps + 1) return cur.knots;  // merged knots
    std::vector<double> acc(path.size(), 0.0);
    for (std::size_t i = 1; i < path.size(); ++i)
        acc[i] = acc[i - 1] + glm::distance(path[i - 1], path[i]);
    const double total = acc.back();
    const auto pointAt = [&](double s) {
        if (cur.closed) s = std::fmod(std::fmod(s, total) + total, total);
        s = std::clamp(s, 0.0, total);
        const std::size_t i =
            std::size_t(std::upper_bound(acc.begin(), acc.end(), s) - acc.begin());
        if (i >= path.size()) return std::pair{total, path.back()};
        const double seg = acc[i] - acc[i - 1];
        const double t = seg > 0.0 ? (s - acc[i - 1]) / seg : 0.0;
        return std::pair{s, path[i - 1] + t * (path[i] - path[i - 1])};
    };
    std::vector<std::pair<double, glm::dvec2>> knots;
    for (std::size_t i = 0; i < n; ++i)
        knots.push_back({acc[i * sps], cur.knots[i]});
    const double margin = 2.0 * params_.join.mergeDistance;
    for (int id : ids) {
        const Polyline2 poly = resampled(id);
        for (const glm::dvec2& end : {poly.front(), poly.back()}) {
            const detail::Projection q = detail::project(path, end);
            if (q.distance > params_.join.overlapDistance || q.atStart || q.atEnd) continue;
            for (double s : {q.s - 3.0 * margin, q.s - margin, q.s + margin, q.s + 3.0 * margin}) {
                // Pins cost a crowding test against every knot; a group of thousands of strokes
                // would make that quadratic, and buildCurve would cap the knots anyway.
                if (knots.size() >= params_.limits.maxCurveKnots) break;
                const auto [sAt, p] = pointAt(s);
                const bool crowded = std::any_of(knots.begin(), knots.end(), [&](const auto& k) {
                    return glm::distance(k.second, p) < params_.join.mergeDistance;
                });
                if (!crowded) knots.push_back({sAt, p});
            }
        }
    }
    std::stable_sort(knots.begin(), knots.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    Polyline2 out;
    for (const auto& k : knots)
        out.push_back(k.second);
    return out;
}

void CleanupSession::cleanLineStroke(int strokeId, std::vector<Entry>& history,
                                     std::vector<int>& touched) const {
    const Segment2 seg = fitSegment(resampled(strokeId));
    int best = -1;
    double bestDist = 0.0;
    for (std::size_t i = 0; i < history.size(); ++i) {
        const CleanCurve& c = history[i].cur();
        if (c.kind != StrokeKind::Line) continue;
        const Segment2 line{c.knots[0], c.knots[1]};
        if (!isSameLine(line, seg, params_.line)) continue;
        const double d = detail::project(c.knots, 0.5 * (seg.a + seg.b)).distance;
        if (best < 0 || d < bestDist) {
            best = int(i);
            bestDist = d;
        }
    }
    if (best < 0) {
        Entry e;
        e.versions.push_back(std::make_shared<const CleanCurve>(
            makeCurve(int(history.size()), StrokeKind::Line, {seg.a, seg.b}, false, {strokeId})));
        touched.push_back(int(history.size()));
        history.push_back(std::move(e));
        return;
    }
    Entry& e = history[std::size_t(best)];
    const CleanCurve& cur = e.cur();
    LineMixParams mix = params_.line;
    if (params_.lineRunningMean)
        mix.angleWeight = mix.offsetWeight = 1.0 / double(cur.strokes.size() + 1);
    const Segment2 mixed = mixSegments({cur.knots[0], cur.knots[1]}, seg, mix);
    std::vector<int> ids = cur.strokes;
    ids.push_back(strokeId);
    CleanCurve next = makeCurve(best, StrokeKind::Line, {mixed.a, mixed.b}, false, ids);
    if (contains(touched, best)) {
        e.versions[std::size_t(e.current)] =
            std::make_shared<const CleanCurve>(std::move(next));  // one version per group
    } else {
        e.versions.push_back(std::make_shared<const CleanCurve>(std::move(next)));
        e.current = int(e.versions.size()) - 1;
        touched.push_back(best);
    }
}

std::vector<int> CleanupSession::cleanGroup(const std::vector<int>& group,
                                            std::vector<Entry>& history) const {
    std::vector<int> ids;
    for (int id : group)
        if (!reports_[std::size_t(id)].scribble) ids.push_back(id);
    std::vector<int> touched;
    if (ids.empty()) return touched;
    if (kinds_[std::size_t(ids.front())] == StrokeKind::Line) {
        for (int id : ids)
            cleanLineStroke(id, history, touched);
        return touched;
    }

    // Which existing curve, if any, does the group correct? The one most of its ink lies on.
    // Each ink point is projected onto every nearby curve, so a huge group tests every k-th.
    std::size_t inkTotal = 0;
    for (int id : ids)
        inkTotal += reports_[std::size_t(id)].points;
    const std::size_t stride = std::max<std::size_t>(
        1, (inkTotal + params_.limits.maxGroupInkPoints - 1) / params_.limits.maxGroupInkPoints);
    std::vector<glm::dvec2> ink;
    ink.reserve(std::min(inkTotal, params_.limits.maxGroupInkPoints));
    std::size_t inkIndex = 0;
    for (int id : ids)
        for (const glm::dvec2& p : resampled(id))
            if (inkIndex++ % stride == 0) ink.push_back(p);
    glm::dvec2 inkLo = ink.front(), inkHi = ink.front();
    for (const glm::dvec2& p : ink) {
        inkLo = glm::min(inkLo, p);
        inkHi = glm::max(inkHi, p);
    }
    int target = -1;
    double bestFraction = 0.0;
    for (std::size_t i = 0; i < history.size(); ++i) {
        const CleanCurve& c = history[i].cur();
        if (c.kind != StrokeKind::Curve || c.samples.empty()) continue;
        glm::dvec2 lo = c.samples.front(), hi = lo;
        for (const glm::dvec2& p : c.samples) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        // Cheap rejection before projecting every ink point: boxes too far apart to attach.
        const double d = params_.attachDistance;
        if (lo.x - d > inkHi.x || inkLo.x > hi.x + d || lo.y - d > inkHi.y || inkLo.y > hi.y + d)
            continue;
        Polyline2 path = c.samples;
        if (c.closed) path.push_back(path.front());
        std::size_t near = 0;
        for (const glm::dvec2& p : ink)
            if (detail::project(path, p).distance <= params_.attachDistance) ++near;
        const double fraction = double(near) / double(ink.size());
        if (fraction >= params_.attachFraction && fraction > bestFraction) {
            bestFraction = fraction;
            target = int(i);
        }
    }
    Polyline2 knots;
    bool closed = false;
    std::vector<int> strokeIds;
    if (target >= 0) {
        const CleanCurve& cur = history[std::size_t(target)].cur();
        knots = anchoredKnots(cur, ids);
        closed = cur.closed;
        strokeIds = cur.strokes;
    }
    std::string note = buildCurve(ids, knots, closed);
    strokeIds.insert(strokeIds.end(), ids.begin(), ids.end());
    if (target < 0) {
        target = int(history.size());
        history.push_back({});
    }
    Entry& e = history[std::size_t(target)];
    CleanCurve next = makeCurve(target, StrokeKind::Curve, std::move(knots), closed, strokeIds);
    next.limitNote = std::move(note);
    e.versions.push_back(std::make_shared<const CleanCurve>(std::move(next)));
    e.current = int(e.versions.size()) - 1;
    touched.push_back(target);
    return touched;
}

}  // namespace vsculpt::sketch
