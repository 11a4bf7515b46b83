#include "vsculpt/studio/SketchDocument.h"

#include "vsculpt/core/JsonNesting.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>

namespace vsculpt::studio {

// The geometry this editor drives lives in core/sketch.
using namespace vsculpt::sketch;

namespace {

bool finite2(glm::dvec2 v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
}

[[noreturn]] void invalid(const std::string& what) {
    throw std::invalid_argument(what);
}

using L = SketchLimits;

bool within(double v, double bound) {
    return std::abs(v) <= bound;  // false for NaN
}
bool within2(glm::dvec2 v, double bound) {
    return within(v.x, bound) && within(v.y, bound);
}
bool scaleInRange(double scale) {
    return scale >= L::minViewScale && scale <= L::maxViewScale;  // false for NaN
}
bool factorInRange(double f) {
    return f >= L::minEditFactor && f <= L::maxEditFactor;
}
void checkName(const std::string& name, const char* what) {
    if (name.size() > L::maxNameBytes) invalid(std::string(what) + " is longer than 1024 bytes");
}

double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double len2 = ab.x * ab.x + ab.y * ab.y;
    double t = len2 > 0.0 ? ((p.x - a.x) * ab.x + (p.y - a.y) * ab.y) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const glm::dvec2 d = p - (a + t * ab);
    return std::sqrt(d.x * d.x + d.y * d.y);
}

bool insidePolygon(glm::dvec2 p, const Polyline2& poly) {
    bool inside = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const glm::dvec2 a = poly[i], b = poly[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
            inside = !inside;
    }
    return inside;
}

bool twoDistinctPoints(const Stroke& s) {
    for (const StrokeSample& x : s.samples)
        if (x.position != s.samples.front().position) return true;
    return false;
}

// The page decides when groups end (each clean-up is its own undoable action), so the session
// only ever cleans up on endGroup().
CleanupParams sessionParams(const CleanupParams& p) {
    CleanupParams out = p;
    out.trigger = CleanupTrigger::Explicit;
    return out;
}

SketchAction action(SketchAction::Type type) {
    SketchAction a;
    a.type = type;
    return a;
}

void checkUniqueIds(const std::vector<int>& ids, const char* what) {
    std::set<int> seen;
    for (int id : ids)
        if (!seen.insert(id).second)
            invalid(std::string(what) + ": stroke " + std::to_string(id) + " listed twice");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// View

void CanvasView::zoomAbout(glm::dvec2 viewPoint, double factor) {
    if (!finite2(viewPoint)) invalid("zoomAbout: non-finite view point");
    if (!within2(viewPoint, L::maxViewMm)) invalid("zoomAbout: view point outside [-1e9, 1e9] mm");
    if (!(std::isfinite(factor) && factor > 0.0)) invalid("zoomAbout: factor must be > 0");
    const double newScale = scale / factor;
    if (!scaleInRange(newScale)) invalid("zoomAbout: zoom out of range [1e-9, 1e9]");
    const glm::dvec2 fixed = canvasFromView(viewPoint);
    const glm::dvec2 newOffset = fixed - newScale * viewPoint;
    if (!within2(newOffset, L::maxViewOffsetMm))
        invalid("zoomAbout: the view would leave [-1e9, 1e9] mm");
    scale = newScale;
    offset = newOffset;
}

void CanvasView::pan(glm::dvec2 deltaView) {
    if (!finite2(deltaView)) invalid("pan: non-finite delta");
    if (!within2(deltaView, L::maxViewMm)) invalid("pan: delta outside [-1e9, 1e9] mm");
    const glm::dvec2 newOffset = offset - scale * deltaView;
    if (!within2(newOffset, L::maxViewOffsetMm))
        invalid("pan: the view would leave [-1e9, 1e9] mm");
    offset = newOffset;
}

// ---------------------------------------------------------------------------------------------
// Ink

void validateInkParams(const InkParams& k) {
    const auto fin = [](double v) { return std::isfinite(v); };
    if (!(fin(k.minWidth) && k.minWidth > 0.0)) invalid("ink.minWidth must be > 0");
    if (!(fin(k.maxWidth) && k.maxWidth >= k.minWidth))
        invalid("ink.maxWidth must be >= ink.minWidth");
    if (!(fin(k.minDarkness) && k.minDarkness >= 0.0 && k.minDarkness <= 1.0))
        invalid("ink.minDarkness must be in [0, 1]");
    if (!(fin(k.maxDarkness) && k.maxDarkness >= k.minDarkness && k.maxDarkness <= 1.0))
        invalid("ink.maxDarkness must be in [ink.minDarkness, 1]");
    if (!(fin(k.gamma) && k.gamma > 0.0)) invalid("ink.gamma must be > 0");
    if (!(fin(k.cleanWidth) && k.cleanWidth > 0.0)) invalid("ink.cleanWidth must be > 0");
}

namespace {
double pressureCurve(double pressure, const InkParams& ink) {
    if (!(pressure >= 0.0 && pressure <= 1.0)) invalid("ink: pressure outside [0, 1]");
    // std::lerp is exact at both ends and monotone, so the endpoints are the parameters.
    return std::pow(pressure, ink.gamma);
}
}  // namespace

double inkWidth(double pressure, const InkParams& ink) {
    return std::lerp(ink.minWidth, ink.maxWidth, pressureCurve(pressure, ink));
}

double inkDarkness(double pressure, const InkParams& ink) {
    return std::lerp(ink.minDarkness, ink.maxDarkness, pressureCurve(pressure, ink));
}

const char* roleName(Role role) {
    switch (role) {
        case Role::None:
            return "none";
        case Role::Outline:
            return "outline";
        case Role::SurfaceLineX:
            return "surfaceLineX";
        case Role::SurfaceLineY:
            return "surfaceLineY";
        case Role::SurfaceLineZ:
            return "surfaceLineZ";
        case Role::SweepSection:
            return "sweepSection";
        case Role::SweepPath:
            return "sweepPath";
        case Role::Cut:
            return "cut";
        case Role::Extrude:
            return "extrude";
    }
    return "none";
}

// ---------------------------------------------------------------------------------------------
// Content hash

namespace {
struct Fnv {
    std::uint64_t h = 1469598103934665603ULL;
    void bytes(const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) {
            h ^= b[i];
            h *= 1099511628211ULL;
        }
    }
    void i(std::int64_t v) { bytes(&v, sizeof v); }
    void d(double v) {
        if (v == 0.0) v = 0.0;  // -0.0 == 0.0 under operator==
        bytes(&v, sizeof v);
    }
    void v2(glm::dvec2 v) {
        d(v.x);
        d(v.y);
    }
    void line(const Polyline2& l) {
        i(std::int64_t(l.size()));
        for (glm::dvec2 p : l)
            v2(p);
    }
    void ids(const std::vector<int>& v) {
        i(std::int64_t(v.size()));
        for (int x : v)
            i(x);
    }
};
}  // namespace

std::uint64_t contentHash(const PageContent& c) {
    Fnv f;
    f.i(std::int64_t(c.strokes.size()));
    for (const auto& s : c.strokes) {
        f.i(s.id);
        f.i(s.cleanup);
        f.i(int(s.kind));
        f.i(int(s.role));
        f.d(s.scale);
        f.v2(s.offset);
        f.line(s.points);
    }
    f.i(std::int64_t(c.curves.size()));
    for (const auto& k : c.curves) {
        f.i(k.id);
        f.i(int(k.kind));
        f.i(k.closed);
        f.i(k.version);
        f.i(k.versionCount);
        f.i(int(k.role));
        f.line(k.knots);
        f.line(k.samples);
        f.ids(k.strokes);
    }
    f.ids(c.pending);
    return f.h;
}

// ---------------------------------------------------------------------------------------------
// Page

SketchPage::SketchPage(std::string name, std::string group, const SketchParams& params)
    : name_(std::move(name)),
      group_(std::move(group)),
      params_(params),
      session_(sessionParams(params.cleanup)) {
    if (name_.empty()) invalid("page name must not be empty");
    checkName(name_, "page name");
    checkName(group_, "page group");
    validateInkParams(params_.ink);
}

void SketchPage::setName(std::string name) {
    if (name.empty()) invalid("page name must not be empty");
    checkName(name, "page name");
    name_ = std::move(name);
}

void SketchPage::setGroup(std::string group) {
    checkName(group, "page group");
    group_ = std::move(group);
}

void SketchPage::setView(const CanvasView& view) {
    if (!scaleInRange(view.scale)) invalid("view.scale must be in [1e-9, 1e9]");
    if (!within2(view.offset, L::maxViewOffsetMm)) invalid("view.offset must be in [-1e9, 1e9]");
    view_ = view;
}

// --- pen ---

namespace {
// Returns the sample's canvas position.
glm::dvec2 checkPenSample(const PenSample& s, const CanvasView& view, const char* call) {
    const std::string at = std::string(call) + ": ";
    if (!finite2(s.view)) invalid(at + "non-finite position");
    if (!within2(s.view, L::maxViewMm)) invalid(at + "view position outside [-1e9, 1e9] mm");
    if (!std::isfinite(s.time)) invalid(at + "non-finite time");
    if (!within(s.time, L::maxTime)) invalid(at + "time outside [-1e10, 1e10] s");
    if (s.pressure && !(*s.pressure >= 0.0 && *s.pressure <= 1.0))
        invalid(at + "pressure outside [0, 1]");
    if (s.tiltDeg && !(std::abs(s.tiltDeg->x) <= 90.0 && std::abs(s.tiltDeg->y) <= 90.0))
        invalid(at + "tilt outside [-90, 90] degrees");
    // A sane view point can still land far off the canvas through a zoomed-out view.
    const glm::dvec2 canvas = view.canvasFromView(s.view);
    if (!within2(canvas, L::maxCanvasMm))
        invalid(at + "canvas position outside [-1e6, 1e6] mm (the view maps the pen there)");
    return canvas;
}
}  // namespace

void SketchPage::penDown(const PenSample& sample) {
    if (drawing_) invalid("penDown: the pen is already down");
    const glm::dvec2 canvas = checkPenSample(sample, view_, "penDown");
    if (archive_.size() >= L::maxPageStrokes)
        invalid("penDown: the page holds 100000 strokes, the most a page can; add a page");
    if (mode_ == SketchMode::Cleanup && pendingGroupPaused(sample.time))
        record(action(SketchAction::Type::EndGroup));
    Drawing d;
    d.stroke.inkScale = view_.scale;
    d.stroke.stroke.hasPressure = sample.pressure.has_value();
    d.tilt = sample.tiltDeg.has_value();
    d.stroke.stroke.samples.push_back({canvas, sample.time, sample.pressure.value_or(1.0)});
    if (d.tilt) d.stroke.tiltDeg.push_back(*sample.tiltDeg);
    drawing_ = std::move(d);
}

void SketchPage::penMove(const PenSample& sample) {
    if (!drawing_) invalid("penMove: the pen is not down");
    const glm::dvec2 canvas = checkPenSample(sample, view_, "penMove");
    Stroke& s = drawing_->stroke.stroke;
    if (s.samples.size() >= L::maxStrokeSamples)
        invalid("penMove: the stroke has 100000 samples, the most a stroke can hold");
    if (sample.time < s.samples.back().time) invalid("penMove: time goes backwards");
    if (sample.pressure.has_value() != s.hasPressure)
        invalid("penMove: pressure present in some samples of the stroke and not in others");
    if (sample.tiltDeg.has_value() != drawing_->tilt)
        invalid("penMove: tilt present in some samples of the stroke and not in others");
    s.samples.push_back({canvas, sample.time, sample.pressure.value_or(1.0)});
    if (drawing_->tilt) drawing_->stroke.tiltDeg.push_back(*sample.tiltDeg);
}

std::optional<int> SketchPage::penUp(const std::optional<PenSample>& last) {
    if (!drawing_) invalid("penUp: the pen is not down");
    if (last) penMove(*last);
    ArchivedStroke stroke = std::move(drawing_->stroke);
    drawing_.reset();
    return addStrokeAction(std::move(stroke), true);
}

void SketchPage::cancelStroke() {
    drawing_.reset();
}

void SketchPage::hover(glm::dvec2 view) {
    if (!finite2(view)) invalid("hover: non-finite position");
    if (!within2(view, L::maxViewMm)) invalid("hover: position outside [-1e9, 1e9] mm");
    hover_ = view;
}

std::optional<glm::dvec2> SketchPage::hoverCanvas() const {
    if (!hover_) return std::nullopt;
    return view_.canvasFromView(*hover_);
}

std::optional<int> SketchPage::addStrokeAction(ArchivedStroke stroke, bool allowPressureTrigger) {
    const bool cleanup = mode_ == SketchMode::Cleanup;
    if (cleanup && !twoDistinctPoints(stroke.stroke)) return std::nullopt;
    if (archive_.size() >= L::maxPageStrokes)
        invalid("the page holds 100000 strokes, the most a page can; add a page");
    const int id = int(archive_.size());
    stroke.id = id;
    const double peak = peakPressure(stroke.stroke);
    archive_.push_back(std::move(stroke));
    try {
        // A change between line and curve ends the group first, as its own action.
        if (cleanup && !session_.pendingStrokes().empty() &&
            session_.strokeKind(session_.pendingStrokes().back()) != kind_)
            record(action(SketchAction::Type::EndGroup));
        SketchAction a = action(SketchAction::Type::Stroke);
        a.stroke = id;
        a.cleanup = cleanup;
        a.kind = kind_;
        record(a);
    } catch (const std::invalid_argument&) {
        archive_.pop_back();
        if (cleanup) return std::nullopt;
        throw;
    }
    if (cleanup && allowPressureTrigger && params_.cleanup.trigger == CleanupTrigger::Pressure &&
        peak >= params_.cleanup.pressureThreshold)
        record(action(SketchAction::Type::EndGroup));
    return id;
}

bool SketchPage::pendingGroupPaused(double now) const {
    const std::vector<int>& pending = session_.pendingStrokes();
    if (pending.empty() || params_.cleanup.trigger != CleanupTrigger::PauseTime) return false;
    const double lastEnd = archive_[std::size_t(sessionToArchive_[std::size_t(pending.back())])]
                               .stroke.samples.back()
                               .time;
    return now - lastEnd >= params_.cleanup.pauseSeconds;
}

// --- clean-up ---

bool SketchPage::advanceTime(double now) {
    if (!std::isfinite(now)) invalid("advanceTime: non-finite time");
    if (!within(now, L::maxTime)) invalid("advanceTime: time outside [-1e10, 1e10] s");
    if (drawing_ || !pendingGroupPaused(now)) return false;
    record(action(SketchAction::Type::EndGroup));
    return true;
}

bool SketchPage::endGroup() {
    if (session_.pendingStrokes().empty()) return false;
    record(action(SketchAction::Type::EndGroup));
    return true;
}

std::string SketchPage::cleanupNote(int strokeId) const {
    const auto it = live_.find(strokeId);
    if (it == live_.end() || !it->second.cleanup)
        invalid("stroke " + std::to_string(strokeId) + " is not a live clean-up stroke");
    return session_.strokeReport(it->second.sessionId).note;
}

std::vector<int> SketchPage::pendingStrokes() const {
    std::vector<int> out;
    for (int sid : session_.pendingStrokes())
        out.push_back(sessionToArchive_[std::size_t(sid)]);
    return out;
}

// --- actions ---

void SketchPage::record(const SketchAction& action) {
    if (done_.size() >= L::maxPageActions)
        invalid("the page has 1000000 actions, the most a page can; add a page");
    apply(action);
    done_.push_back(action);
    redo_.clear();
}

const SketchPage::LiveStroke& SketchPage::liveDraft(int strokeId) const {
    const auto it = live_.find(strokeId);
    if (it == live_.end() || it->second.cleanup)
        invalid("stroke " + std::to_string(strokeId) + " is not a live draft stroke");
    return it->second;
}

void SketchPage::apply(const SketchAction& a) {
    using T = SketchAction::Type;
    switch (a.type) {
        case T::Stroke: {
            if (a.stroke < 0 || std::size_t(a.stroke) >= archive_.size())
                invalid("stroke: unknown stroke " + std::to_string(a.stroke));
            if (live_.count(a.stroke))
                invalid("stroke: stroke " + std::to_string(a.stroke) + " is already live");
            LiveStroke ls;
            ls.cleanup = a.cleanup;
            ls.kind = a.kind;
            if (a.cleanup) {
                ls.sessionId = session_.addStroke(archive_[std::size_t(a.stroke)].stroke, a.kind);
                sessionToArchive_.push_back(a.stroke);
            } else {
                validateStroke(archive_[std::size_t(a.stroke)].stroke);
            }
            live_[a.stroke] = ls;
            return;
        }
        case T::EndGroup:
            if (session_.pendingStrokes().empty()) invalid("endGroup: nothing pending");
            session_.endGroup();
            return;
        case T::Move:
        case T::Scale:
        case T::Delete: {
            const char* what = a.type == T::Move ? "move" : a.type == T::Scale ? "scale" : "delete";
            if (a.strokes.empty()) invalid(std::string(what) + ": no strokes");
            checkUniqueIds(a.strokes, what);
            for (int id : a.strokes)
                liveDraft(id);
            if (a.type == T::Move && !within2(a.vec, 2.0 * L::maxCanvasMm))
                invalid("move: delta not finite or outside [-2e6, 2e6] mm");
            if (a.type == T::Scale) {
                if (!factorInRange(a.factor)) invalid("scale: factor outside [1e-6, 1e6]");
                if (!within2(a.vec, L::maxCanvasMm))
                    invalid("scale: pivot not finite or outside [-1e6, 1e6] mm");
            }
            if (a.type == T::Delete) {
                for (int id : a.strokes)
                    live_.erase(id);
                return;
            }
            // Placements are checked in full before any is changed (strong guarantee): every
            // point must stay on the canvas, or later arithmetic on it could overflow.
            std::vector<std::pair<double, glm::dvec2>> placed;
            for (int id : a.strokes) {
                const LiveStroke& s = live_.at(id);
                double scale = s.scale;
                glm::dvec2 offset = s.offset + a.vec;
                if (a.type == T::Scale) {
                    scale = s.scale * a.factor;
                    offset = a.factor * (s.offset - a.vec) + a.vec;
                    if (!factorInRange(scale))
                        invalid("scale: stroke " + std::to_string(id) +
                                " would reach a placement scale outside [1e-6, 1e6]");
                }
                for (const StrokeSample& x : archive_[std::size_t(id)].stroke.samples)
                    if (!within2(scale * x.position + offset, L::maxCanvasMm))
                        invalid(std::string(what) + ": stroke " + std::to_string(id) +
                                " would leave the canvas [-1e6, 1e6] mm");
                placed.push_back({scale, offset});
            }
            for (std::size_t i = 0; i < a.strokes.size(); ++i) {
                LiveStroke& s = live_.at(a.strokes[i]);
                s.scale = placed[i].first;
                s.offset = placed[i].second;
            }
            return;
        }
        case T::SetRole:
            if (a.curve) {
                if (a.target < 0 || std::size_t(a.target) >= session_.curveCount())
                    invalid("role: no clean curve " + std::to_string(a.target));
                if (a.role == Role::None)
                    curveRoles_.erase(a.target);
                else
                    curveRoles_[a.target] = a.role;
            } else {
                const auto it = live_.find(a.target);
                if (it == live_.end())
                    invalid("role: stroke " + std::to_string(a.target) + " is not live");
                it->second.role = a.role;
            }
            return;
    }
    invalid("unknown action type");
}

void SketchPage::rebuild() {
    live_.clear();
    session_ = CleanupSession(sessionParams(params_.cleanup));
    sessionToArchive_.clear();
    curveRoles_.clear();
    for (const SketchAction& a : done_)
        apply(a);
}

void SketchPage::pruneSelection() {
    std::erase_if(selection_, [&](int id) {
        const auto it = live_.find(id);
        return it == live_.end() || it->second.cleanup;
    });
}

bool SketchPage::undo() {
    if (done_.empty()) return false;
    redo_.push_back(done_.back());
    done_.pop_back();
    rebuild();
    pruneSelection();
    return true;
}

bool SketchPage::redo() {
    if (redo_.empty()) return false;
    const SketchAction a = redo_.back();
    apply(a);
    redo_.pop_back();
    done_.push_back(a);
    pruneSelection();
    return true;
}

// --- selection and editing ---

void SketchPage::select(const std::vector<int>& strokeIds) {
    std::vector<int> sel;
    for (int id : strokeIds) {
        liveDraft(id);
        if (std::find(sel.begin(), sel.end(), id) == sel.end()) sel.push_back(id);
    }
    selection_ = std::move(sel);
}

std::vector<int> SketchPage::selectLasso(const Polyline2& polygon) {
    if (polygon.size() < 3) invalid("selectLasso: the lasso needs at least 3 points");
    // Every lasso point is tested against every stroke sample.
    if (polygon.size() > L::maxStrokeSamples)
        invalid("selectLasso: the lasso has more than 100000 points");
    for (glm::dvec2 p : polygon)
        if (!within2(p, L::maxCanvasMm))
            invalid("selectLasso: lasso point not finite or outside [-1e6, 1e6] mm");
    std::vector<int> sel;
    for (const auto& [id, s] : live_) {
        if (s.cleanup) continue;
        bool all = true;
        for (const StrokeSample& x : archive_[std::size_t(id)].stroke.samples)
            if (!insidePolygon(toCanvas(s, x.position), polygon)) {
                all = false;
                break;
            }
        if (all) sel.push_back(id);
    }
    selection_ = sel;
    return sel;
}

std::optional<int> SketchPage::selectNearest(glm::dvec2 point, double tolerance) {
    if (!within2(point, L::maxCanvasMm))
        invalid("selectNearest: point not finite or outside [-1e6, 1e6] mm");
    if (!(std::isfinite(tolerance) && tolerance >= 0.0))
        invalid("selectNearest: tolerance must be finite and >= 0");
    std::optional<int> best;
    double bestDist = std::numeric_limits<double>::infinity();
    for (const auto& [id, s] : live_) {
        if (s.cleanup) continue;
        const Polyline2 pts = strokePoints(id);
        double d = distanceToSegment(point, pts[0], pts[0]);
        for (std::size_t i = 1; i < pts.size(); ++i)
            d = std::min(d, distanceToSegment(point, pts[i - 1], pts[i]));
        if (d <= tolerance && d < bestDist) {
            bestDist = d;
            best = id;
        }
    }
    selection_.clear();
    if (best) selection_.push_back(*best);
    return best;
}

std::optional<std::pair<glm::dvec2, glm::dvec2>> SketchPage::selectionBounds() const {
    if (selection_.empty()) return std::nullopt;
    glm::dvec2 lo{std::numeric_limits<double>::infinity()}, hi = -lo;
    for (int id : selection_)
        for (glm::dvec2 p : strokePoints(id)) {
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
        }
    return std::make_pair(lo, hi);
}

bool SketchPage::moveSelection(glm::dvec2 deltaCanvas) {
    if (!finite2(deltaCanvas)) invalid("moveSelection: non-finite delta");
    if (selection_.empty()) return false;
    SketchAction a = action(SketchAction::Type::Move);
    a.strokes = selection_;
    a.vec = deltaCanvas;
    record(a);
    return true;
}

bool SketchPage::scaleSelection(double factor) {
    const auto box = selectionBounds();
    if (!box) return false;
    return scaleSelection(factor, 0.5 * (box->first + box->second));
}

bool SketchPage::scaleSelection(double factor, glm::dvec2 pivot) {
    if (!(std::isfinite(factor) && factor > 0.0))
        invalid("scaleSelection: factor must be finite and > 0");
    if (!finite2(pivot)) invalid("scaleSelection: non-finite pivot");
    if (selection_.empty()) return false;
    SketchAction a = action(SketchAction::Type::Scale);
    a.strokes = selection_;
    a.vec = pivot;
    a.factor = factor;
    record(a);
    return true;
}

bool SketchPage::deleteSelection() {
    if (selection_.empty()) return false;
    SketchAction a = action(SketchAction::Type::Delete);
    a.strokes = selection_;
    record(a);
    selection_.clear();
    return true;
}

// --- roles ---

bool SketchPage::setStrokeRole(int strokeId, Role role) {
    if (strokeRole(strokeId) == role) return false;
    SketchAction a = action(SketchAction::Type::SetRole);
    a.target = strokeId;
    a.role = role;
    record(a);
    return true;
}

bool SketchPage::setCurveRole(int curveId, Role role) {
    if (curveRole(curveId) == role) return false;
    SketchAction a = action(SketchAction::Type::SetRole);
    a.curve = true;
    a.target = curveId;
    a.role = role;
    record(a);
    return true;
}

Role SketchPage::strokeRole(int strokeId) const {
    const auto it = live_.find(strokeId);
    if (it == live_.end()) invalid("stroke " + std::to_string(strokeId) + " is not live");
    return it->second.role;
}

Role SketchPage::curveRole(int curveId) const {
    if (curveId < 0 || std::size_t(curveId) >= session_.curveCount())
        invalid("no clean curve " + std::to_string(curveId));
    const auto it = curveRoles_.find(curveId);
    return it == curveRoles_.end() ? Role::None : it->second;
}

std::vector<RolePolyline> SketchPage::rolePolylines() const {
    std::vector<RolePolyline> out;
    std::set<std::pair<int, int>> curveUsed;  // (curve id, role)
    for (const auto& [id, role] : curveRoles_) {
        const CleanCurve& c = session_.curve(id);
        out.push_back({role, true, id, c.closed, c.samples});
        curveUsed.insert({id, int(role)});
    }
    for (const auto& [id, s] : live_) {
        if (s.role == Role::None) continue;
        if (s.cleanup) {
            bool replaced = false;
            for (std::size_t c = 0; c < session_.curveCount() && !replaced; ++c) {
                const CleanCurve& cur = session_.curve(int(c));
                if (std::find(cur.strokes.begin(), cur.strokes.end(), s.sessionId) ==
                    cur.strokes.end())
                    continue;
                replaced = true;
                if (curveUsed.insert({int(c), int(s.role)}).second)
                    out.push_back({s.role, true, int(c), cur.closed, cur.samples});
            }
            if (replaced) continue;
        }
        out.push_back({s.role, false, id, false, strokePoints(id)});
    }
    return out;
}

// --- history ---

StrokeStatus SketchPage::strokeStatus(int strokeId) const {
    if (strokeId < 0 || std::size_t(strokeId) >= archive_.size())
        throw std::out_of_range("no stroke " + std::to_string(strokeId) + " in the history");
    if (live_.count(strokeId)) return StrokeStatus::Live;
    for (const SketchAction& a : done_)
        if (a.type == SketchAction::Type::Stroke && a.stroke == strokeId)
            return StrokeStatus::Deleted;
    return StrokeStatus::Undone;
}

int SketchPage::reuse(int strokeId) {
    if (strokeId < 0 || std::size_t(strokeId) >= archive_.size())
        throw std::out_of_range("reuse: no stroke " + std::to_string(strokeId) + " in the history");
    ArchivedStroke copy = archive_[std::size_t(strokeId)];
    copy.reusedFrom = strokeId;
    const std::optional<int> id = addStrokeAction(std::move(copy), false);
    if (!id) invalid("reuse: stroke " + std::to_string(strokeId) + " is too short for clean-up");
    return *id;
}

// --- queries ---

std::vector<int> SketchPage::liveStrokeIds() const {
    std::vector<int> out;
    for (const auto& entry : live_)
        out.push_back(entry.first);
    return out;
}

Polyline2 SketchPage::strokePoints(int strokeId) const {
    const auto it = live_.find(strokeId);
    if (it == live_.end()) invalid("stroke " + std::to_string(strokeId) + " is not live");
    Polyline2 out;
    for (const StrokeSample& x : archive_[std::size_t(strokeId)].stroke.samples)
        out.push_back(toCanvas(it->second, x.position));
    return out;
}

std::vector<DrawItem> SketchPage::drawList() const {
    const InkParams& ink = params_.ink;
    const auto strokeItem = [&](const ArchivedStroke& a, InkClass cls, Polyline2 points) {
        DrawItem item;
        item.ink = cls;
        item.strokeId = a.id;
        item.points = std::move(points);
        for (const StrokeSample& x : a.stroke.samples) {
            const bool p = a.stroke.hasPressure;
            const double w = p ? inkWidth(x.pressure, ink) : 0.5 * (ink.minWidth + ink.maxWidth);
            item.width.push_back(w * a.inkScale);
            item.darkness.push_back(p ? inkDarkness(x.pressure, ink)
                                      : 0.5 * (ink.minDarkness + ink.maxDarkness));
        }
        return item;
    };
    std::vector<DrawItem> out;
    const std::vector<int> pending = pendingStrokes();
    for (const auto& [id, s] : live_) {
        InkClass cls = InkClass::Draft;
        if (s.cleanup)
            cls = std::find(pending.begin(), pending.end(), id) != pending.end()
                      ? InkClass::Pending
                      : InkClass::Consumed;
        else if (std::find(selection_.begin(), selection_.end(), id) != selection_.end())
            cls = InkClass::Selected;
        DrawItem item = strokeItem(archive_[std::size_t(id)], cls, strokePoints(id));
        item.role = s.role;
        out.push_back(std::move(item));
    }
    for (std::size_t c = 0; c < session_.curveCount(); ++c) {
        const CleanCurve& cur = session_.curve(int(c));
        DrawItem item;
        item.ink = InkClass::Clean;
        item.curveId = int(c);
        item.closed = cur.closed;
        item.role = curveRole(int(c));
        item.points = cur.samples;
        item.width.assign(cur.samples.size(), ink.cleanWidth * view_.scale);
        item.darkness.assign(cur.samples.size(), 1.0);
        out.push_back(std::move(item));
    }
    if (drawing_) {
        DrawItem item = strokeItem(
            drawing_->stroke, mode_ == SketchMode::Cleanup ? InkClass::Pending : InkClass::Draft,
            strokePositions(drawing_->stroke.stroke));
        item.strokeId = -1;
        out.push_back(std::move(item));
    }
    return out;
}

PageContent SketchPage::content() const {
    PageContent c;
    for (const auto& [id, s] : live_)
        c.strokes.push_back({id, s.cleanup, s.kind, s.role, s.scale, s.offset, strokePoints(id)});
    for (std::size_t i = 0; i < session_.curveCount(); ++i) {
        const CleanCurve& cur = session_.curve(int(i));
        PageContent::CurveEntry e;
        e.id = int(i);
        e.kind = cur.kind;
        e.closed = cur.closed;
        e.version = session_.currentVersion(int(i));
        e.versionCount = int(session_.versionCount(int(i)));
        e.role = curveRole(int(i));
        e.knots = cur.knots;
        e.samples = cur.samples;
        for (int sid : cur.strokes)
            e.strokes.push_back(sessionToArchive_[std::size_t(sid)]);
        c.curves.push_back(std::move(e));
    }
    c.pending = pendingStrokes();
    return c;
}

SketchPage SketchPage::restore(std::string name, std::string group, const SketchParams& params,
                               std::vector<ArchivedStroke> archive,
                               const std::vector<SketchAction>& done,
                               std::vector<SketchAction> redo) {
    SketchPage page(std::move(name), std::move(group), params);
    if (archive.size() > L::maxPageStrokes) invalid("strokes: more than 100000 strokes");
    if (done.size() + redo.size() > L::maxPageActions)
        invalid("done: more than 1000000 actions with the redo stack");
    for (std::size_t i = 0; i < archive.size(); ++i) {
        const std::string at = "strokes[" + std::to_string(i) + "]";
        if (archive[i].id != int(i)) invalid(at + ".id: expected " + std::to_string(i));
        const ArchivedStroke& a = archive[i];
        if (a.stroke.samples.size() > L::maxStrokeSamples)
            invalid(at + ".samples: more than 100000 samples");
        try {
            validateStroke(a.stroke);
        } catch (const std::invalid_argument& e) {
            invalid(at + ": " + e.what());
        }
        if (!a.tiltDeg.empty() && a.tiltDeg.size() != a.stroke.samples.size())
            invalid(at + ": tilt count differs from sample count");
        for (const glm::dvec2& t : a.tiltDeg)
            if (!(std::abs(t.x) <= 90.0 && std::abs(t.y) <= 90.0))
                invalid(at + ": tilt outside [-90, 90] degrees");
        if (!scaleInRange(a.inkScale)) invalid(at + ".inkScale: outside [1e-9, 1e9]");
        if (a.reusedFrom < -1 || a.reusedFrom >= a.id)
            invalid(at + ".reusedFrom: must name an earlier stroke");
    }
    page.archive_ = std::move(archive);
    for (std::size_t i = 0; i < done.size(); ++i) {
        try {
            page.apply(done[i]);
        } catch (const std::exception& e) {
            invalid("done[" + std::to_string(i) + "]: " + e.what());
        }
        page.done_.push_back(done[i]);
    }
    // The redo stack must apply in order from its top; check it on a scratch copy.
    SketchPage scratch = page;
    for (std::size_t k = redo.size(); k-- > 0;) {
        try {
            scratch.apply(redo[k]);
        } catch (const std::exception& e) {
            invalid("redo[" + std::to_string(k) + "]: " + e.what());
        }
    }
    page.redo_ = std::move(redo);
    return page;
}

// ---------------------------------------------------------------------------------------------
// Document

SketchDocument::SketchDocument(const SketchParams& params) : params_(params) {
    pages_.emplace_back("Sketch 1", "Sketches", params_);
}

SketchPage& SketchDocument::page(std::size_t index) {
    if (index >= pages_.size()) throw std::out_of_range("no page " + std::to_string(index));
    return pages_[index];
}

const SketchPage& SketchDocument::page(std::size_t index) const {
    if (index >= pages_.size()) throw std::out_of_range("no page " + std::to_string(index));
    return pages_[index];
}

void SketchDocument::selectPage(std::size_t index) {
    page(index);
    current_ = index;
}

std::size_t SketchDocument::addPage(std::string name, std::string group) {
    if (pages_.size() >= L::maxPages) invalid("the document has 10000 pages, the most it can");
    pages_.emplace_back(std::move(name), std::move(group), params_);
    current_ = pages_.size() - 1;
    return current_;
}

void SketchDocument::renamePage(std::size_t index, std::string name) {
    page(index).setName(std::move(name));
}

void SketchDocument::setPageGroup(std::size_t index, std::string group) {
    page(index).setGroup(std::move(group));
}

std::vector<std::string> SketchDocument::groups() const {
    std::vector<std::string> out;
    for (const SketchPage& p : pages_)
        if (std::find(out.begin(), out.end(), p.group()) == out.end()) out.push_back(p.group());
    return out;
}

std::vector<std::size_t> SketchDocument::pagesInGroup(const std::string& group) const {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < pages_.size(); ++i)
        if (pages_[i].group() == group) out.push_back(i);
    return out;
}

// --- JSON ---

namespace {

using nlohmann::json;

constexpr const char* kFormat = "vsculpt-sketch";
constexpr int kVersion = 1;

const char* kindName(StrokeKind k) {
    return k == StrokeKind::Line ? "line" : "curve";
}

json vec2Json(glm::dvec2 v) {
    return json::array({v.x, v.y});
}

json actionJson(const SketchAction& a) {
    using T = SketchAction::Type;
    json j;
    switch (a.type) {
        case T::Stroke:
            j = {{"type", "stroke"},
                 {"stroke", a.stroke},
                 {"cleanup", a.cleanup},
                 {"kind", kindName(a.kind)}};
            break;
        case T::EndGroup:
            j = {{"type", "endGroup"}};
            break;
        case T::Move:
            j = {{"type", "move"}, {"strokes", a.strokes}, {"delta", vec2Json(a.vec)}};
            break;
        case T::Scale:
            j = {{"type", "scale"},
                 {"strokes", a.strokes},
                 {"factor", a.factor},
                 {"pivot", vec2Json(a.vec)}};
            break;
        case T::Delete:
            j = {{"type", "delete"}, {"strokes", a.strokes}};
            break;
        case T::SetRole:
            j = {{"type", "role"},
                 {"target", a.curve ? "curve" : "stroke"},
                 {"id", a.target},
                 {"role", roleName(a.role)}};
            break;
    }
    return j;
}

// Reading with field paths: every error names where it is, e.g. pages[1].strokes[3].samples[0].t.
std::string at(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}
std::string at(const std::string& path, std::size_t index) {
    return path + "[" + std::to_string(index) + "]";
}
[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::invalid_argument(path + ": " + what);
}

const json& member(const json& obj, const std::string& path, const char* key) {
    if (!obj.is_object()) fail(path, "expected an object");
    const auto it = obj.find(key);
    if (it == obj.end()) fail(at(path, key), "missing");
    return *it;
}
bool has(const json& obj, const char* key) {
    return obj.is_object() && obj.contains(key);
}
double number(const json& v, const std::string& path) {
    if (!v.is_number()) fail(path, "expected a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "not finite");
    return d;
}
// A number within [-bound, bound]; `range` is that interval as the message shows it.
double number(const json& v, const std::string& path, double bound, const char* range) {
    const double d = number(v, path);
    if (!within(d, bound)) fail(path, std::string("outside ") + range);
    return d;
}
int integer(const json& v, const std::string& path) {
    if (!v.is_number_integer()) fail(path, "expected an integer");
    // Read as signed, 2^64 - 1 would come back as -1 and pass.
    if (v.is_number_unsigned() &&
        v.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<int>::max()))
        fail(path, "integer out of range");
    const auto i = v.get<std::int64_t>();
    if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
        fail(path, "integer out of range");
    return int(i);
}
bool boolean(const json& v, const std::string& path) {
    if (!v.is_boolean()) fail(path, "expected true or false");
    return v.get<bool>();
}
std::string text(const json& v, const std::string& path) {
    if (!v.is_string()) fail(path, "expected a string");
    return v.get<std::string>();
}
const json& array(const json& v, const std::string& path) {
    if (!v.is_array()) fail(path, "expected an array");
    return v;
}
// An array of at most maxSize elements, checked before any element is read.
const json& array(const json& v, const std::string& path, std::size_t maxSize) {
    if (array(v, path).size() > maxSize)
        fail(path, "more than " + std::to_string(maxSize) + " elements");
    return v;
}
std::string name(const json& v, const std::string& path) {
    std::string s = text(v, path);
    if (s.size() > L::maxNameBytes) fail(path, "longer than 1024 bytes");
    return s;
}
glm::dvec2 vec2(const json& v, const std::string& path, double bound, const char* range) {
    if (!v.is_array() || v.size() != 2) fail(path, "expected [x, y]");
    return {number(v[0], at(path, 0), bound, range), number(v[1], at(path, 1), bound, range)};
}
// Stroke ids listed by an action: at most one per stroke in the page, each naming one.
std::vector<int> ids(const json& v, const std::string& path, std::size_t strokeCount) {
    std::vector<int> out;
    for (std::size_t i = 0; i < array(v, path, strokeCount).size(); ++i) {
        const int id = integer(v[i], at(path, i));
        if (id < 0 || std::size_t(id) >= strokeCount)
            fail(at(path, i), "no stroke " + std::to_string(id) + " in the page");
        out.push_back(id);
    }
    return out;
}
StrokeKind kindFrom(const json& v, const std::string& path) {
    const std::string s = text(v, path);
    if (s == "line") return StrokeKind::Line;
    if (s == "curve") return StrokeKind::Curve;
    fail(path, "expected \"line\" or \"curve\", got \"" + s + "\"");
}
Role roleFrom(const json& v, const std::string& path) {
    const std::string s = text(v, path);
    for (int r = 0; r <= int(Role::Extrude); ++r)
        if (s == roleName(Role(r))) return Role(r);
    fail(path, "unknown role \"" + s + "\"");
}

SketchAction actionFrom(const json& j, const std::string& path, std::size_t strokeCount) {
    using T = SketchAction::Type;
    SketchAction a;
    const std::string type = text(member(j, path, "type"), at(path, "type"));
    if (type == "stroke") {
        a.type = T::Stroke;
        a.stroke = integer(member(j, path, "stroke"), at(path, "stroke"));
        a.cleanup = boolean(member(j, path, "cleanup"), at(path, "cleanup"));
        a.kind = kindFrom(member(j, path, "kind"), at(path, "kind"));
    } else if (type == "endGroup") {
        a.type = T::EndGroup;
    } else if (type == "move" || type == "scale" || type == "delete") {
        a.type = type == "move" ? T::Move : type == "scale" ? T::Scale : T::Delete;
        a.strokes = ids(member(j, path, "strokes"), at(path, "strokes"), strokeCount);
        if (a.type == T::Move)
            a.vec = vec2(member(j, path, "delta"), at(path, "delta"), 2.0 * L::maxCanvasMm,
                         "[-2e6, 2e6] mm");
        if (a.type == T::Scale) {
            a.factor = number(member(j, path, "factor"), at(path, "factor"));
            if (!factorInRange(a.factor)) fail(at(path, "factor"), "outside [1e-6, 1e6]");
            a.vec =
                vec2(member(j, path, "pivot"), at(path, "pivot"), L::maxCanvasMm, "[-1e6, 1e6] mm");
        }
    } else if (type == "role") {
        a.type = T::SetRole;
        const std::string target = text(member(j, path, "target"), at(path, "target"));
        if (target != "stroke" && target != "curve")
            fail(at(path, "target"), "expected \"stroke\" or \"curve\"");
        a.curve = target == "curve";
        a.target = integer(member(j, path, "id"), at(path, "id"));
        a.role = roleFrom(member(j, path, "role"), at(path, "role"));
    } else {
        fail(at(path, "type"), "unknown action \"" + type + "\"");
    }
    return a;
}

ArchivedStroke strokeFrom(const json& j, const std::string& path, std::size_t index) {
    ArchivedStroke a;
    a.id = integer(member(j, path, "id"), at(path, "id"));
    if (a.id != int(index)) fail(at(path, "id"), "expected " + std::to_string(index));
    a.inkScale = number(member(j, path, "inkScale"), at(path, "inkScale"));
    if (!scaleInRange(a.inkScale)) fail(at(path, "inkScale"), "outside [1e-9, 1e9]");
    if (has(j, "reusedFrom")) {
        a.reusedFrom = integer(j["reusedFrom"], at(path, "reusedFrom"));
        if (a.reusedFrom < 0 || a.reusedFrom >= a.id)
            fail(at(path, "reusedFrom"), "must name an earlier stroke");
    }
    a.stroke.hasPressure = boolean(member(j, path, "hasPressure"), at(path, "hasPressure"));
    const bool tilt = boolean(member(j, path, "hasTilt"), at(path, "hasTilt"));
    const std::string sp = at(path, "samples");
    const json& samples = array(member(j, path, "samples"), sp, L::maxStrokeSamples);
    if (samples.empty()) fail(sp, "a stroke needs at least one sample");
    a.stroke.samples.reserve(samples.size());
    if (tilt) a.tiltDeg.reserve(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const std::string p = at(sp, i);
        const json& s = samples[i];
        StrokeSample x;
        x.position = {number(member(s, p, "x"), at(p, "x"), L::maxCanvasMm, "[-1e6, 1e6] mm"),
                      number(member(s, p, "y"), at(p, "y"), L::maxCanvasMm, "[-1e6, 1e6] mm")};
        x.time = number(member(s, p, "t"), at(p, "t"), L::maxTime, "[-1e10, 1e10] s");
        if (i > 0 && x.time < a.stroke.samples.back().time) fail(at(p, "t"), "time goes backwards");
        if (a.stroke.hasPressure) {
            x.pressure = number(member(s, p, "pressure"), at(p, "pressure"));
            if (x.pressure < 0.0 || x.pressure > 1.0) fail(at(p, "pressure"), "outside [0, 1]");
        } else if (has(s, "pressure")) {
            fail(at(p, "pressure"), "present but the stroke has hasPressure false");
        }
        if (tilt) {
            const glm::dvec2 t{number(member(s, p, "tiltX"), at(p, "tiltX")),
                               number(member(s, p, "tiltY"), at(p, "tiltY"))};
            if (std::abs(t.x) > 90.0) fail(at(p, "tiltX"), "outside [-90, 90] degrees");
            if (std::abs(t.y) > 90.0) fail(at(p, "tiltY"), "outside [-90, 90] degrees");
            a.tiltDeg.push_back(t);
        }
        a.stroke.samples.push_back(x);
    }
    return a;
}

}  // namespace

std::string SketchDocument::toJson() const {
    json pages = json::array();
    for (const SketchPage& p : pages_) {
        json strokes = json::array();
        for (const ArchivedStroke& a : p.history()) {
            json samples = json::array();
            for (std::size_t i = 0; i < a.stroke.samples.size(); ++i) {
                const StrokeSample& x = a.stroke.samples[i];
                json s = {{"x", x.position.x}, {"y", x.position.y}, {"t", x.time}};
                if (a.stroke.hasPressure) s["pressure"] = x.pressure;
                if (!a.tiltDeg.empty()) {
                    s["tiltX"] = a.tiltDeg[i].x;
                    s["tiltY"] = a.tiltDeg[i].y;
                }
                samples.push_back(std::move(s));
            }
            json js = {{"id", a.id},
                       {"inkScale", a.inkScale},
                       {"hasPressure", a.stroke.hasPressure},
                       {"hasTilt", !a.tiltDeg.empty()},
                       {"samples", std::move(samples)}};
            if (a.reusedFrom >= 0) js["reusedFrom"] = a.reusedFrom;
            strokes.push_back(std::move(js));
        }
        json done = json::array(), redo = json::array();
        for (const SketchAction& a : p.actions())
            done.push_back(actionJson(a));
        for (const SketchAction& a : p.redoStack())
            redo.push_back(actionJson(a));
        pages.push_back(
            {{"name", p.name()},
             {"group", p.group()},
             {"mode", p.mode() == SketchMode::Draft ? "draft" : "cleanup"},
             {"kind", kindName(p.kind())},
             {"view", {{"scale", p.view().scale}, {"offset", vec2Json(p.view().offset)}}},
             {"strokes", std::move(strokes)},
             {"done", std::move(done)},
             {"redo", std::move(redo)}});
    }
    // nlohmann writes the shortest decimal that reads back to the same double, so the text
    // round trip is exact.
    const json doc = {{"format", kFormat},
                      {"version", kVersion},
                      {"current", current_},
                      {"pages", std::move(pages)}};
    // Names set through the API may hold invalid UTF-8, which strict dumping would throw on.
    return doc.dump(-1, ' ', false, json::error_handler_t::replace);
}

SketchDocument SketchDocument::fromJson(const std::string& textIn, const SketchParams& params) {
    if (const auto deep = core::jsonNestingBeyond(textIn)) throw std::invalid_argument(*deep);
    json j;
    try {
        j = json::parse(textIn);
    } catch (const json::exception& e) {
        // Not only parse_error: a number like 1e400 overflows with out_of_range.
        throw std::invalid_argument(std::string("not JSON: ") + e.what());
    }
    if (!j.is_object()) fail("(root)", "expected an object");
    if (text(member(j, "", "format"), "format") != kFormat)
        fail("format", std::string("expected \"") + kFormat + "\"");
    const int version = integer(member(j, "", "version"), "version");
    if (version != kVersion)
        fail("version", "unsupported version " + std::to_string(version) + " (this build reads " +
                            std::to_string(kVersion) + ")");
    const json& pagesJ = array(member(j, "", "pages"), "pages", L::maxPages);
    if (pagesJ.empty()) fail("pages", "a document needs at least one page");
    const int current = integer(member(j, "", "current"), "current");
    if (current < 0 || std::size_t(current) >= pagesJ.size())
        fail("current", "no page " + std::to_string(current));

    SketchDocument doc(params);
    doc.pages_.clear();
    std::size_t totalSamples = 0;
    for (std::size_t pi = 0; pi < pagesJ.size(); ++pi) {
        const std::string pp = at("pages", pi);
        const json& pj = pagesJ[pi];
        const std::string name = studio::name(member(pj, pp, "name"), at(pp, "name"));
        if (name.empty()) fail(at(pp, "name"), "must not be empty");
        const std::string group = studio::name(member(pj, pp, "group"), at(pp, "group"));
        const std::string mode = text(member(pj, pp, "mode"), at(pp, "mode"));
        if (mode != "draft" && mode != "cleanup")
            fail(at(pp, "mode"), "expected \"draft\" or \"cleanup\"");
        const StrokeKind kind = kindFrom(member(pj, pp, "kind"), at(pp, "kind"));
        const std::string vp = at(pp, "view");
        const json& vj = member(pj, pp, "view");
        CanvasView view;
        view.scale = number(member(vj, vp, "scale"), at(vp, "scale"));
        if (!scaleInRange(view.scale)) fail(at(vp, "scale"), "outside [1e-9, 1e9]");
        view.offset =
            vec2(member(vj, vp, "offset"), at(vp, "offset"), L::maxViewOffsetMm, "[-1e9, 1e9] mm");

        std::vector<ArchivedStroke> archive;
        const std::string sp = at(pp, "strokes");
        const json& sj = array(member(pj, pp, "strokes"), sp, L::maxPageStrokes);
        archive.reserve(sj.size());
        for (std::size_t i = 0; i < sj.size(); ++i) {
            archive.push_back(strokeFrom(sj[i], at(sp, i), i));
            totalSamples += archive.back().stroke.samples.size();
            if (totalSamples > L::maxDocumentSamples)
                fail(at(at(sp, i), "samples"), "the document has more than 10000000 samples");
        }
        std::vector<SketchAction> done, redo;
        const std::string dp = at(pp, "done"), rp = at(pp, "redo");
        const json& dj = array(member(pj, pp, "done"), dp, L::maxPageActions);
        const json& rj = array(member(pj, pp, "redo"), rp, L::maxPageActions - dj.size());
        for (std::size_t i = 0; i < dj.size(); ++i)
            done.push_back(actionFrom(dj[i], at(dp, i), archive.size()));
        for (std::size_t i = 0; i < rj.size(); ++i)
            redo.push_back(actionFrom(rj[i], at(rp, i), archive.size()));

        try {
            SketchPage page =
                SketchPage::restore(name, group, params, std::move(archive), done, std::move(redo));
            page.setMode(mode == "draft" ? SketchMode::Draft : SketchMode::Cleanup);
            page.setKind(kind);
            page.setView(view);
            doc.pages_.push_back(std::move(page));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(pp + "." + e.what());
        }
    }
    doc.current_ = std::size_t(current);
    return doc;
}

}  // namespace vsculpt::studio
