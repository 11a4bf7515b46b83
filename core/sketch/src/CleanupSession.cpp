#include "vsculpt/sketch/CleanupSession.h"

#include "CleanupGeometry.h"
#include "vsculpt/sketch/FeaturePoints.h"
#include "vsculpt/sketch/NaturalSpline.h"
#include "vsculpt/sketch/ResampleStroke.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>

namespace vsculpt::sketch {

namespace {

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

}  // namespace

CleanupSession::CleanupSession(CleanupParams params) : params_(std::move(params)) {
    const CleanupParams& p = params_;
    if (!(p.pauseSeconds > 0.0)) throw std::invalid_argument("CleanupSession: pauseSeconds <= 0");
    if (!(p.pressureThreshold >= 0.0 && p.pressureThreshold <= 1.0))
        throw std::invalid_argument("CleanupSession: pressureThreshold outside [0, 1]");
    if (p.samplesPerSpan < 1) throw std::invalid_argument("CleanupSession: samplesPerSpan < 1");
    if (!(p.resampleSpacing > 0.0))
        throw std::invalid_argument("CleanupSession: resampleSpacing <= 0");
    if (!(p.attachDistance >= 0.0) || !(p.attachFraction > 0.0 && p.attachFraction <= 1.0))
        throw std::invalid_argument("CleanupSession: attach parameters out of range");
    if (!(p.knots.epsilon > 0.0)) throw std::invalid_argument("CleanupSession: epsilon <= 0");
}

int CleanupSession::addStroke(const Stroke& stroke, StrokeKind kind) {
    validateStroke(stroke);
    if (!(strokeLength(stroke) > 0.0))
        throw std::invalid_argument("CleanupSession::addStroke: stroke has zero length");
    if (!pending_.empty()) {
        const bool kindChange = kinds_[std::size_t(pending_.front())] != kind;
        const bool paused = params_.trigger == CleanupTrigger::PauseTime &&
                            stroke.samples.front().time - lastEnd_ >= params_.pauseSeconds;
        if (kindChange || paused) endGroup();
    }
    const int id = int(strokes_.size());
    strokes_.push_back(stroke);
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
        buildCurve({strokeId}, knots, closed);
        curve = makeCurve(curveId, kind, std::move(knots), closed, {strokeId});
    }
    e.versions.push_back(std::make_shared<const CleanCurve>(std::move(curve)));
    e.current = int(e.versions.size()) - 1;
    return e.current;
}

Polyline2 CleanupSession::resampled(int strokeId) const {
    return strokePositions(
        resampleByArcLength(strokes_[std::size_t(strokeId)], params_.resampleSpacing));
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

void CleanupSession::buildCurve(const std::vector<int>& strokeIds, Polyline2& knots,
                                bool& closed) const {
    const Polyline2 original = knots;
    // A loop in one stroke: three points cannot describe it, so take the feature points of its
    // two halves (split at the point farthest from the start).
    auto loopKnots = [&](Polyline2 poly) {
        poly = trimLoop(poly);
        std::size_t far = 1;
        for (std::size_t k = 1; k < poly.size(); ++k)
            if (glm::distance(poly[k], poly[0]) > glm::distance(poly[far], poly[0])) far = k;
        const Polyline2 first(poly.begin(), poly.begin() + std::ptrdiff_t(far) + 1);
        const Polyline2 second(poly.begin() + std::ptrdiff_t(far), poly.end());
        Polyline2 out = strokeFeaturePoints(first, params_.featureChordRatio);
        const Polyline2 f2 = strokeFeaturePoints(second, params_.featureChordRatio);
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
            continue;
        }
        if (knots.size() < 2) {
            if (poly.size() >= 6 && isClosedStroke(poly, params_.closedness)) {
                knots = loopKnots(poly);
                closed = true;
            } else {
                knots = strokeFeaturePoints(poly, params_.featureChordRatio);
                closed = false;
            }
            continue;
        }
        JoinResult joined = joinFeaturePoints(
            knots, closed, strokeFeaturePoints(poly, params_.featureChordRatio), params_.join);
        knots = std::move(joined.points);
        if (joined.overlap == Overlap::Closes) closed = true;
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
    if (!params_.smooth || knots.size() < (closed ? 4u : 3u)) return;
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
        if (lo > hi) return;  // nothing new survived
        lo = lo > 0 ? lo - 1 : 0;
        hi = std::min(hi + 1, knots.size() - 1);
        if (!closed || lo > 0 || hi < knots.size() - 1) {
            const Polyline2 stretch(curve.begin() + std::ptrdiff_t(lo * sps),
                                    curve.begin() + std::ptrdiff_t(hi * sps) + 1);
            Polyline2 result(knots.begin(), knots.begin() + std::ptrdiff_t(lo));
            for (std::size_t i : knotDivision(stretch, false, params_.knots))
                result.push_back(stretch[i]);
            result.insert(result.end(), knots.begin() + std::ptrdiff_t(hi) + 1, knots.end());
            if (result.size() >= (closed ? 3u : 2u)) knots = std::move(result);
            return;
        }
    }
    Polyline2 kept;
    for (std::size_t i : knotDivision(curve, closed, params_.knots))
        kept.push_back(curve[i]);
    if (kept.size() >= (closed ? 3u : 2u)) knots = std::move(kept);
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
        if (!params_.ignoreScribbles || !isScribble(strokes_[std::size_t(id)], params_.scribble))
            ids.push_back(id);
    std::vector<int> touched;
    if (ids.empty()) return touched;
    if (kinds_[std::size_t(ids.front())] == StrokeKind::Line) {
        for (int id : ids)
            cleanLineStroke(id, history, touched);
        return touched;
    }

    // Which existing curve, if any, does the group correct? The one most of its ink lies on.
    std::vector<glm::dvec2> ink;
    for (int id : ids) {
        const Polyline2 p = resampled(id);
        ink.insert(ink.end(), p.begin(), p.end());
    }
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
    buildCurve(ids, knots, closed);
    strokeIds.insert(strokeIds.end(), ids.begin(), ids.end());
    if (target < 0) {
        target = int(history.size());
        history.push_back({});
    }
    Entry& e = history[std::size_t(target)];
    e.versions.push_back(std::make_shared<const CleanCurve>(
        makeCurve(target, StrokeKind::Curve, std::move(knots), closed, strokeIds)));
    e.current = int(e.versions.size()) - 1;
    touched.push_back(target);
    return touched;
}

}  // namespace vsculpt::sketch
