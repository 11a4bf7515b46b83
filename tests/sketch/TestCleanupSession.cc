// The clean-up engine end to end: synthetic noisy strokes of known lines and curves.
#include "vsculpt/sketch/CleanupSession.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

constexpr double kPi = glm::pi<double>();

// Small deterministic generator (std distributions differ between standard libraries).
struct Rng {
    std::uint64_t state;
    double uniform(double lo, double hi) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return lo + (hi - lo) * double(state >> 11) * 0x1.0p-53;
    }
};

// A hand-drawn stroke along curve(u), u in [u0, u1]: smooth wobble of amplitude `wobble` mm
// across the curve plus 0.1 mm tablet jitter, 1 mm point spacing, 100 samples per second.
Stroke drawStroke(const std::function<glm::dvec2(double)>& curve, double u0, double u1,
                  double wobble, double startTime, Rng& rng) {
    const double phase = rng.uniform(0, 2 * kPi), freq = rng.uniform(0.5, 1.5);
    const glm::dvec2 a = curve(u0), b = curve(u1);
    const int n = std::max(8, int(glm::distance(a, b) * 1.5));
    Polyline2 pts;
    for (int i = 0; i <= n; ++i) {
        const double u = u0 + (u1 - u0) * i / n, eps = 1e-4 * (u1 - u0);
        const glm::dvec2 t = glm::normalize(curve(u + eps) - curve(u - eps));
        const glm::dvec2 nrm{-t.y, t.x};
        const double off = wobble * std::sin(phase + freq * kPi * i / n);
        pts.push_back(curve(u) + off * nrm +
                      glm::dvec2{rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1)});
    }
    return makeStroke(pts, startTime, 0.01);
}

double distanceToArc(const glm::dvec2& p, glm::dvec2 centre, double radius) {
    return std::abs(glm::distance(p, centre) - radius);
}

CleanupParams explicitParams() {
    CleanupParams p;
    p.trigger = CleanupTrigger::Explicit;
    return p;
}

TEST(CleanupSession, NoisyOverdrawnLinesConvergeToTheLine) {
    // True line through (10, 20) at 25 degrees, 100 mm long; 10 strokes each off by up to
    // 2 degrees and 1.5 mm, with random extent.
    const double angle = 25.0 * kPi / 180.0;
    const glm::dvec2 origin{10, 20}, dir{std::cos(angle), std::sin(angle)};
    const glm::dvec2 nrm{-dir.y, dir.x};
    CleanupParams params = explicitParams();
    params.lineRunningMean = true;  // plain mean of all strokes (the seed favours the newest)
    CleanupSession session(params);
    Rng rng{7};
    double worstStrokeAngle = 0.0;
    for (int k = 0; k < 10; ++k) {
        const double da = rng.uniform(-2, 2) * kPi / 180.0, off = rng.uniform(-1.5, 1.5);
        worstStrokeAngle = std::max(worstStrokeAngle, std::abs(da));
        const glm::dvec2 d{std::cos(angle + da), std::sin(angle + da)};
        const glm::dvec2 c = origin + 50.0 * dir + off * nrm;
        const double s0 = rng.uniform(-55, -45), s1 = rng.uniform(45, 55);
        const bool backwards = k % 3 == 1;  // drawing direction must not matter
        const auto line = [&](double u) { return c + u * d; };
        session.addStroke(drawStroke(line, backwards ? s1 : s0, backwards ? s0 : s1, 0.3, k, rng),
                          StrokeKind::Line);
    }
    session.endGroup();
    ASSERT_EQ(session.curveCount(), 1u);  // all ten were recognised as the same line
    const CleanCurve line = session.curves()[0];
    ASSERT_EQ(line.knots.size(), 2u);
    const glm::dvec2 got = glm::normalize(line.knots[1] - line.knots[0]);
    const double angleError = std::acos(std::min(1.0, std::abs(glm::dot(got, dir))));
    EXPECT_LT(angleError, 1.0 * kPi / 180.0);
    EXPECT_LT(angleError, worstStrokeAngle);
    for (const glm::dvec2& p : line.knots)
        EXPECT_LT(std::abs(glm::dot(p - origin, nrm)), 1.0);  // ends within 1 mm of the line
    EXPECT_EQ(line.strokes.size(), 10u);
    EXPECT_EQ(session.versionCount(0), 1u);  // one group, one version
}

TEST(CleanupSession, SeedLineRulePassesThroughNewestStrokeAndKeepsEdgesApart) {
    CleanupSession session(explicitParams());
    session.addStroke(makeStroke({{0, 0}, {50, 0}, {100, 0}}), StrokeKind::Line);
    session.addStroke(makeStroke({{0, 2}, {100, 2}}), StrokeKind::Line);
    session.addStroke(makeStroke({{50, -40}, {50, 40}}), StrokeKind::Line);  // crossing edge
    session.endGroup();
    const auto curves = session.curves();
    ASSERT_EQ(curves.size(), 2u);
    // Default offsetWeight 1: the mixed line is y = 2, the newest stroke's midpoint line.
    for (const glm::dvec2& p : curves[0].knots)
        EXPECT_NEAR(p.y, 2.0, 1e-9);
    EXPECT_EQ(curves[1].strokes, std::vector<int>{2});
}

TEST(CleanupSession, OverdrawnPartialStrokesConvergeToTheCurve) {
    // A 150-degree arc of radius 60 drawn as 7 overlapping partial strokes (each ~45 degrees)
    // with 0.4 mm wobble, the way designers build a long curve.
    const glm::dvec2 centre{0, 0};
    const double radius = 60.0;
    const auto arc = [&](double u) {
        return centre + radius * glm::dvec2{std::cos(u), std::sin(u)};
    };
    const double u0 = 15.0 * kPi / 180.0, u1 = 165.0 * kPi / 180.0;
    CleanupSession session(explicitParams());
    Rng rng{11};
    for (int k = 0; k < 7; ++k) {
        const double a = u0 + (u1 - u0) * k / 8.0 - 0.03, b = a + (u1 - u0) * 2.0 / 8.0 + 0.06;
        session.addStroke(drawStroke(arc, std::max(a, u0), std::min(b, u1), 0.4, k, rng),
                          StrokeKind::Curve);
    }
    session.endGroup();
    ASSERT_EQ(session.curveCount(), 1u);
    const CleanCurve c = session.curves()[0];
    EXPECT_FALSE(c.closed);
    double worst = 0.0;
    for (const glm::dvec2& p : c.samples)
        worst = std::max(worst, distanceToArc(p, centre, radius));
    EXPECT_LT(worst, 1.0);  // mm, against 0.4 mm wobble + 0.1 mm jitter
    EXPECT_LT(std::min(glm::distance(c.samples.front(), arc(u0)),
                       glm::distance(c.samples.front(), arc(u1))),
              2.0);
    EXPECT_LT(std::min(glm::distance(c.samples.back(), arc(u0)),
                       glm::distance(c.samples.back(), arc(u1))),
              2.0);
    // The curve spans the whole arc, not only the last stroke.
    EXPECT_GT(length(c.samples, false), 0.95 * radius * (u1 - u0));
}

TEST(CleanupSession, RepeatedFullOverdrawsStayWithinTheStrokesAndAverageWithWeight) {
    // Five full overdraws of a 120-degree arc with 1 mm wobble. Each replaces the last (seed
    // rule), so the result is never worse than the worst stroke; with newStrokeWeight 0.5 the
    // wobble of successive strokes partly cancels.
    const double radius = 50.0;
    const auto arc = [&](double u) { return radius * glm::dvec2{std::cos(u), std::sin(u)}; };
    const double u0 = 30.0 * kPi / 180.0, u1 = 150.0 * kPi / 180.0;
    double rms[2] = {0.0, 0.0};
    for (int w = 0; w < 2; ++w) {
        CleanupParams params = explicitParams();
        params.join.newStrokeWeight = w == 0 ? 1.0 : 0.5;
        params.featureChordRatio = 0.05;  // a 120-degree arc in one stroke needs > 3 points
        CleanupSession session(params);
        Rng rng{3};
        double worstStroke = 0.0;
        for (int k = 0; k < 5; ++k) {
            const Stroke s = drawStroke(arc, u0, u1, 1.0, k, rng);
            for (const StrokeSample& p : s.samples)
                worstStroke = std::max(worstStroke, distanceToArc(p.position, {0, 0}, radius));
            session.addStroke(s, StrokeKind::Curve);
        }
        session.endGroup();
        ASSERT_EQ(session.curveCount(), 1u);
        const Polyline2& samples = session.curve(0).samples;
        double worst = 0.0, sum2 = 0.0;
        for (const glm::dvec2& p : samples) {
            const double d = distanceToArc(p, {0, 0}, radius);
            worst = std::max(worst, d);
            sum2 += d * d;
        }
        rms[w] = std::sqrt(sum2 / double(samples.size()));
        EXPECT_LT(worst, worstStroke) << "weight " << params.join.newStrokeWeight;
    }
    EXPECT_LT(rms[1], rms[0]);
}

TEST(CleanupSession, CorrectionStrokeReplacesOnlyTheOverlappedPart) {
    // Clean a gentle wave, then redraw its middle 5 mm higher.
    const auto wave = [](double x) { return glm::dvec2{x, 10.0 * std::sin(x / 40.0)}; };
    CleanupSession session(explicitParams());
    Rng rng{5};
    session.addStroke(drawStroke(wave, 0, 120, 0.2, 0.0, rng), StrokeKind::Curve);
    session.addStroke(drawStroke(wave, 100, 200, 0.2, 1.0, rng), StrokeKind::Curve);
    session.endGroup();
    ASSERT_EQ(session.curveCount(), 1u);
    const CleanCurve before = session.curves()[0];

    const auto raised = [&](double x) {
        const double w = 0.5 - 0.5 * std::cos(2 * kPi * (x - 80.0) / 40.0);  // 0 at 80 and 120
        return wave(x) + glm::dvec2{0.0, 3.0 * w};
    };
    session.addStroke(drawStroke(raised, 80, 120, 0.0, 5.0, rng), StrokeKind::Curve);
    session.endGroup();
    ASSERT_EQ(session.curveCount(), 1u);  // corrected, not a new curve
    ASSERT_EQ(session.versionCount(0), 2u);
    const CleanCurve after = session.curves()[0];
    EXPECT_EQ(after.strokes, (std::vector<int>{0, 1, 2}));

    const auto yAt = [](const Polyline2& c, double x) {
        for (std::size_t i = 0; i + 1 < c.size(); ++i)
            if ((c[i].x - x) * (c[i + 1].x - x) <= 0.0) {
                const double t = (x - c[i].x) / (c[i + 1].x - c[i].x);
                return c[i].y + t * (c[i + 1].y - c[i].y);
            }
        return std::numeric_limits<double>::quiet_NaN();
    };
    // Over the correction the curve follows the new stroke ...
    EXPECT_NEAR(yAt(after.samples, 100.0), raised(100.0).y, 0.6);
    EXPECT_GT(yAt(after.samples, 100.0) - yAt(before.samples, 100.0), 2.0);
    // ... and away from it the curve is where it was.
    for (double x : {10.0, 30.0, 50.0, 150.0, 170.0, 190.0})
        EXPECT_NEAR(yAt(after.samples, x), yAt(before.samples, x), 0.3) << "x = " << x;

    // The old version can be chosen again, and the next correction builds on the chosen one.
    EXPECT_EQ(session.version(0, 0).samples, before.samples);
    EXPECT_THROW(session.version(0, 2), std::out_of_range);
    session.selectVersion(0, 0);
    EXPECT_EQ(session.curves()[0].samples, before.samples);
    EXPECT_THROW(session.selectVersion(0, 5), std::out_of_range);
    session.selectVersion(0, 1);
    EXPECT_EQ(session.curves()[0].samples, after.samples);
}

TEST(CleanupSession, ClosedCurveFromOverlappingStrokes) {
    const double radius = 30.0;
    const auto circle = [&](double u) { return radius * glm::dvec2{std::cos(u), std::sin(u)}; };
    CleanupSession session(explicitParams());
    Rng rng{9};
    for (int k = 0; k < 3; ++k)  // three 140-degree strokes going round
        session.addStroke(
            drawStroke(circle, k * 2 * kPi / 3, k * 2 * kPi / 3 + 140 * kPi / 180, 0.3, k, rng),
            StrokeKind::Curve);
    session.endGroup();
    ASSERT_EQ(session.curveCount(), 1u);
    const CleanCurve c = session.curves()[0];
    EXPECT_TRUE(c.closed);
    double worst = 0.0;
    for (const glm::dvec2& p : c.samples)
        worst = std::max(worst, distanceToArc(p, {0, 0}, radius));
    EXPECT_LT(worst, 0.05 * radius);
}

// A designer going round a loop again: the same group, or a later one correcting it.
TEST(CleanupSession, WholeLoopsDrawnOverALoopDoNotGoRoundTwice) {
    const double radius = 25.0;
    // A loose loop of `turns` turns starting at angle a0, wobbling by `wobble` mm.
    auto loop = [&](double a0, double turns, double wobble, double t0) {
        Polyline2 pts;
        const int n = int(2 * kPi * radius * turns);  // about 1 mm apart
        for (int i = 0; i <= n; ++i) {
            const double a = a0 + 2 * kPi * turns * i / n;
            const double r = radius + wobble * std::sin(5 * a);
            pts.push_back(r * glm::dvec2{std::cos(a), std::sin(a)});
        }
        return makeStroke(pts, t0, 0.01);
    };
    // Winding number of a closed polyline about the origin.
    auto winding = [](const Polyline2& p) {
        double total = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const glm::dvec2 a = p[i], b = p[(i + 1) % p.size()];
            total += std::atan2(a.x * b.y - a.y * b.x, glm::dot(a, b));
        }
        return total / (2 * kPi);
    };
    for (double chord : {0.0, 0.05})
        for (double weight : {1.0, 0.5}) {
            SCOPED_TRACE("featureChordRatio " + std::to_string(chord) + ", newStrokeWeight " +
                         std::to_string(weight));
            CleanupParams params = explicitParams();
            params.featureChordRatio = chord;
            params.join.newStrokeWeight = weight;
            CleanupSession session(params);
            session.addStroke(loop(0.1, 1.04, 0.4, 0), StrokeKind::Curve);
            session.addStroke(loop(1.3, 1.02, -0.4, 1), StrokeKind::Curve);
            session.endGroup();
            ASSERT_EQ(session.curveCount(), 1u);
            CleanCurve c = session.curves()[0];
            EXPECT_TRUE(c.closed);
            EXPECT_NEAR(winding(c.samples), 1.0, 1e-9);
            double worst = 0;
            for (const glm::dvec2& p : c.samples)
                worst = std::max(worst, distanceToArc(p, {0, 0}, radius));
            EXPECT_LT(worst, 0.08 * radius);
            // A later group going round again corrects the curve: still one turn.
            session.addStroke(loop(2.0, 1.03, 0.3, 5), StrokeKind::Curve);
            session.endGroup();
            ASSERT_EQ(session.curveCount(), 1u);
            EXPECT_EQ(session.versionCount(0), 2u);
            c = session.curves()[0];
            EXPECT_TRUE(c.closed);
            EXPECT_NEAR(winding(c.samples), 1.0, 1e-9);
        }
}

TEST(CleanupSession, PauseTriggerGroupsByTime) {
    CleanupSession session;  // defaults: pause trigger, 1 s
    const auto stroke = [](double y, double t0) {
        return makeStroke({{0, y}, {50, y}, {100, y}}, t0, 0.1);  // lasts 0.2 s
    };
    session.addStroke(stroke(0, 0.0), StrokeKind::Line);
    session.addStroke(stroke(1, 0.9), StrokeKind::Line);  // 0.7 s after the first ended
    EXPECT_EQ(session.pendingStrokes().size(), 2u);
    EXPECT_FALSE(session.advanceTime(1.5));  // 0.4 s after the last pen-up
    EXPECT_EQ(session.curveCount(), 0u);
    EXPECT_EQ(session.previewPending().size(), 1u);  // preview changes nothing
    EXPECT_EQ(session.curveCount(), 0u);
    EXPECT_TRUE(session.advanceTime(2.1));
    EXPECT_EQ(session.curveCount(), 1u);
    EXPECT_TRUE(session.pendingStrokes().empty());
    // A stroke starting after a long pause cleans up the group before it on its own.
    session.addStroke(stroke(60, 3.0), StrokeKind::Line);
    session.addStroke(stroke(61, 5.0), StrokeKind::Line);
    EXPECT_EQ(session.curveCount(), 2u);
    EXPECT_EQ(session.pendingStrokes(), std::vector<int>{3});
    EXPECT_EQ(session.strokes().size(), 4u);
}

TEST(CleanupSession, PressureAndExplicitTriggers) {
    CleanupParams params;
    params.trigger = CleanupTrigger::Pressure;
    CleanupSession session(params);
    Stroke light = makeStroke({{0, 0}, {100, 0}}, 0.0, 0.1);
    light.hasPressure = true;
    for (auto& s : light.samples)
        s.pressure = 0.4;
    Stroke hard = light;
    hard.samples[1].pressure = 0.95;
    session.addStroke(light, StrokeKind::Line);
    EXPECT_FALSE(session.advanceTime(100.0));  // time does not trigger in pressure mode
    EXPECT_EQ(session.curveCount(), 0u);
    session.addStroke(hard, StrokeKind::Line);
    EXPECT_EQ(session.curveCount(), 1u);
    EXPECT_EQ(session.curves()[0].strokes.size(), 2u);

    CleanupSession manual(explicitParams());
    manual.addStroke(light, StrokeKind::Line);
    manual.addStroke(hard, StrokeKind::Line);
    EXPECT_FALSE(manual.advanceTime(100.0));
    EXPECT_EQ(manual.curveCount(), 0u);
    // Switching between line and curve mode ends the group.
    manual.addStroke(makeStroke({{0, 50}, {50, 60}, {100, 50}}), StrokeKind::Curve);
    EXPECT_EQ(manual.curveCount(), 1u);
    EXPECT_TRUE(manual.endGroup());
    EXPECT_FALSE(manual.endGroup());
    EXPECT_EQ(manual.curveCount(), 2u);
    EXPECT_EQ(manual.strokeKind(2), StrokeKind::Curve);
}

TEST(CleanupSession, OlderStrokeCanBeChosenAgain) {
    CleanupSession session(explicitParams());
    const auto arch = [](double h) {
        Polyline2 p;
        for (int i = 0; i <= 50; ++i)
            p.push_back({2.0 * i, h * std::sin(kPi * i / 50.0)});
        return p;
    };
    session.addStroke(makeStroke(arch(20)), StrokeKind::Curve);
    session.endGroup();
    session.addStroke(makeStroke(arch(22)), StrokeKind::Curve);  // correction over all of it
    session.endGroup();
    ASSERT_EQ(session.curveCount(), 1u);
    const auto peak = [](const CleanCurve& c) {
        double m = 0.0;
        for (const glm::dvec2& p : c.samples)
            m = std::max(m, p.y);
        return m;
    };
    EXPECT_NEAR(peak(session.curves()[0]), 22.0, 0.5);
    const int v = session.restartFromStroke(0, 0);  // the designer prefers the first line
    EXPECT_EQ(v, 2);
    EXPECT_EQ(session.currentVersion(0), 2);
    EXPECT_NEAR(peak(session.curves()[0]), 20.0, 0.5);
    EXPECT_EQ(session.curves()[0].strokes, std::vector<int>{0});
    EXPECT_EQ(session.versionCount(0), 3u);
    EXPECT_THROW(session.restartFromStroke(0, 7), std::out_of_range);
}

TEST(CleanupSession, RandomScribblingNeverBreaksTheSession) {
    // Random walks, repeated points, tiny strokes, all three triggers: only zero-length strokes
    // are refused, and every curve stays finite and well formed.
    for (CleanupTrigger trigger :
         {CleanupTrigger::PauseTime, CleanupTrigger::Pressure, CleanupTrigger::Explicit}) {
        CleanupParams params;
        params.trigger = trigger;
        CleanupSession session(params);
        Rng rng{static_cast<std::uint64_t>(trigger) + 100};
        double t = 0.0;
        for (int k = 0; k < 60; ++k) {
            Stroke s;
            s.hasPressure = true;
            glm::dvec2 p{rng.uniform(0, 100), rng.uniform(0, 100)};
            const int n = int(rng.uniform(1, 40));
            const double step = rng.uniform(0.0, 1.0) < 0.2 ? 0.01 : rng.uniform(0.5, 8);
            for (int i = 0; i < n; ++i) {
                if (rng.uniform(0, 1) > 0.1)
                    p += step * glm::dvec2{rng.uniform(-1, 1), rng.uniform(-1, 1)};
                s.samples.push_back({p, t, rng.uniform(0, 1)});
                t += 0.01;
            }
            t += rng.uniform(0, 2);
            const StrokeKind kind = rng.uniform(0, 1) < 0.3 ? StrokeKind::Line : StrokeKind::Curve;
            if (strokeLength(s) > 0.0)
                session.addStroke(s, kind);
            else
                EXPECT_THROW(session.addStroke(s, kind), std::invalid_argument);
            if (k % 7 == 0) session.advanceTime(t);
            if (k % 11 == 0) session.endGroup();
        }
        session.endGroup();
        for (const CleanCurve& c : session.curves()) {
            ASSERT_GE(c.knots.size(), c.closed ? 3u : 2u);
            ASSERT_FALSE(c.samples.empty());
            for (const glm::dvec2& p : c.samples)
                ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
        }
    }
}

TEST(CleanupSession, DeterministicAndRejectsBadStrokes) {
    const auto run = [] {
        CleanupSession s(explicitParams());
        Rng rng{21};
        const auto arc = [](double u) { return 40.0 * glm::dvec2{std::cos(u), std::sin(u)}; };
        for (int k = 0; k < 4; ++k)
            s.addStroke(drawStroke(arc, 0.2 * k, 0.2 * k + 1.0, 0.5, k, rng), StrokeKind::Curve);
        s.endGroup();
        return s.curves();
    };
    const auto a = run(), b = run();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].knots, b[i].knots);
        EXPECT_EQ(a[i].samples, b[i].samples);
    }

    CleanupSession session(explicitParams());
    EXPECT_THROW(session.addStroke(Stroke{}, StrokeKind::Curve), std::invalid_argument);
    EXPECT_THROW(session.addStroke(makeStroke({{1, 1}, {1, 1}}), StrokeKind::Curve),
                 std::invalid_argument);
    EXPECT_THROW(session.addStroke(makeStroke({{0, 0}, {NAN, 1}}), StrokeKind::Line),
                 std::invalid_argument);
    EXPECT_TRUE(session.strokes().empty());
    // A scribble is kept but produces no curve.
    Polyline2 zigzag;
    for (int i = 0; i < 12; ++i) {
        zigzag.push_back({i * 0.8, 0.0});
        zigzag.push_back({i * 0.8 + 0.4, 15.0});
    }
    session.addStroke(makeStroke(zigzag), StrokeKind::Curve);
    EXPECT_TRUE(session.endGroup());
    EXPECT_EQ(session.strokes().size(), 1u);
    EXPECT_EQ(session.curveCount(), 0u);
    CleanupParams bad;
    bad.pauseSeconds = 0.0;
    EXPECT_THROW(CleanupSession{bad}, std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Limits: no stroke, whatever its size, makes the session's cost grow without bound.

// Peak resident memory of this process so far (MB). gtest_discover_tests runs every test in a
// process of its own, and the other tests here stay far below the margins used.
double peakRssMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // kB on Linux
}

// 20 points zigzagging between opposite edges of the canvas (+-1e6 mm): 38 km of ink, which
// at the 0.5 mm resampling step asked for 76 million points per stroke (2.1 GB and more for
// the pair). `k` shifts the copy drawn over it.
Stroke canvasZigzag(int k) {
    Polyline2 pts;
    for (int i = 0; i < 20; ++i)
        pts.push_back({-9.5e5 + 1e5 * i + 3.0 * k, (i % 2 ? 9.9e5 : -9.9e5) + 2.0 * k});
    return makeStroke(pts, 10.0 * k, 0.01);
}

void expectWithinLimits(const CleanupSession& s) {
    const CleanupLimits& limits = s.params().limits;
    for (const CleanCurve& c : s.curves()) {
        EXPECT_LE(c.knots.size(), limits.maxCurveKnots);
        EXPECT_LE(c.samples.size(),
                  limits.maxCurveKnots * std::size_t(s.params().samplesPerSpan) + 1);
        for (const glm::dvec2& p : c.samples)
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
    }
}

TEST(CleanupLimits, ZigzagsAcrossTheWholeCanvasCostBoundedMemory) {
    const double before = peakRssMb();
    for (const StrokeKind kind : {StrokeKind::Curve, StrokeKind::Line})
        for (const bool ignoreScribbles : {true, false})
            for (const double ratio : {0.0, 0.05, 1e-4}) {
                SCOPED_TRACE(std::to_string(int(kind)) + " " + std::to_string(ignoreScribbles) +
                             " " + std::to_string(ratio));
                CleanupParams params = explicitParams();
                params.ignoreScribbles = ignoreScribbles;
                params.featureChordRatio = ratio;
                CleanupSession session(params);
                for (int k = 0; k < 2; ++k)
                    session.addStroke(canvasZigzag(k), kind);
                EXPECT_LE(session.previewPending().size(), 1u);
                ASSERT_NO_THROW(session.endGroup());
                for (int k = 0; k < 2; ++k) {
                    const StrokeReport& r = session.strokeReport(k);
                    EXPECT_EQ(r.samples, 20u);
                    EXPECT_LE(r.points, params.limits.maxStrokePoints);
                    EXPECT_GE(r.points, params.limits.maxStrokePoints - 4);
                    EXPECT_TRUE(r.coarsened);
                    EXPECT_GT(r.spacing, 9000.0);
                    EXPECT_LE(r.featurePoints, params.limits.maxFeaturePoints);
                    EXPECT_NE(r.note.find("4096-point limit"), std::string::npos) << r.note;
                    EXPECT_EQ(r.scribble, ignoreScribbles);  // back and forth 19 times
                }
                // Without the scribble rule the pair is one curve or one line, as drawn.
                EXPECT_EQ(session.curveCount(), ignoreScribbles ? 0u : 1u);
                expectWithinLimits(session);
            }
    // All twelve sessions together; before the limits one of them needed over 2 GB.
    EXPECT_LT(peakRssMb() - before, 100.0);
}

TEST(CleanupLimits, ChainedStrokesKeepTheCurveWithinItsKnotLimit) {
    // 60 wavy strokes (not scribbles: each turn stays below the reversal angle), each
    // continuing where the last ended, in one group: every join chains about 15 more feature
    // points onto the curve.
    for (const bool smooth : {false, true}) {
        CleanupParams params = explicitParams();
        params.featureChordRatio = 0.01;
        params.smooth = smooth;
        CleanupSession session(params);
        for (int k = 0; k < 60; ++k) {
            Polyline2 pts;
            for (int i = 0; i <= 120; ++i) {
                const double x = 60.0 * k + 0.5 * i;
                pts.push_back({x, 3.0 * std::sin(x * 2.0 * kPi / 8.0)});
            }
            session.addStroke(makeStroke(pts, k, 0.001), StrokeKind::Curve);
        }
        ASSERT_NO_THROW(session.endGroup());
        ASSERT_EQ(session.curveCount(), 1u);
        const CleanCurve& c = session.curve(0);
        EXPECT_LE(c.knots.size(), params.limits.maxCurveKnots);
        EXPECT_NE(c.limitNote.find("limit 256"), std::string::npos) << c.limitNote;
        EXPECT_EQ(c.strokes.size(), 60u);
        // The simplified curve still runs the whole chain.
        EXPECT_NEAR(c.samples.front().x, 0.0, 1.0);
        EXPECT_NEAR(c.samples.back().x, 60.0 * 59 + 60.0, 1.0);
        expectWithinLimits(session);
    }
}

TEST(CleanupLimits, NormalDrawingIsUnchangedBitForBit) {
    // Partial arcs, a correction, a loop and lines, with the default limits and with limits
    // no input reaches: the same curves, and no stroke reports a limit.
    const auto run = [](CleanupLimits limits) {
        CleanupParams params = explicitParams();
        params.featureChordRatio = 0.05;
        params.limits = limits;
        CleanupSession s(params);
        Rng rng{5};
        const auto arc = [](double u) { return 60.0 * glm::dvec2{std::cos(u), std::sin(u)}; };
        for (int k = 0; k < 5; ++k)
            s.addStroke(drawStroke(arc, 0.3 * k, 0.3 * k + 0.8, 0.4, k, rng), StrokeKind::Curve);
        s.endGroup();
        s.addStroke(drawStroke(arc, 0.5, 1.2, 0.4, 6, rng), StrokeKind::Curve);
        s.endGroup();
        const auto circle = [](double u) {
            return glm::dvec2{200, 0} + 30.0 * glm::dvec2{std::cos(u), std::sin(u)};
        };
        s.addStroke(drawStroke(circle, 0.0, 2 * kPi + 0.3, 0.3, 8, rng), StrokeKind::Curve);
        s.endGroup();
        const auto line = [](double u) { return glm::dvec2{u, 0.3 * u - 50}; };
        for (int k = 0; k < 3; ++k)
            s.addStroke(drawStroke(line, -80, 120, 0.3, 10 + k, rng), StrokeKind::Line);
        s.endGroup();
        for (std::size_t i = 0; i < s.strokes().size(); ++i) {
            EXPECT_TRUE(s.strokeReport(int(i)).note.empty()) << s.strokeReport(int(i)).note;
            EXPECT_EQ(s.strokeReport(int(i)).spacing, params.resampleSpacing);
        }
        for (const CleanCurve& c : s.curves())
            EXPECT_TRUE(c.limitNote.empty());
        return s.curves();
    };
    CleanupLimits unreachable;
    unreachable.maxStrokePoints = unreachable.maxFeaturePoints = unreachable.maxCurveKnots =
        unreachable.maxGroupInkPoints = std::size_t(1) << 40;
    const auto a = run({}), b = run(unreachable);
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].knots, b[i].knots);
        EXPECT_EQ(a[i].samples, b[i].samples);
        EXPECT_EQ(a[i].closed, b[i].closed);
    }
}

TEST(CleanupLimits, RefusesParametersThatWouldUnboundTheCost) {
    CleanupParams p;
    p.samplesPerSpan = 100000;
    EXPECT_THROW(CleanupSession{p}, std::invalid_argument);
    p = {};
    p.join.samplesPerSpan = 0;
    EXPECT_THROW(CleanupSession{p}, std::invalid_argument);
    p = {};
    p.limits.maxStrokePoints = 3;
    EXPECT_THROW(CleanupSession{p}, std::invalid_argument);
    p = {};
    p.limits.maxCurveKnots = 2;
    EXPECT_THROW(CleanupSession{p}, std::invalid_argument);
    p = {};
    p.resampleSpacing = 1e-5;  // the point limit, not the step, bounds the work
    CleanupSession tiny(p);
    tiny.addStroke(makeStroke({{0, 0}, {10, 0}, {20, 5}}), StrokeKind::Curve);
    EXPECT_LE(tiny.strokeReport(0).points, p.limits.maxStrokePoints);
    EXPECT_TRUE(tiny.strokeReport(0).coarsened);
    EXPECT_THROW(tiny.strokeReport(1), std::out_of_range);
    // Positions beyond the canvas bound are refused, not resampled into gigabytes.
    EXPECT_THROW(tiny.addStroke(makeStroke({{0, 0}, {1e308, 0}}), StrokeKind::Curve),
                 std::invalid_argument);
    EXPECT_EQ(tiny.strokes().size(), 1u);
}

}  // namespace
}  // namespace vsculpt::sketch
