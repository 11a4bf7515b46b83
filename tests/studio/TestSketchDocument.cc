// The sketch mode's model: view transforms, pen input, ink, undo/redo, history, selection,
// clean-up mode, roles, pages and the JSON file format.
#include "vsculpt/studio/SketchDocument.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

namespace vsculpt::studio {
namespace {

// Small deterministic generator (std distributions differ between standard libraries).
struct Rng {
    std::uint64_t state;
    double uniform(double lo, double hi) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return lo + (hi - lo) * double(state >> 11) * 0x1.0p-53;
    }
    int below(int n) { return std::min(n - 1, int(uniform(0, n))); }
};

PenSample pen(glm::dvec2 view, double t, std::optional<double> pressure = std::nullopt) {
    PenSample s;
    s.view = view;
    s.time = t;
    s.pressure = pressure;
    return s;
}

// Draws a stroke through view points, 10 ms apart from t0; returns its id.
std::optional<int> draw(SketchPage& page, const Polyline2& view, double t0,
                        std::optional<double> pressure = std::nullopt) {
    page.penDown(pen(view[0], t0, pressure));
    for (std::size_t i = 1; i < view.size(); ++i)
        page.penMove(pen(view[i], t0 + 0.01 * double(i), pressure));
    return page.penUp();
}

Polyline2 segment(glm::dvec2 a, glm::dvec2 b, int n = 20) {
    Polyline2 out;
    for (int i = 0; i <= n; ++i)
        out.push_back(a + (b - a) * (double(i) / n));
    return out;
}

bool near(glm::dvec2 a, glm::dvec2 b, double tol) {
    return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol;
}

// ---------------------------------------------------------------------------------------------

TEST(SketchView, InverseAndFixedPointsAreExactTo1e12) {
    Rng rng{7};
    CanvasView v;
    for (int i = 0; i < 200; ++i) {
        const glm::dvec2 vp{rng.uniform(-150, 150), rng.uniform(-100, 100)};
        const glm::dvec2 before = v.canvasFromView(vp);
        v.zoomAbout(vp, std::exp(rng.uniform(-0.7, 0.7)));
        // The canvas point under the zoom centre stays under it.
        EXPECT_TRUE(near(v.canvasFromView(vp), before, 1e-12 * (1 + glm::length(before))));
        const glm::dvec2 d{rng.uniform(-20, 20), rng.uniform(-20, 20)};
        const glm::dvec2 c = v.canvasFromView(vp);
        v.pan(d);
        // Panning drags the content with the pen: the same canvas point is now at vp + d.
        EXPECT_TRUE(near(v.canvasFromView(vp + d), c, 1e-12 * (1 + glm::length(c))));
        const glm::dvec2 q{rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3)};
        EXPECT_TRUE(near(v.canvasFromView(v.viewFromCanvas(q)), q, 1e-12 * (1 + glm::length(q))));
        const glm::dvec2 w = v.viewFromCanvas(q);
        EXPECT_TRUE(near(v.viewFromCanvas(v.canvasFromView(w)), w, 1e-12 * (1 + glm::length(w))));
    }
    v.reset();
    EXPECT_EQ(v, CanvasView{});
    EXPECT_THROW(v.zoomAbout({0, 0}, 0.0), std::invalid_argument);
    EXPECT_THROW(v.zoomAbout({0, 0}, NAN), std::invalid_argument);
    EXPECT_THROW(v.pan({INFINITY, 0}), std::invalid_argument);
    EXPECT_EQ(v, CanvasView{});
}

TEST(SketchView, ZoomAndPanBetweenStrokesKeepStrokesInCanvasSpace) {
    SketchPage page("p", "g");
    const int a = *draw(page, segment({0, 0}, {30, 10}), 0.0, 0.5);
    const Polyline2 aPoints = page.strokePoints(a);
    EXPECT_EQ(aPoints, segment({0, 0}, {30, 10}));  // identity view at first

    page.zoomAbout({10, 5}, 3.0);
    page.pan({-7.5, 2.25});
    page.zoomAbout({-4, 8}, 0.8);
    EXPECT_EQ(page.strokePoints(a), aPoints);  // bit for bit: the view never moves ink

    // A stroke drawn where canvas target points appear lands on them.
    const Polyline2 target = segment({5, -5}, {25, 15});
    Polyline2 viewPts;
    for (glm::dvec2 c : target)
        viewPts.push_back(page.view().viewFromCanvas(c));
    const int b = *draw(page, viewPts, 1.0, 1.0);
    const Polyline2 bPoints = page.strokePoints(b);
    for (std::size_t i = 0; i < target.size(); ++i)
        EXPECT_TRUE(near(bPoints[i], target[i], 1e-12 * 30)) << i;
    // Ink width is view mm at drawing time, kept in canvas mm: scale 1/(3·0.8).
    for (const DrawItem& item : page.drawList())
        if (item.strokeId == b) {
            EXPECT_DOUBLE_EQ(item.width[0], page.params().ink.maxWidth / 2.4);
        } else if (item.strokeId == a) {
            EXPECT_EQ(item.width[0], inkWidth(0.5, page.params().ink));
        }
    page.resetView();
    EXPECT_EQ(page.strokePoints(a), aPoints);
    EXPECT_EQ(page.strokePoints(b), bPoints);
}

TEST(SketchInk, PressureMappingIsMonotoneWithExactEndpoints) {
    for (const double gamma : {0.5, 1.0, 1.5, 2.2}) {
        InkParams ink;
        ink.gamma = gamma;
        ink.minWidth = 0.1;
        ink.maxWidth = 0.7;  // 0.1 + (0.7 - 0.1) != 0.7 in doubles: lerp must still hit it
        EXPECT_EQ(inkWidth(0.0, ink), ink.minWidth);
        EXPECT_EQ(inkWidth(1.0, ink), ink.maxWidth);
        EXPECT_EQ(inkDarkness(0.0, ink), ink.minDarkness);
        EXPECT_EQ(inkDarkness(1.0, ink), ink.maxDarkness);
        EXPECT_NEAR(inkWidth(0.5, ink), 0.1 + 0.6 * std::pow(0.5, gamma), 1e-15);
        double w = 0, d = 0;
        for (int i = 0; i <= 10000; ++i) {
            const double p = i / 10000.0;
            const double wi = inkWidth(p, ink), di = inkDarkness(p, ink);
            EXPECT_GE(wi, w);
            EXPECT_GE(di, d);
            w = wi;
            d = di;
        }
    }
    InkParams ink;
    EXPECT_THROW(inkWidth(1.01, ink), std::invalid_argument);
    EXPECT_THROW(inkWidth(NAN, ink), std::invalid_argument);
    ink.gamma = 0;
    EXPECT_THROW(validateInkParams(ink), std::invalid_argument);

    // The mouse (no pressure) draws at the middle width and darkness.
    SketchPage page("p", "g");
    draw(page, segment({0, 0}, {10, 0}), 0.0);
    const DrawItem item = page.drawList().at(0);
    const InkParams& k = page.params().ink;
    for (std::size_t i = 0; i < item.points.size(); ++i) {
        EXPECT_EQ(item.width[i], 0.5 * (k.minWidth + k.maxWidth));
        EXPECT_EQ(item.darkness[i], 0.5 * (k.minDarkness + k.maxDarkness));
    }
}

TEST(SketchPen, BadInputIsRejectedAndHoverNeverInks) {
    SketchPage page("p", "g");
    page.hover({3, 4});
    page.zoomAbout({0, 0}, 2.0);
    ASSERT_TRUE(page.hoverCanvas());
    EXPECT_EQ(*page.hoverCanvas(), glm::dvec2(1.5, 2.0));
    EXPECT_TRUE(page.history().empty());
    EXPECT_TRUE(page.drawList().empty());
    page.leaveProximity();
    EXPECT_FALSE(page.hoverCanvas());

    EXPECT_THROW(page.penMove(pen({0, 0}, 0)), std::invalid_argument);
    EXPECT_THROW(page.penUp(), std::invalid_argument);
    EXPECT_THROW(page.penDown(pen({NAN, 0}, 0)), std::invalid_argument);
    EXPECT_THROW(page.penDown(pen({0, 0}, INFINITY)), std::invalid_argument);
    EXPECT_THROW(page.penDown(pen({0, 0}, 0, 1.5)), std::invalid_argument);
    PenSample tilted = pen({0, 0}, 0, 0.5);
    tilted.tiltDeg = glm::dvec2(95, 0);
    EXPECT_THROW(page.penDown(tilted), std::invalid_argument);
    EXPECT_FALSE(page.penIsDown());

    page.penDown(pen({0, 0}, 1.0, 0.5));
    EXPECT_THROW(page.penDown(pen({0, 0}, 1.0, 0.5)), std::invalid_argument);
    EXPECT_THROW(page.penMove(pen({1, 0}, 0.99, 0.5)), std::invalid_argument);  // backwards
    EXPECT_THROW(page.penMove(pen({1, 0}, 1.1)), std::invalid_argument);        // no pressure
    EXPECT_THROW(page.penMove(pen({1, 0}, 1.1, NAN)), std::invalid_argument);
    page.penMove(pen({1, 0}, 1.1, 0.6));
    const std::optional<int> id = page.penUp(pen({2, 0}, 1.2, 0.7));
    ASSERT_TRUE(id);
    // The rejected samples left no trace.
    ASSERT_EQ(page.history().size(), 1u);
    const Stroke& s = page.history()[0].stroke;
    ASSERT_EQ(s.samples.size(), 3u);
    EXPECT_EQ(s.samples[1].position, glm::dvec2(0.5, 0));  // view zoomed 2x
    EXPECT_EQ(s.samples[2].pressure, 0.7);
    EXPECT_EQ(page.undoCount(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Undo / redo

// Three draft strokes, one clean curve and a pending clean-up stroke: every action type has
// something to act on.
SketchPage busyPage() {
    SketchParams params;
    params.cleanup.trigger = sketch::CleanupTrigger::Explicit;
    SketchPage page("p", "g", params);
    draw(page, segment({0, 0}, {20, 0}), 0.0, 0.4);
    draw(page, segment({0, 10}, {20, 15}), 1.0, 0.8);
    draw(page, segment({5, 30}, {6, 50}), 2.0);
    page.setMode(SketchMode::Cleanup);
    page.setKind(StrokeKind::Line);
    for (int i = 0; i < 3; ++i)
        draw(page, segment({0, 60 + 0.3 * i}, {40, 61 - 0.2 * i}), 3.0 + i);
    page.endGroup();
    draw(page, segment({0, 80}, {40, 90}), 7.0);
    page.setMode(SketchMode::Draft);
    return page;
}

TEST(SketchUndo, EveryActionTypeUndoesToTheExactPriorState) {
    struct Case {
        const char* name;
        std::function<void(SketchPage&)> act;
    };
    const std::vector<Case> cases = {
        {"stroke",
         [](SketchPage& p) {
             draw(p, segment({1, 1}, {9, 4}), 20.0, 0.3);
         }},
        {"cleanup stroke",
         [](SketchPage& p) {
             p.setMode(SketchMode::Cleanup);
             draw(p, segment({0, 80.5}, {40, 90.5}), 20.0);
         }},
        {"clean-up group", [](SketchPage& p) { EXPECT_TRUE(p.endGroup()); }},
        {"move",
         [](SketchPage& p) {
             p.select({0, 2});
             EXPECT_TRUE(p.moveSelection({3.25, -1.5}));
         }},
        {"scale",
         [](SketchPage& p) {
             p.select({1});
             EXPECT_TRUE(p.scaleSelection(1.7));
         }},
        {"scale about pivot",
         [](SketchPage& p) {
             p.select({0, 1, 2});
             EXPECT_TRUE(p.scaleSelection(0.3, {100, -7}));
         }},
        {"delete",
         [](SketchPage& p) {
             p.select({1, 2});
             EXPECT_TRUE(p.deleteSelection());
         }},
        {"stroke role", [](SketchPage& p) { EXPECT_TRUE(p.setStrokeRole(0, Role::Outline)); }},
        {"curve role", [](SketchPage& p) { EXPECT_TRUE(p.setCurveRole(0, Role::SurfaceLineY)); }},
        {"reuse", [](SketchPage& p) { p.reuse(1); }},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        SketchPage page = busyPage();
        const PageContent before = page.content();
        const std::size_t undoBefore = page.undoCount();
        c.act(page);
        const PageContent after = page.content();
        ASSERT_EQ(page.undoCount(), undoBefore + 1);
        EXPECT_NE(after, before);
        EXPECT_NE(contentHash(after), contentHash(before));

        ASSERT_TRUE(page.undo());  // no selection needed
        EXPECT_EQ(page.content(), before);
        EXPECT_EQ(contentHash(page.content()), contentHash(before));
        ASSERT_TRUE(page.redo());
        EXPECT_EQ(page.content(), after);
        EXPECT_EQ(contentHash(page.content()), contentHash(after));

        // A new action clears the redo stack.
        ASSERT_TRUE(page.undo());
        EXPECT_EQ(page.redoCount(), 1u);
        EXPECT_TRUE(page.setStrokeRole(0, Role::Cut));
        EXPECT_EQ(page.redoCount(), 0u);
        EXPECT_FALSE(page.redo());
    }
}

TEST(SketchUndo, RandomSequencesUndoneToTheStartEqualTheEmptyPage) {
    SketchParams params;
    params.cleanup.trigger = sketch::CleanupTrigger::PauseTime;
    const PageContent empty = SketchPage("e", "g", params).content();
    int checked = 0, cleanups = 0;
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
        SCOPED_TRACE(seed);
        Rng rng{seed};
        SketchPage page("p", "g", params);
        // states[k]: the content with k actions done, where observed.
        std::vector<std::optional<PageContent>> states = {page.content()};
        double t = 0;
        for (int step = 0; step < 40; ++step) {
            const std::size_t level = page.undoCount();
            const int what = rng.below(10);
            t += rng.uniform(0.1, 1.5);
            if (what == 0 && page.undo()) {
                // Levels inside a call that recorded two actions (a group end, then the
                // stroke) were not observed.
                if (states[level - 1]) {
                    ASSERT_EQ(page.content(), *states[level - 1]);
                    ++checked;
                }
                continue;
            }
            if (what == 1 && page.redo()) {
                if (states[level + 1]) {
                    ASSERT_EQ(page.content(), *states[level + 1]);
                    ++checked;
                }
                continue;
            }
            const std::vector<int> live = page.liveStrokeIds();
            std::vector<int> drafts;
            for (const PageContent::StrokeEntry& e : page.content().strokes)
                if (!e.cleanup) drafts.push_back(e.id);
            switch (what) {
                case 2:
                case 3: {
                    page.setMode(rng.below(2) ? SketchMode::Cleanup : SketchMode::Draft);
                    page.setKind(rng.below(2) ? StrokeKind::Line : StrokeKind::Curve);
                    const glm::dvec2 a{rng.uniform(0, 50), rng.uniform(0, 50)};
                    const glm::dvec2 b = a + glm::dvec2(rng.uniform(5, 30), rng.uniform(-10, 10));
                    draw(page, segment(a, b, 12), t, rng.uniform(0, 1));
                    t += 0.2;
                    break;
                }
                case 4:
                    page.advanceTime(t);
                    break;
                case 5:
                    if (!drafts.empty()) {
                        page.select({drafts[std::size_t(rng.below(int(drafts.size())))]});
                        page.moveSelection({rng.uniform(-5, 5), rng.uniform(-5, 5)});
                    }
                    break;
                case 6:
                    if (!drafts.empty()) {
                        page.select(drafts);
                        page.scaleSelection(rng.uniform(0.5, 2));
                    }
                    break;
                case 7:
                    if (!drafts.empty()) {
                        page.select({drafts[std::size_t(rng.below(int(drafts.size())))]});
                        page.deleteSelection();
                    }
                    break;
                case 8:
                    if (!live.empty())
                        page.setStrokeRole(live[std::size_t(rng.below(int(live.size())))],
                                           Role(rng.below(9)));
                    else if (page.cleanup().curveCount() > 0)
                        page.setCurveRole(0, Role(rng.below(9)));
                    break;
                default:
                    if (!page.history().empty()) {
                        try {
                            page.reuse(rng.below(int(page.history().size())));
                        } catch (const std::invalid_argument&) {
                        }
                    }
            }
            if (page.undoCount() != level) {
                // Levels between `level` and the new one were not observed on this branch.
                states.resize(level + 1);
                states.resize(page.undoCount() + 1);
                states[page.undoCount()] = page.content();
            }
        }
        // The incremental state equals a replay of the log (what undo relies on).
        const SketchPage replayed =
            SketchPage::restore("p", "g", params, page.history(), page.actions(), page.redoStack());
        ASSERT_EQ(replayed.content(), page.content());
        while (page.undo()) {
            const std::size_t level = page.undoCount();
            if (level < states.size() && states[level]) {
                ASSERT_EQ(page.content(), *states[level]);
                ++checked;
            }
        }
        EXPECT_EQ(page.content(), empty);
        EXPECT_EQ(contentHash(page.content()), contentHash(empty));
        for (const SketchAction& a : page.redoStack())
            cleanups += a.type == SketchAction::Type::EndGroup;
        // The history keeps every stroke ever drawn.
        for (std::size_t i = 0; i < page.history().size(); ++i)
            EXPECT_EQ(page.strokeStatus(int(i)), StrokeStatus::Undone);
    }
    // The sequences really exercised undo against observed states, including clean-ups.
    EXPECT_GT(checked, 300);
    EXPECT_GT(cleanups, 10);
}

TEST(SketchHistory, ReuseReinsertsACopyAsANewAction) {
    SketchPage page("p", "g");
    const int a = *draw(page, segment({0, 0}, {10, 5}), 0.0, 0.9);
    const Polyline2 drawn = page.strokePoints(a);
    page.select({a});
    page.moveSelection({100, 0});
    page.deleteSelection();
    EXPECT_EQ(page.strokeStatus(a), StrokeStatus::Deleted);
    EXPECT_TRUE(page.liveStrokeIds().empty());

    const int b = page.reuse(a);
    EXPECT_NE(b, a);
    EXPECT_EQ(page.liveStrokeIds(), std::vector<int>{b});
    EXPECT_EQ(page.strokePoints(b), drawn);  // as drawn, not where it was moved
    EXPECT_EQ(page.history().at(std::size_t(b)).reusedFrom, a);
    EXPECT_EQ(page.history().at(std::size_t(b)).stroke.samples[3].pressure, 0.9);

    ASSERT_TRUE(page.undo());
    EXPECT_EQ(page.strokeStatus(b), StrokeStatus::Undone);
    EXPECT_EQ(page.history().size(), 2u);  // still listed, still reusable
    const int c = page.reuse(b);
    EXPECT_EQ(page.strokePoints(c), drawn);
    EXPECT_THROW(page.reuse(99), std::out_of_range);
}

TEST(SketchEdit, LassoNearestMoveAndScale) {
    SketchPage page("p", "g");
    const int a = *draw(page, segment({0, 0}, {10, 0}), 0.0);
    const int b = *draw(page, segment({0, 5}, {10, 8}), 1.0);
    const int c = *draw(page, segment({30, 0}, {40, 0}), 2.0);
    // A lasso around a and b; c lies outside, and a stroke half inside is not taken.
    EXPECT_EQ(page.selectLasso({{-1, -1}, {11, -1}, {11, 9}, {-1, 9}}), (std::vector<int>{a, b}));
    EXPECT_EQ(page.selectLasso({{-1, -1}, {35, -1}, {35, 9}, {-1, 9}}), (std::vector<int>{a, b}));
    EXPECT_THROW(page.selectLasso({{0, 0}, {1, 1}}), std::invalid_argument);

    EXPECT_EQ(page.selectNearest({33, 0.4}, 0.5), c);
    EXPECT_EQ(page.selection(), std::vector<int>{c});
    EXPECT_FALSE(page.selectNearest({20, 20}, 1.0));
    EXPECT_TRUE(page.selection().empty());
    EXPECT_FALSE(page.moveSelection({1, 1}));  // nothing selected: no action
    EXPECT_EQ(page.undoCount(), 3u);
    EXPECT_THROW(page.select({a, 99}), std::invalid_argument);

    page.select({a, b});
    ASSERT_TRUE(page.moveSelection({2.5, -4}));
    EXPECT_EQ(page.strokePoints(a).front(), glm::dvec2(2.5, -4));
    EXPECT_EQ(page.strokePoints(c).front(), glm::dvec2(30, 0));
    // Scale about the bounding-box centre: the box grows about its centre.
    const auto box = *page.selectionBounds();
    ASSERT_TRUE(page.scaleSelection(2.0));
    const auto box2 = *page.selectionBounds();
    const glm::dvec2 centre = 0.5 * (box.first + box.second);
    EXPECT_TRUE(near(box2.first, centre + 2.0 * (box.first - centre), 1e-12));
    EXPECT_TRUE(near(box2.second, centre + 2.0 * (box.second - centre), 1e-12));
    EXPECT_THROW(page.scaleSelection(-1.0), std::invalid_argument);
    for (const DrawItem& item : page.drawList())
        EXPECT_EQ(item.ink, item.strokeId == c ? InkClass::Draft : InkClass::Selected);
}

// ---------------------------------------------------------------------------------------------
// Clean-up mode

TEST(SketchCleanup, ThreeOverdrawnStrokesBecomeOneLineAndUndoRestoresPending) {
    SketchParams params;
    params.cleanup.trigger = sketch::CleanupTrigger::PauseTime;
    SketchPage page("p", "g", params);
    page.setMode(SketchMode::Cleanup);
    page.setKind(StrokeKind::Line);
    // Three strokes along y = 0.25 x + 10, a little off each other, 0.3 s apart.
    const auto line = [](double x, double dy) { return glm::dvec2(x, 0.25 * x + 10 + dy); };
    draw(page, segment(line(0, 0.4), line(50, -0.3)), 0.0, 0.5);
    draw(page, segment(line(2, -0.3), line(48, 0.4)), 0.5, 0.5);
    const int last = *draw(page, segment(line(1, 0.1), line(51, 0.0)), 1.0, 0.5);
    const double lastEnd = page.history()[std::size_t(last)].stroke.samples.back().time;
    EXPECT_EQ(page.pendingStrokes(), (std::vector<int>{0, 1, 2}));
    EXPECT_TRUE(page.cleanCurves().empty());
    const PageContent pending = page.content();

    EXPECT_FALSE(page.advanceTime(lastEnd + 0.5));  // still thinking
    ASSERT_TRUE(page.advanceTime(lastEnd + 1.01));  // the pause ends the group
    const std::vector<CleanCurve> curves = page.cleanCurves();
    ASSERT_EQ(curves.size(), 1u);
    EXPECT_EQ(curves[0].kind, StrokeKind::Line);
    ASSERT_EQ(curves[0].samples.size(), 2u);
    for (glm::dvec2 p : curves[0].samples)
        EXPECT_NEAR(p.y, 0.25 * p.x + 10, 0.5);
    EXPECT_TRUE(page.pendingStrokes().empty());
    const PageContent cleaned = page.content();
    EXPECT_EQ(cleaned.curves[0].strokes, (std::vector<int>{0, 1, 2}));
    for (const DrawItem& item : page.drawList())
        EXPECT_EQ(item.ink, item.curveId >= 0 ? InkClass::Clean : InkClass::Consumed);

    ASSERT_TRUE(page.undo());  // undoes the clean-up, not a stroke
    EXPECT_EQ(page.content(), pending);
    EXPECT_EQ(page.pendingStrokes().size(), 3u);
    EXPECT_TRUE(page.cleanCurves().empty());
    ASSERT_TRUE(page.redo());
    EXPECT_EQ(page.content(), cleaned);

    // A stroke drawn after a pause starts a new group; drawing over the line corrects it.
    draw(page, segment(line(0, 1.0), line(50, 1.0)), 10.0, 0.5);
    EXPECT_EQ(page.pendingStrokes(), std::vector<int>{3});
    ASSERT_TRUE(page.endGroup());
    EXPECT_EQ(page.cleanCurves().size(), 1u);
    EXPECT_EQ(page.cleanup().versionCount(0), 2u);
}

TEST(SketchCleanup, PressureTriggerAndKindChangeEndGroupsAsTheirOwnActions) {
    SketchParams params;
    params.cleanup.trigger = sketch::CleanupTrigger::Pressure;
    SketchPage page("p", "g", params);
    page.setMode(SketchMode::Cleanup);
    page.setKind(StrokeKind::Line);
    draw(page, segment({0, 0}, {30, 0}), 0.0, 0.5);
    EXPECT_EQ(page.undoCount(), 1u);
    draw(page, segment({0, 0.5}, {30, 0.2}), 0.5, 0.9);  // pressed hard: ends the group
    EXPECT_EQ(page.undoCount(), 3u);
    EXPECT_EQ(page.cleanCurves().size(), 1u);

    draw(page, segment({0, 20}, {30, 20}), 1.0, 0.5);
    page.setKind(StrokeKind::Curve);
    Polyline2 arc;
    for (int i = 0; i <= 30; ++i)
        arc.push_back({40 + 10 * std::cos(i * 0.1), 10 * std::sin(i * 0.1)});
    draw(page, arc, 2.0, 0.5);
    // stroke, endGroup (kind changed), stroke.
    EXPECT_EQ(page.undoCount(), 6u);
    EXPECT_EQ(page.cleanCurves().size(), 2u);
    EXPECT_EQ(page.pendingStrokes(), std::vector<int>{3});
    // A dot cannot be cleaned up: nothing is recorded.
    EXPECT_FALSE(draw(page, {{1, 1}, {1, 1}}, 3.0, 0.5));
    EXPECT_EQ(page.undoCount(), 6u);
    EXPECT_EQ(page.history().size(), 4u);
}

// ---------------------------------------------------------------------------------------------
// Roles, pages

TEST(SketchRoles, PolylinesPerRolePreferCleanCurves) {
    SketchParams params;
    params.cleanup.trigger = sketch::CleanupTrigger::Explicit;
    SketchPage page("p", "g", params);
    const int outline = *draw(page, segment({0, 0}, {10, 10}), 0.0);
    page.setMode(SketchMode::Cleanup);
    page.setKind(StrokeKind::Line);
    const int s1 = *draw(page, segment({0, 30}, {40, 30}), 1.0);
    draw(page, segment({0, 30.4}, {40, 30.2}), 2.0);
    page.endGroup();
    EXPECT_TRUE(page.setStrokeRole(outline, Role::Outline));
    EXPECT_FALSE(page.setStrokeRole(outline, Role::Outline));  // unchanged: no action
    EXPECT_TRUE(page.setStrokeRole(s1, Role::SurfaceLineY));
    EXPECT_THROW(page.setCurveRole(5, Role::Cut), std::invalid_argument);
    EXPECT_THROW(page.setStrokeRole(42, Role::Cut), std::invalid_argument);

    std::vector<RolePolyline> lines = page.rolePolylines();
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0].role, Role::Outline);
    EXPECT_FALSE(lines[0].fromCurve);
    EXPECT_EQ(lines[0].points, page.strokePoints(outline));
    // The clean-up stroke's role gives its clean line, not the raw stroke.
    EXPECT_EQ(lines[1].role, Role::SurfaceLineY);
    EXPECT_TRUE(lines[1].fromCurve);
    EXPECT_EQ(lines[1].points, page.cleanCurves()[0].samples);

    EXPECT_TRUE(page.setCurveRole(0, Role::SweepPath));
    lines = page.rolePolylines();
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0].role, Role::SweepPath);  // curves first
    EXPECT_TRUE(lines[0].fromCurve);
    EXPECT_EQ(std::string(roleName(Role::SurfaceLineZ)), "surfaceLineZ");
}

TEST(SketchPages, PagesGroupsAndPerPageUndo) {
    SketchDocument doc;
    EXPECT_EQ(doc.pageCount(), 1u);
    const std::size_t p1 = doc.addPage("Chair A", "Chairs");
    const std::size_t p2 = doc.addPage("Lamp", "Lamps");
    const std::size_t p3 = doc.addPage("Chair B", "Chairs");
    EXPECT_EQ(doc.currentIndex(), p3);
    EXPECT_EQ(doc.groups(), (std::vector<std::string>{"Sketches", "Chairs", "Lamps"}));
    EXPECT_EQ(doc.pagesInGroup("Chairs"), (std::vector<std::size_t>{p1, p3}));
    doc.renamePage(p2, "Desk lamp");
    doc.setPageGroup(p2, "Chairs");
    EXPECT_EQ(doc.page(p2).name(), "Desk lamp");
    EXPECT_EQ(doc.pagesInGroup("Chairs"), (std::vector<std::size_t>{p1, p2, p3}));
    EXPECT_EQ(doc.pagesInGroup("Lamps"), std::vector<std::size_t>{});
    EXPECT_THROW(doc.renamePage(p2, ""), std::invalid_argument);
    EXPECT_THROW(doc.selectPage(9), std::out_of_range);
    EXPECT_THROW(doc.addPage("", "x"), std::invalid_argument);

    doc.selectPage(p1);
    draw(doc.current(), segment({0, 0}, {5, 5}), 0.0);
    doc.selectPage(p3);
    draw(doc.current(), segment({1, 0}, {5, 5}), 0.0);
    draw(doc.current(), segment({2, 0}, {5, 5}), 1.0);
    ASSERT_TRUE(doc.current().undo());
    ASSERT_TRUE(doc.current().undo());
    EXPECT_FALSE(doc.current().undo());
    EXPECT_EQ(doc.page(p1).liveStrokeIds().size(), 1u);  // another page's history
}

// ---------------------------------------------------------------------------------------------
// Files

SketchDocument sampleDocument() {
    SketchParams params;
    params.cleanup.trigger = sketch::CleanupTrigger::Explicit;
    SketchDocument doc(params);
    Rng rng{99};
    {
        SketchPage& p = doc.current();
        p.zoomAbout({3, 4}, 1.37);
        draw(p, segment({0, 0}, {20, 7}), 0.0, 0.25);
        PenSample s = pen({1.0 / 3, 2.0 / 7}, 1.0, 0.123456789);
        s.tiltDeg = glm::dvec2(12.5, -40.125);
        p.penDown(s);
        for (int i = 1; i < 10; ++i) {
            s.view = {rng.uniform(-50, 50), rng.uniform(-50, 50)};
            s.time += rng.uniform(0, 0.02);
            s.pressure = rng.uniform(0, 1);
            s.tiltDeg = glm::dvec2(rng.uniform(-90, 90), rng.uniform(-90, 90));
            p.penMove(s);
        }
        p.penUp();
        p.select({0, 1});
        p.scaleSelection(std::sqrt(2.0));
        p.moveSelection({std::acos(-1.0), -1e-17});
        p.setStrokeRole(1, Role::Outline);
        p.setMode(SketchMode::Cleanup);
        p.setKind(StrokeKind::Line);
        for (int i = 0; i < 3; ++i)
            draw(p, segment({0, 60 + 0.3 * i}, {40, 61 - 0.2 * i}), 3.0 + i, 0.6);
        p.endGroup();
        p.setCurveRole(0, Role::SurfaceLineX);
        draw(p, segment({0, 90}, {40, 90}), 8.0);
        p.undo();  // leaves a redo stack to save
    }
    doc.addPage("Second", "Other");
    {
        SketchPage& p = doc.current();
        for (int i = 0; i < 5; ++i)
            draw(p, segment({i * 3.0, 0}, {i * 3.0 + 10, 4}), i, 0.1 * (i + 1));
        p.select({3});
        p.deleteSelection();
        p.reuse(3);
        p.pan({-0.1, 1e-3});
    }
    doc.selectPage(0);
    return doc;
}

TEST(SketchFile, JsonRoundTripIsExact) {
    const SketchDocument doc = sampleDocument();
    const std::string text = doc.toJson();
    const SketchDocument back = SketchDocument::fromJson(text, doc.params());
    EXPECT_EQ(back.toJson(), text);
    ASSERT_EQ(back.pageCount(), doc.pageCount());
    EXPECT_EQ(back.currentIndex(), doc.currentIndex());
    for (std::size_t i = 0; i < doc.pageCount(); ++i) {
        const SketchPage &a = doc.page(i), &b = back.page(i);
        EXPECT_EQ(b.name(), a.name());
        EXPECT_EQ(b.group(), a.group());
        EXPECT_EQ(b.view(), a.view());
        EXPECT_EQ(b.mode(), a.mode());
        EXPECT_EQ(b.kind(), a.kind());
        EXPECT_EQ(b.content(), a.content());
        EXPECT_EQ(contentHash(b.content()), contentHash(a.content()));
        EXPECT_EQ(b.actions(), a.actions());
        EXPECT_EQ(b.redoStack(), a.redoStack());
        ASSERT_EQ(b.history().size(), a.history().size());
        for (std::size_t k = 0; k < a.history().size(); ++k) {
            const ArchivedStroke &x = a.history()[k], &y = b.history()[k];
            EXPECT_EQ(y.inkScale, x.inkScale);
            EXPECT_EQ(y.reusedFrom, x.reusedFrom);
            EXPECT_EQ(y.tiltDeg, x.tiltDeg);
            EXPECT_EQ(y.stroke.hasPressure, x.stroke.hasPressure);
            ASSERT_EQ(y.stroke.samples.size(), x.stroke.samples.size());
            for (std::size_t s = 0; s < x.stroke.samples.size(); ++s) {
                EXPECT_EQ(y.stroke.samples[s].position, x.stroke.samples[s].position);
                EXPECT_EQ(y.stroke.samples[s].time, x.stroke.samples[s].time);
                EXPECT_EQ(y.stroke.samples[s].pressure, x.stroke.samples[s].pressure);
            }
        }
    }
    // The loaded log keeps working: redo and undo give the same states as the original.
    SketchDocument live = sampleDocument();
    SketchDocument loaded = SketchDocument::fromJson(text, doc.params());
    ASSERT_TRUE(live.page(0).redo());
    ASSERT_TRUE(loaded.page(0).redo());
    EXPECT_EQ(loaded.page(0).content(), live.page(0).content());
    while (live.page(0).undo()) {
        ASSERT_TRUE(loaded.page(0).undo());
        EXPECT_EQ(loaded.page(0).content(), live.page(0).content());
    }
}

std::string errorOf(const std::string& text) {
    try {
        SketchDocument::fromJson(text);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(SketchFile, BadFilesNameTheField) {
    using nlohmann::json;
    const json good = json::parse(sampleDocument().toJson());
    struct Case {
        std::function<void(json&)> edit;
        std::string expected;  // start of the message
    };
    const std::vector<Case> cases = {
        {[](json& j) { j["pages"][1]["strokes"][3]["samples"][0]["pressure"] = 1.5; },
         "pages[1].strokes[3].samples[0].pressure: outside [0, 1]"},
        {[](json& j) { j["pages"][1]["strokes"][3]["samples"][0]["pressure"] = "hard"; },
         "pages[1].strokes[3].samples[0].pressure: expected a number"},
        {[](json& j) { j["pages"][0]["strokes"][1]["samples"][2].erase("t"); },
         "pages[0].strokes[1].samples[2].t: missing"},
        {[](json& j) { j["pages"][0]["strokes"][1]["samples"][2]["t"] = -5.0; },
         "pages[0].strokes[1].samples[2].t: time goes backwards"},
        {[](json& j) { j["pages"][0]["strokes"][1]["samples"][0]["tiltY"] = 91; },
         "pages[0].strokes[1].samples[0].tiltY: outside [-90, 90] degrees"},
        {[](json& j) { j["pages"][0]["strokes"][2]["id"] = 7; },
         "pages[0].strokes[2].id: expected 2"},
        {[](json& j) { j["pages"][1]["strokes"][0]["samples"] = json::array(); },
         "pages[1].strokes[0].samples: a stroke needs at least one sample"},
        {[](json& j) { j["pages"][0]["done"][1]["type"] = "paint"; },
         "pages[0].done[1].type: unknown action \"paint\""},
        {[](json& j) { j["pages"][0]["done"][0]["stroke"] = 40; },
         "pages[0].done[0]: stroke: unknown stroke 40"},
        {[](json& j) { j["pages"][1]["done"][1]["stroke"] = 0; },
         "pages[1].done[1]: stroke: stroke 0 is already live"},
        {[](json& j) { j["pages"][0]["redo"][0]["stroke"] = 0; },
         "pages[0].redo[0]: stroke: stroke 0 is already live"},
        {[](json& j) {
             for (json& a : j["pages"][0]["done"])
                 if (a["type"] == "role") a["role"] = "handle";
         },
         "pages[0].done[4].role: unknown role \"handle\""},
        {[](json& j) { j["pages"][0]["view"]["scale"] = 0; },
         "pages[0].view.scale: outside [1e-9, 1e9]"},
        {[](json& j) { j["pages"][0]["name"] = ""; }, "pages[0].name: must not be empty"},
        {[](json& j) { j["pages"][1].erase("group"); }, "pages[1].group: missing"},
        {[](json& j) { j["pages"][0]["mode"] = "ink"; }, "pages[0].mode: expected"},
        {[](json& j) { j["version"] = 2; }, "version: unsupported version 2"},
        {[](json& j) { j["format"] = "svg"; }, "format: expected \"vsculpt-sketch\""},
        {[](json& j) { j["current"] = 2; }, "current: no page 2"},
        {[](json& j) { j["pages"] = json::array(); }, "pages: a document needs at least one page"},
    };
    for (const Case& c : cases) {
        json bad = good;
        c.edit(bad);
        const std::string message = errorOf(bad.dump());
        EXPECT_EQ(message.substr(0, c.expected.size()), c.expected) << message;
    }
    EXPECT_EQ(errorOf(good.dump().substr(0, 200)).substr(0, 9), "not JSON:");
    EXPECT_EQ(errorOf("[1, 2]"), "(root): expected an object");
    EXPECT_EQ(errorOf(good.dump()), "(no error)");
}

TEST(SketchFile, EveryClassOfBadValueNamesItsField) {
    using nlohmann::json;
    const json good = json::parse(sampleDocument().toJson());
    // Page 0: strokes 0-5 (stroke 1 has pressure and tilt); done[2] scale, done[3] move,
    // done[4] stroke role, done[5] a clean-up stroke, done[9] curve role. Page 1: strokes 0-5,
    // stroke 5 reused from 3.
    const std::string s12 = "pages[0].strokes[1].samples[2]";
    struct Case {
        std::function<void(json&)> edit;
        std::string expected;  // start of the message
    };
    const auto sample = [](json& j) -> json& { return j["pages"][0]["strokes"][1]["samples"][2]; };
    const std::vector<Case> cases = {
        // Numbers that are not finite or lie beyond the documented bounds.
        {[&](json& j) { sample(j)["x"] = 1e308; }, s12 + ".x: outside [-1e6, 1e6] mm"},
        {[&](json& j) { sample(j)["y"] = -1000000.5; }, s12 + ".y: outside [-1e6, 1e6] mm"},
        {[&](json& j) { sample(j)["x"] = NAN; }, s12 + ".x: expected a number"},  // null
        {[&](json& j) { sample(j)["t"] = 1e300; }, s12 + ".t: outside [-1e10, 1e10] s"},
        {[&](json& j) { sample(j)["pressure"] = 1e308; }, s12 + ".pressure: outside [0, 1]"},
        {[&](json& j) { sample(j)["tiltX"] = -1e308; }, s12 + ".tiltX: outside [-90, 90] degrees"},
        {[](json& j) { j["pages"][0]["strokes"][0]["inkScale"] = 1e300; },
         "pages[0].strokes[0].inkScale: outside [1e-9, 1e9]"},
        {[](json& j) { j["pages"][0]["strokes"][0]["inkScale"] = 0; },
         "pages[0].strokes[0].inkScale: outside [1e-9, 1e9]"},
        {[](json& j) { j["pages"][0]["view"]["scale"] = 1e300; },
         "pages[0].view.scale: outside [1e-9, 1e9]"},
        {[](json& j) { j["pages"][0]["view"]["offset"][0] = 1e300; },
         "pages[0].view.offset[0]: outside [-1e9, 1e9] mm"},
        {[](json& j) { j["pages"][0]["done"][3]["delta"][0] = 1e300; },
         "pages[0].done[3].delta[0]: outside [-2e6, 2e6] mm"},
        {[](json& j) { j["pages"][0]["done"][2]["factor"] = 1e300; },
         "pages[0].done[2].factor: outside [1e-6, 1e6]"},
        {[](json& j) { j["pages"][0]["done"][2]["factor"] = -2; },
         "pages[0].done[2].factor: outside [1e-6, 1e6]"},
        {[](json& j) { j["pages"][0]["done"][2]["pivot"][1] = 1e300; },
         "pages[0].done[2].pivot[1]: outside [-1e6, 1e6] mm"},
        // In range, but it would carry a stroke off the canvas when replayed.
        {[](json& j) { j["pages"][0]["done"][3]["delta"][0] = 1.9e6; },
         "pages[0].done[3]: move: stroke 0 would leave the canvas [-1e6, 1e6] mm"},
        // Names, enums, roles and ids out of range.
        {[](json& j) { j["pages"][0]["kind"] = "spline"; },
         "pages[0].kind: expected \"line\" or \"curve\", got \"spline\""},
        {[](json& j) { j["pages"][0]["done"][5]["kind"] = "arc"; },
         "pages[0].done[5].kind: expected \"line\" or \"curve\""},
        {[](json& j) { j["pages"][0]["done"][4]["target"] = "both"; },
         "pages[0].done[4].target: expected \"stroke\" or \"curve\""},
        {[](json& j) { j["pages"][0]["done"][4]["role"] = 3; },
         "pages[0].done[4].role: expected a string"},
        {[](json& j) { j["pages"][0]["mode"] = 1; }, "pages[0].mode: expected a string"},
        {[](json& j) { j["pages"][0]["done"][0]["stroke"] = -1; },
         "pages[0].done[0]: stroke: unknown stroke -1"},
        {[](json& j) { j["pages"][0]["done"][0]["stroke"] = 18446744073709551615ULL; },
         "pages[0].done[0].stroke: integer out of range"},
        {[](json& j) { j["pages"][0]["done"][0]["stroke"] = 1e20; },
         "pages[0].done[0].stroke: expected an integer"},
        {[](json& j) { j["pages"][0]["done"][3]["strokes"] = {99}; },
         "pages[0].done[3].strokes[0]: no stroke 99 in the page"},
        {[](json& j) { j["pages"][0]["done"][9]["id"] = 99; },
         "pages[0].done[9]: role: no clean curve 99"},
        {[](json& j) { j["pages"][1]["strokes"][5]["reusedFrom"] = 99; },
         "pages[1].strokes[5].reusedFrom: must name an earlier stroke"},
        {[](json& j) { j["current"] = -1; }, "current: no page -1"},
        {[](json& j) { j["version"] = 1.5; }, "version: expected an integer"},
        // Wrong types.
        {[](json& j) { j["pages"][0]["strokes"][1]["samples"] = json::object(); },
         "pages[0].strokes[1].samples: expected an array"},
        {[&](json& j) { sample(j) = 5; }, s12 + ": expected an object"},
        {[&](json& j) { sample(j).erase("y"); }, s12 + ".y: missing"},
        {[](json& j) { j["pages"][0]["strokes"][1]["hasPressure"] = "yes"; },
         "pages[0].strokes[1].hasPressure: expected true or false"},
        {[](json& j) { j["pages"] = "x"; }, "pages: expected an array"},
        {[](json& j) { j["pages"][0] = json::array(); }, "pages[0]: expected an object"},
        {[](json& j) { j["pages"][0]["view"] = json::array(); },
         "pages[0].view: expected an object"},
        {[](json& j) {
             j["pages"][0]["done"][3]["delta"] = {1, 2, 3};
         },
         "pages[0].done[3].delta: expected [x, y]"},
        {[](json& j) { j["pages"][0]["name"] = 7; }, "pages[0].name: expected a string"},
        {[](json& j) { j["pages"][0]["done"] = json::object(); },
         "pages[0].done: expected an array"},
        // Absurd sizes, refused before their elements are read.
        {[](json& j) {
             json& samples = j["pages"][1]["strokes"][0]["samples"];
             while (samples.size() <= SketchLimits::maxStrokeSamples)
                 samples.push_back(samples[0]);
         },
         "pages[1].strokes[0].samples: more than 100000 elements"},
        {[](json& j) { j["pages"][0]["name"] = std::string(2000, 'n'); },
         "pages[0].name: longer than 1024 bytes"},
        {[](json& j) { j["pages"][1]["group"] = std::string(2000, 'g'); },
         "pages[1].group: longer than 1024 bytes"},
        {[](json& j) { j["pages"][0]["done"][3]["strokes"] = {0, 1, 2, 3, 4, 5, 0}; },
         "pages[0].done[3].strokes: more than 6 elements"},
        {[](json& j) { j["pages"] = json(std::vector<json>(SketchLimits::maxPages + 1)); },
         "pages: more than 10000 elements"},
        {[](json& j) {
             j["pages"][0]["strokes"] = json(std::vector<json>(SketchLimits::maxPageStrokes + 1));
         },
         "pages[0].strokes: more than 100000 elements"},
        {[](json& j) {
             j["pages"][0]["done"] = json(std::vector<json>(SketchLimits::maxPageActions + 1));
         },
         "pages[0].done: more than 1000000 elements"},
    };
    for (const Case& c : cases) {
        json bad = good;
        c.edit(bad);
        const std::string message = errorOf(bad.dump());
        EXPECT_EQ(message.substr(0, c.expected.size()), c.expected) << message;
    }
    // A number too large for a double fails in the parser, with the parser's words.
    json big = good;
    sample(big)["x"] = 12345.678;
    std::string text = big.dump();
    text.replace(text.find("12345.678"), 9, "1e400");
    EXPECT_EQ(errorOf(text).substr(0, 9), "not JSON:") << errorOf(text);
    // Nesting past 64 levels is refused before parsing, at the bracket that opens level 65
    // (writing such a value back, as the studio's loader does, recursed until the stack ran out).
    EXPECT_EQ(errorOf(std::string(100000, '[')), "1:65: nested more than 64 levels deep");
}

// Peak resident memory of this process so far (MB); each test runs in its own process under
// ctest, and the other tests here stay far below the margins used.
double peakRssMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // kB on Linux
}

std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(SketchLimits, PenInputBeyondTheBoundsIsRefusedNamingTheValue) {
    SketchPage page("p", "g");
    EXPECT_EQ(messageOf([&] {
                  page.penDown(pen({1e308, 0}, 0));
              }),
              "penDown: view position outside [-1e9, 1e9] mm");
    EXPECT_EQ(messageOf([&] {
                  page.penDown(pen({0, 0}, 1e11));
              }),
              "penDown: time outside [-1e10, 1e10] s");
    // A sane pen position through a view zoomed out to the limit lands off the canvas.
    page.setView({1e9, {0, 0}});
    EXPECT_EQ(messageOf([&] {
                  page.penDown(pen({10, 0}, 0));
              }),
              "penDown: canvas position outside [-1e6, 1e6] mm (the view maps the pen there)");
    EXPECT_EQ(messageOf([&] {
                  page.setView({1e10, {0, 0}});
              }),
              "view.scale must be in [1e-9, 1e9]");
    EXPECT_EQ(messageOf([&] {
                  page.setView({1, {1e10, 0}});
              }),
              "view.offset must be in [-1e9, 1e9]");
    page.setView({1e8, {0, 0}});
    EXPECT_EQ(messageOf([&] {
                  page.zoomAbout({1e10, 0}, 2);
              }),
              "zoomAbout: view point outside [-1e9, 1e9] mm");
    EXPECT_EQ(messageOf([&] {
                  page.zoomAbout({100, 0}, 0.5);
              }),
              "zoomAbout: the view would leave [-1e9, 1e9] mm");
    EXPECT_EQ(messageOf([&] { page.pan({100, 0}); }), "pan: the view would leave [-1e9, 1e9] mm");
    EXPECT_EQ(messageOf([&] { page.pan({1e300, 0}); }), "pan: delta outside [-1e9, 1e9] mm");
    EXPECT_EQ(page.view(), (CanvasView{1e8, {0, 0}}));  // refused calls changed nothing
    page.resetView();
    EXPECT_THROW(page.hover({0, -1e300}), std::invalid_argument);
    EXPECT_THROW(page.advanceTime(1e300), std::invalid_argument);
    EXPECT_FALSE(page.penIsDown());
    EXPECT_TRUE(page.history().empty());

    // Edits that would carry ink off the canvas.
    const int id = *draw(page, segment({0, 0}, {30, 10}), 0.0);
    page.select({id});
    const PageContent drawn = page.content();
    EXPECT_EQ(messageOf([&] {
                  page.moveSelection({1.5e6, 0});
              }),
              "move: stroke 0 would leave the canvas [-1e6, 1e6] mm");
    EXPECT_EQ(messageOf([&] {
                  page.moveSelection({3e6, 0});
              }),
              "move: delta not finite or outside [-2e6, 2e6] mm");
    EXPECT_EQ(messageOf([&] { page.scaleSelection(1e7); }), "scale: factor outside [1e-6, 1e6]");
    EXPECT_EQ(messageOf([&] {
                  page.scaleSelection(1e5, {0, 0});
              }),
              "scale: stroke 0 would leave the canvas [-1e6, 1e6] mm");
    ASSERT_TRUE(page.scaleSelection(1e-5, {0, 0}));
    EXPECT_EQ(messageOf([&] {
                  page.scaleSelection(1e-5, {0, 0});
              }),
              "scale: stroke 0 would reach a placement scale outside [1e-6, 1e6]");
    ASSERT_TRUE(page.undo());
    EXPECT_EQ(page.content(), drawn);
    EXPECT_EQ(page.undoCount(), 1u);
    EXPECT_THROW(page.selectLasso({{0, 0}, {1e300, 0}, {0, 1}}), std::invalid_argument);
    EXPECT_THROW(page.selectNearest({-1e300, 0}, 1.0), std::invalid_argument);

    // One stroke holds at most maxStrokeSamples samples; the stroke keeps those it has.
    page.penDown(pen({0, 0}, 10.0));
    for (std::size_t i = 1; i < SketchLimits::maxStrokeSamples; ++i)
        page.penMove(pen({1e-3 * double(i), 0}, 10.0 + 1e-4 * double(i)));
    EXPECT_EQ(messageOf([&] {
                  page.penMove(pen({200, 0}, 30.0));
              }),
              "penMove: the stroke has 100000 samples, the most a stroke can hold");
    const std::optional<int> full = page.penUp();
    ASSERT_TRUE(full);
    EXPECT_EQ(page.history()[std::size_t(*full)].stroke.samples.size(),
              SketchLimits::maxStrokeSamples);
    EXPECT_THROW(page.setName(std::string(2000, 'n')), std::invalid_argument);
}

TEST(SketchLimits, CanvasWideZigzagsInCleanupModeCostBoundedMemory) {
    // Two 20-point zigzags drawn over each other while zoomed far out, so that each spans the
    // whole canvas (38 km of ink): in clean-up mode they once took 2.1 GB.
    const double before = peakRssMb();
    SketchParams params;
    params.cleanup.trigger = sketch::CleanupTrigger::Explicit;
    params.cleanup.ignoreScribbles = false;  // make them a curve and a line, not scribbles
    SketchDocument doc(params);
    SketchPage& page = doc.current();
    page.setView({1e4, {0, 0}});  // one view mm is 10 m of canvas
    page.setMode(SketchMode::Cleanup);
    std::vector<int> ids;
    for (const StrokeKind kind : {StrokeKind::Curve, StrokeKind::Line}) {
        page.setKind(kind);
        for (int k = 0; k < 2; ++k) {
            Polyline2 view;
            for (int i = 0; i < 20; ++i)
                view.push_back({-95.0 + 10.0 * i + 3e-4 * k, (i % 2 ? 99.0 : -99.0) + 2e-4 * k});
            ids.push_back(*draw(page, view, 10.0 * double(ids.size())));
        }
        ASSERT_TRUE(page.endGroup());
    }
    const sketch::CleanupLimits& limits = params.cleanup.limits;
    for (int id : ids) {
        const std::string note = page.cleanupNote(id);
        EXPECT_NE(note.find("4096-point limit"), std::string::npos) << note;
    }
    for (std::size_t i = 0; i < page.cleanup().strokes().size(); ++i)
        EXPECT_LE(page.cleanup().strokeReport(int(i)).points, limits.maxStrokePoints);
    ASSERT_EQ(page.cleanCurves().size(), 2u);
    for (const CleanCurve& c : page.cleanCurves()) {
        EXPECT_LE(c.knots.size(), limits.maxCurveKnots);
        EXPECT_LE(c.samples.size(), limits.maxCurveKnots * 16 + 1);
    }
    // The file replays them under the same limits.
    const SketchDocument back = SketchDocument::fromJson(doc.toJson(), params);
    EXPECT_EQ(back.page(0).content(), page.content());
    EXPECT_LT(peakRssMb() - before, 100.0);
}

}  // namespace
}  // namespace vsculpt::studio
