// SPDX-License-Identifier: MIT
// Issue #13, placement mode "swept": carve = subtract the tool's swept volume, add = union with
// it, dabs of the tool's size, smooth strokes, no spurious pieces. Measured in the field
// (docs/placement.md).
//
// "Penetration" p is how far the tool's lowest point lies below the surface, as a fraction of
// the tool radius rho = D/2: at 100 % the tool's centre is on the surface. A carve then leaves
// a groove p deep, an add a bump 2 rho - p high (the tool's top above the surface).
//
// Set VSCULPT_PLACEMENT_TABLES=1 to print the measured tables.
#include "vsculpt/core/PlaceStroke.h"

#include "TestHelpers.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/SweptVertices.h"
#include "vsculpt/core/Zoom.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>
#include <thread>
#include <tuple>

using namespace vsculpt::core;
using vsculpt::test::emptyConfig;
using vsculpt::test::linePath;

namespace {

bool printTables() {
    const char* e = std::getenv("VSCULPT_PLACEMENT_TABLES");
    return e && *e && *e != '0';
}

/// Distance along the ray o + t d (t in [0, tMax]) to the first point where (f > 0) != startIn,
/// refined by bisection; tMax when there is none.
double firstCrossing(FieldProbe& probe, const Vec3& o, const Vec3& d, double tMax, double step) {
    const bool startIn = probe.value(o) > 0;
    double lo = 0, hi = step;
    while (hi < tMax && (probe.value(o + hi * d) > 0) == startIn) {
        lo = hi;
        hi += step;
    }
    if (hi >= tMax) return tMax;
    for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((probe.value(o + mid * d) > 0) == startIn ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

struct Stats {
    double min = 1e300, max = -1e300, sum = 0;
    int n = 0;
    void add(double v) {
        min = std::min(min, v);
        max = std::max(max, v);
        sum += v;
        ++n;
    }
    double mean() const { return n ? sum / n : 0; }
};

constexpr double kSphereRadius = 40;

/// Unit vectors (u0 = where the stroke's middle lies on the sphere, t0 = its direction there):
/// along a lattice axis, along a face diagonal, and a generic one.
struct Direction {
    Vec3 u0, t0;
    const char* name;
};
std::vector<Direction> directions() {
    const Vec3 g = glm::normalize(Vec3(0.31, -0.52, 0.8));
    const Vec3 gt = glm::normalize(glm::cross(g, Vec3(0.2, 0.9, -0.1)));
    return {{Vec3(0, 0, 1), Vec3(1, 0, 0), "axis"},
            {Vec3(0, 0, 1), glm::normalize(Vec3(1, 1, 0)), "diagonal"},
            {g, gt, "generic"}};
}

/// Groove depth (carve) or bump height (add) relative to what the tool's swept volume gives,
/// along a great-circle stroke on the initial sphere with the tool's lowest point `pen` tool
/// radii below the surface. Probed along the radius at many points of the stroke's middle.
/// refineLevels: placement.refine_levels, or -1 for the environment's VSCULPT_REFINE_LEVELS
/// (0 without it).
Stats sphereStroke(ToolOp op, int level, double pen, const Direction& dir,
                   PlacementMode mode = PlacementMode::Swept, int refineLevels = -1) {
    SculptConfig cfg = emptyConfig(mode);
    cfg.sphereRadiusMm = kSphereRadius;
    // VSCULPT_REFINE_LEVELS=k: with placement.refine_levels = k ("Refining strokes").
    if (const char* e = std::getenv("VSCULPT_REFINE_LEVELS")) cfg.refineLevels = std::atoi(e);
    if (refineLevels >= 0) cfg.refineLevels = refineLevels;
    Sculpture s(cfg);
    const ToolLevel& tl = s.levels().level(level);
    const double rho = 0.5 * tl.diameterMm;
    const double rc = kSphereRadius + rho - pen * rho;  // the tool centre's radius
    const double halfLength = 3 * tl.spacingMm + tl.supportMm + 2 * rho;
    const double halfAngle = std::min(halfLength / rc, 1.4);
    auto at = [&](double th, double r) {
        return (std::cos(th) * dir.u0 + std::sin(th) * dir.t0) * r;
    };
    std::vector<Vec3> path;
    const int n = int(std::ceil(2 * halfAngle * rc / (0.25 * rho)));
    for (int i = 0; i <= n; ++i)
        path.push_back(at(-halfAngle + 2 * halfAngle * i / n, rc));
    applyStroke(s, op, level, path);
    FieldProbe probe(s);
    const double expected = op == ToolOp::Carve ? pen * rho : (2 - pen) * rho;
    const double measureAngle = std::min(2 * tl.spacingMm / rc, 0.5 * halfAngle);
    Stats st;
    const double outer = kSphereRadius + 2 * rho + tl.supportMm + 1;
    for (int i = 0; i <= 24; ++i) {
        const double th = -measureAngle + 2 * measureAngle * i / 24;
        const Vec3 u = at(th, 1.0);
        // From outside inward to the first material.
        const double r = outer - firstCrossing(probe, u * outer, -u, outer, 0.02 * rho);
        const double got = op == ToolOp::Carve ? kSphereRadius - r : r - kSphereRadius;
        st.add(got / expected);
    }
    return st;
}

/// Clay built from many strokes of sizes 4-6: a slab whose top undulates around z ~ 15.
std::unique_ptr<Sculpture> makeClay(int refineLevels = 0) {
    SculptConfig cfg = emptyConfig(PlacementMode::Swept);
    cfg.refineLevels = refineLevels;
    // VSCULPT_CLAY_FINER_LEVELS=k: the slab itself built with placement.finer_lattice_levels
    // = k, as a project at that setting would build it (docs/placement.md "Finer lattices").
    if (const char* e = std::getenv("VSCULPT_CLAY_FINER_LEVELS"))
        cfg.finerLatticeLevels = std::atoi(e);
    // VSCULPT_CLAY_REFINE_LEVELS=k: built with placement.refine_levels = k ("Refining strokes").
    if (const char* e = std::getenv("VSCULPT_CLAY_REFINE_LEVELS")) cfg.refineLevels = std::atoi(e);
    auto s = std::make_unique<Sculpture>(cfg);
    int i = 0;
    for (double z : {-16.0, -8.0, 0.0, 8.0})
        for (double y = -30; y <= 30; y += 6, ++i)
            applyStroke(*s, ToolOp::Add, 4 + i % 3, linePath(Vec3(-50, y, z), Vec3(50, y, z), 2.0));
    return s;
}

double surfaceHeight(FieldProbe& probe, double x, double y, double top) {
    return top - firstCrossing(probe, Vec3(x, y, top), Vec3(0, 0, -1), top + 40, 0.05);
}

/// The same on clay built from strokes: a straight stroke across the slab's top, heights
/// probed vertically; the expected depth (height) at each probe comes from the surface there
/// before the stroke.
Stats clayStroke(Sculpture* s, ToolOp op, int level, double pen, double angleDeg) {
    const ToolLevel& tl = s->levels().level(level);
    const double rho = 0.5 * tl.diameterMm;
    const double a = angleDeg * std::numbers::pi / 180;
    const Vec3 t(std::cos(a), std::sin(a), 0);
    const Vec3 mid(1.3, -0.7, 0);
    const double top = 60;
    std::vector<double> before;
    const double measure = 2 * tl.spacingMm;
    {
        FieldProbe probe(*s);
        for (int i = 0; i <= 24; ++i) {
            const Vec3 q = mid + t * (-measure + 2 * measure * i / 24);
            before.push_back(surfaceHeight(probe, q.x, q.y, top));
        }
    }
    const double zc = before[12] + rho - pen * rho;
    const double halfLength = 3 * tl.spacingMm + tl.supportMm + 2 * rho;
    std::vector<SkeletonChange> changes;
    applyStroke(*s, op, level,
                linePath(mid - t * halfLength + Vec3(0, 0, zc),
                         mid + t * halfLength + Vec3(0, 0, zc), 0.25 * rho),
                &changes);
    FieldProbe probe(*s);
    Stats st;
    for (int i = 0; i <= 24; ++i) {
        const Vec3 q = mid + t * (-measure + 2 * measure * i / 24);
        const double h = surfaceHeight(probe, q.x, q.y, top);
        // The surface undulates, so the error is taken relative to the nominal depth (height).
        const double expected = op == ToolOp::Carve ? before[i] - (zc - rho) : zc + rho - before[i];
        const double got = op == ToolOp::Carve ? before[i] - h : h - before[i];
        const double nominal = op == ToolOp::Carve ? pen * rho : (2 - pen) * rho;
        st.add(1 + (got - std::max(0.0, expected)) / nominal);
        if (std::getenv("VSCULPT_PROBE_PRINT")) {
            // The stroke's change of the field at the old surface there, lattice by lattice.
            std::map<int, double> byLevel;
            const Vec3 at(q.x, q.y, before[i]);
            for (const SkeletonChange& c : changes) {
                const ToolLevel& cl = s->levels().level(c.level);
                const Vec3 v = Vec3(c.coord.x, c.coord.y, c.coord.z) * cl.spacingMm;
                const double d = glm::length(at - v);
                if (d >= cl.supportMm) continue;
                byLevel[c.level] +=
                    (double(c.after.value_or(0.0f)) - double(c.before.value_or(0.0f))) *
                    s->levels().falloff().value(d / cl.supportMm);
            }
            std::printf("  probe %2d before %7.3f expected %6.3f got %6.3f  ratio %.3f  change", i,
                        before[i], expected, got, 1 + (got - std::max(0.0, expected)) / nominal);
            for (const auto& [l, c] : byLevel)
                std::printf("  L%d %+.4f", l, c);
            std::printf("\n");
        }
    }
    revertChanges(*s, changes);
    return st;
}

/// Radius of a single-sample add in empty space over 64 directions, / rho.
Stats dabRadius(int level) {
    Sculpture s(emptyConfig(PlacementMode::Swept));
    const ToolLevel& tl = s.levels().level(level);
    const double rho = 0.5 * tl.diameterMm;
    const Vec3 c = Vec3(0.37, -0.21, 0.13) * tl.spacingMm;
    applyStroke(s, ToolOp::Add, level, std::vector<Vec3>{c});
    FieldProbe probe(s);
    Stats st;
    const int n = 64;
    const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z);
        const Vec3 d(r * std::cos(golden * i), r * std::sin(golden * i), z);
        st.add(firstCrossing(probe, c, d, 4 * rho, 0.02 * rho) / rho);
    }
    return st;
}

/// Depth of a single-sample carve into the sphere with the tool's centre on the surface, / rho.
double dabPit(int level) {
    SculptConfig cfg = emptyConfig(PlacementMode::Swept);
    cfg.sphereRadiusMm = kSphereRadius;
    Sculpture s(cfg);
    const double rho = 0.5 * s.levels().level(level).diameterMm;
    const Vec3 u = glm::normalize(Vec3(0.2, 0.3, 0.93));
    applyStroke(s, ToolOp::Carve, level, std::vector<Vec3>{u * kSphereRadius});
    FieldProbe probe(s);
    const double outer = kSphereRadius + 3 * rho;
    return (kSphereRadius - (outer - firstCrossing(probe, u * outer, -u, outer, 0.02 * rho))) / rho;
}

/// Radius of a straight add stroke in empty space, / rho, at 16 angles x 16 axial positions
/// over two lattice spacings.
Stats strokeRadius(int level, const Vec3& direction) {
    Sculpture s(emptyConfig(PlacementMode::Swept));
    const ToolLevel& tl = s.levels().level(level);
    const double rho = 0.5 * tl.diameterMm;
    const Vec3 d = glm::normalize(direction);
    const Vec3 o = Vec3(0.29, 0.41, -0.17) * tl.spacingMm;
    const double halfLength = 3 * tl.spacingMm + tl.supportMm + 2 * rho;
    applyStroke(s, ToolOp::Add, level,
                linePath(o - d * halfLength, o + d * halfLength, 0.25 * rho));
    const auto r = vsculpt::test::tubeRadius(s, o, d, tl.spacingMm, 4 * rho, 16, 16);
    Stats st;
    st.min = r.min / rho;
    st.max = r.max / rho;
    st.sum = r.mean / rho;
    st.n = 1;
    return st;
}

std::vector<Vec3> rippleDirections() {
    return {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(0.83, 0.31, -0.46),
            Vec3(-0.2, 0.7, 0.35)};
}

}  // namespace

TEST(CarveDepth, PrintTables) {
    if (!printTables()) GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    for (ToolOp op : {ToolOp::Carve, ToolOp::Add}) {
        std::printf("\n%s on the sphere: measured / expected (min..max over the middle)\n",
                    toString(op));
        for (const Direction& d : directions()) {
            std::printf("%-8s", d.name);
            for (double pen : {0.2, 0.6, 1.0, 1.4})
                std::printf(" | pen %3.0f%%      ", pen * 100);
            std::printf("\n");
            for (int k = 1; k <= 7; ++k) {
                std::printf("size %d  ", k);
                for (double pen : {0.2, 0.6, 1.0, 1.4}) {
                    const Stats st = sphereStroke(op, k, pen, d);
                    std::printf(" | %5.2f..%5.2f", st.min, st.max);
                }
                std::printf("\n");
            }
        }
    }
}

/// Half-width of a groove at half its expected depth, / the tool's (the chord of the tool's
/// circle there), at the middle of a great-circle carve on the sphere.
double grooveHalfWidth(int level, double pen, const Direction& dir) {
    SculptConfig cfg = emptyConfig(PlacementMode::Swept);
    cfg.sphereRadiusMm = kSphereRadius;
    Sculpture s(cfg);
    const ToolLevel& tl = s.levels().level(level);
    const double rho = 0.5 * tl.diameterMm;
    const double rc = kSphereRadius + rho - pen * rho;
    const double halfAngle = std::min((3 * tl.spacingMm + tl.supportMm + 2 * rho) / rc, 1.4);
    auto at = [&](double th, double r) {
        return (std::cos(th) * dir.u0 + std::sin(th) * dir.t0) * r;
    };
    std::vector<Vec3> path;
    const int n = int(std::ceil(2 * halfAngle * rc / (0.25 * rho)));
    for (int i = 0; i <= n; ++i)
        path.push_back(at(-halfAngle + 2 * halfAngle * i / n, rc));
    applyStroke(s, ToolOp::Carve, level, path);
    FieldProbe probe(s);
    const Vec3 side = glm::normalize(glm::cross(dir.u0, dir.t0));
    const double half = 0.5 * pen * rho;
    const double outer = kSphereRadius + 2 * rho + tl.supportMm + 1;
    auto depthAt = [&](double q) {  // q: lateral offset, mm (angle on the sphere)
        const Vec3 u = glm::normalize(dir.u0 * kSphereRadius + side * q);
        return kSphereRadius - (outer - firstCrossing(probe, u * outer, -u, outer, 0.02 * rho));
    };
    double lo = 0, hi = 3 * rho;  // bisection on each side for depth = half
    auto edge = [&](double sign) {
        double a = lo, b = hi;
        for (int i = 0; i < 30; ++i) {
            const double m = 0.5 * (a + b);
            (depthAt(sign * m) > half ? a : b) = m;
        }
        return 0.5 * (a + b);
    };
    const double expected = std::sqrt(rho * rho - (rho - half) * (rho - half));
    return 0.5 * (edge(1) + edge(-1)) / expected;
}

TEST(CarveDepth, PrintGrooveWidth) {
    if (!printTables()) GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    std::printf("\ngroove half-width at half depth / the tool's, sphere, size 4\n");
    for (const Direction& d : directions()) {
        std::printf("%-8s", d.name);
        for (double pen : {0.2, 0.6, 1.0, 1.4})
            std::printf("  pen %3.0f%%: %.2f", pen * 100, grooveHalfWidth(4, pen, d));
        std::printf("\n");
    }
}

TEST(CarveDepth, PrintThesisMode) {
    if (!printTables()) GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    for (ToolOp op : {ToolOp::Carve, ToolOp::Add}) {
        std::printf("\nthesis mode, %s on the sphere, generic direction: measured / expected\n",
                    toString(op));
        for (int k = 1; k <= 7; ++k) {
            std::printf("size %d  ", k);
            for (double pen : {0.2, 0.6, 1.0, 1.4}) {
                const Stats st = sphereStroke(op, k, pen, directions()[2], PlacementMode::Thesis);
                std::printf(" | %5.2f..%5.2f", st.min, st.max);
            }
            std::printf("\n");
        }
    }
}

TEST(CarveDepth, PrintClayDabRipple) {
    if (!printTables()) GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    auto clay = makeClay();
    // VSCULPT_FINER_LEVELS=k: the same clay (built as always) carved and added to with
    // placement.finer_lattice_levels = k (docs/placement.md "Finer lattices").
    // VSCULPT_REFINE_LEVELS=k: with placement.refine_levels = k ("Refining strokes").
    const char* finerEnv = std::getenv("VSCULPT_FINER_LEVELS");
    const char* refineEnv = std::getenv("VSCULPT_REFINE_LEVELS");
    if (finerEnv || refineEnv) {
        SculptConfig cfg = clay->config();
        if (finerEnv) cfg.finerLatticeLevels = std::atoi(finerEnv);
        if (refineEnv) cfg.refineLevels = std::atoi(refineEnv);
        auto finer = std::make_unique<Sculpture>(cfg);
        clay->store().forEach(
            [&](const SkeletonEntry& e) { finer->store().set(e.level, e.coord, e.weight); });
        clay = std::move(finer);
    }
    for (ToolOp op : {ToolOp::Carve, ToolOp::Add}) {
        std::printf("\n%s on clay of strokes: measured / expected (min..max)\n", toString(op));
        for (double ang : {90.0, 30.0}) {
            std::printf("angle %2.0f", ang);
            for (double pen : {0.2, 0.6, 1.0, 1.4})
                std::printf(" | pen %3.0f%%      ", pen * 100);
            std::printf("\n");
            for (int k = 1; k <= 7; ++k) {
                std::printf("size %d  ", k);
                for (double pen : {0.2, 0.6, 1.0, 1.4}) {
                    const Stats st = clayStroke(clay.get(), op, k, pen, ang);
                    std::printf(" | %5.2f..%5.2f", st.min, st.max);
                }
                std::printf("\n");
            }
        }
    }
    std::printf("\ndab: add radius / rho (mean, min..max over 64 directions); carve pit / rho\n");
    for (int k = 1; k <= 7; ++k) {
        const Stats st = dabRadius(k);
        std::printf("size %d: %.3f (%.3f..%.3f)  pit %.3f\n", k, st.mean(), st.min, st.max,
                    dabPit(k));
    }
    std::printf("\nstroke radius / rho: mean (min..max) per direction\n");
    for (int k = 1; k <= 7; ++k) {
        std::printf("size %d:", k);
        for (const Vec3& d : rippleDirections()) {
            const Stats st = strokeRadius(k, d);
            std::printf("  %.3f (%.3f..%.3f)", st.mean(), st.min, st.max);
        }
        std::printf("\n");
    }
}

TEST(CarveDepth, PrintCosts) {
    if (!printTables()) GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    // VSCULPT_FINER_LEVELS=k: with placement.finer_lattice_levels = k.
    const char* finerEnv = std::getenv("VSCULPT_FINER_LEVELS");
    const int finer = finerEnv ? std::atoi(finerEnv) : 0;
    std::printf("\nskeletons per 10 tool diameters of stroke, and placement time per sample\n");
    for (int k = 1; k <= 7; ++k) {
        for (ToolOp op : {ToolOp::Add, ToolOp::Carve}) {
            SculptConfig cfg = emptyConfig(PlacementMode::Swept);
            cfg.finerLatticeLevels = finer;
            cfg.sphereRadiusMm = op == ToolOp::Carve ? 200 : 0;  // carve well inside material
            Sculpture s(cfg);
            const double D = s.levels().level(k).diameterMm;
            const Vec3 d = glm::normalize(Vec3(0.83, 0.31, -0.46));
            const auto path = linePath(-d * (5 * D), d * (5 * D), 0.25 * D);
            const auto t0 = std::chrono::steady_clock::now();
            std::vector<SkeletonChange> changes;
            applyStroke(s, op, k, path, &changes);
            const double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
            std::printf("size %d %-5s: %6zu skeletons, %7.3f ms per sample\n", k, toString(op),
                        s.store().vertexCount(), ms / double(path.size()));
        }
    }
    // Along a surface, where the closed-loop fit acts: a great-circle stroke on the initial
    // sphere with the tool's centre on the surface, samples a quarter of the tool apart.
    std::printf("\nplacement time per sample along the sphere's surface (100 %% penetration)\n");
    for (int k = 1; k <= 7; ++k) {
        for (ToolOp op : {ToolOp::Add, ToolOp::Carve}) {
            SculptConfig cfg = emptyConfig(PlacementMode::Swept);
            cfg.finerLatticeLevels = finer;
            cfg.sphereRadiusMm = kSphereRadius;
            Sculpture s(cfg);
            const double rho = 0.5 * s.levels().level(k).diameterMm;
            const Direction dir = directions()[2];
            const double halfAngle = std::min(10 * rho / kSphereRadius, 1.4);
            const int n = int(std::ceil(2 * halfAngle * kSphereRadius / (0.25 * rho)));
            std::vector<Vec3> path;
            for (int i = 0; i <= n; ++i) {
                const double th = -halfAngle + 2 * halfAngle * i / n;
                path.push_back((std::cos(th) * dir.u0 + std::sin(th) * dir.t0) * kSphereRadius);
            }
            const auto t0 = std::chrono::steady_clock::now();
            applyStroke(s, op, k, path);
            const double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
            std::printf("size %d %-5s: %7.3f ms per sample\n", k, toString(op),
                        ms / double(path.size()));
        }
    }
}

// ---------------------------------------------------------------- assertions
//
// The bounds are what the swept-mode rule achieves at the default lattice (sigma = 1/2), with
// the closed-loop fit: the 10 % on the sphere for every size, penetration and
// direction, and on clay of strokes for carves with sizes 1-5 from 60 % and size 6 from 100 %,
// and for every add but size 7 at 140 %; shallow carves on clay, and the two largest tools
// there where their lattices are coarser than the clay's undulation, are not held to it
// (docs/placement.md has the tables).

TEST(CarveDepth, GroovesAndBumpsOnTheSphereFollowTheTool) {
    for (const Direction& d : directions()) {
        for (int k = 1; k <= 7; ++k) {
            for (double pen : {0.2, 0.6, 1.0, 1.4}) {
                const Stats carve = sphereStroke(ToolOp::Carve, k, pen, d);
                EXPECT_GE(carve.min, 0.9) << "carve size " << k << " pen " << pen << " " << d.name;
                EXPECT_LE(carve.max, 1.1) << "carve size " << k << " pen " << pen << " " << d.name;
                // A groove, not a row of pits: the depth varies little along the stroke
                // (measured: 0.13 at 20 %, 0.06 from 60 % on).
                EXPECT_LE(carve.max - carve.min, pen >= 0.6 ? 0.1 : 0.15)
                    << "carve size " << k << " pen " << pen << " " << d.name;
                const Stats add = sphereStroke(ToolOp::Add, k, pen, d);
                EXPECT_GE(add.min, 0.9) << "add size " << k << " pen " << pen << " " << d.name;
                EXPECT_LE(add.max, 1.1) << "add size " << k << " pen " << pen << " " << d.name;
                EXPECT_LE(add.max - add.min, 0.1)
                    << "add size " << k << " pen " << pen << " " << d.name;
            }
        }
    }
}

TEST(CarveDepth, RefinedGroovesAndBumpsOnTheSphereFollowTheTool) {
    // placement.refine_levels = 2 holds the 10 % on fresh clay too. Measured (stop 47,
    // with the refinement's own fit): carves 0.95..1.06, adds 0.98..1.03; without that fit
    // diagonal grooves at 20 % were up to 1.12 deep (sizes 3-4). 24 s in a Release build; under
    // the sanitizers (ten times slower) only the diagonal with sizes 2 and 4, which still runs
    // every path of the refinement (one level and two).
#if defined(__SANITIZE_ADDRESS__)
    const std::vector<Direction> dirs{directions()[1]};
    const std::vector<int> sizes{2, 4};
#else
    const std::vector<Direction> dirs = directions();
    const std::vector<int> sizes{1, 2, 3, 4, 5, 6, 7};
#endif
    for (const Direction& d : dirs) {
        for (int k : sizes) {
            for (double pen : {0.2, 0.6, 1.0, 1.4}) {
                const Stats carve = sphereStroke(ToolOp::Carve, k, pen, d, PlacementMode::Swept, 2);
                EXPECT_GE(carve.min, 0.9) << "carve size " << k << " pen " << pen << " " << d.name;
                EXPECT_LE(carve.max, 1.1) << "carve size " << k << " pen " << pen << " " << d.name;
                EXPECT_LE(carve.max - carve.min, pen >= 0.6 ? 0.1 : 0.15)
                    << "carve size " << k << " pen " << pen << " " << d.name;
                const Stats add = sphereStroke(ToolOp::Add, k, pen, d, PlacementMode::Swept, 2);
                EXPECT_GE(add.min, 0.9) << "add size " << k << " pen " << pen << " " << d.name;
                EXPECT_LE(add.max, 1.1) << "add size " << k << " pen " << pen << " " << d.name;
                EXPECT_LE(add.max - add.min, 0.1)
                    << "add size " << k << " pen " << pen << " " << d.name;
            }
        }
    }
}

TEST(CarveDepth, GroovesAndBumpsOnClayOfStrokesFollowTheTool) {
    const auto clay = makeClay();
    for (double angle : {90.0, 30.0}) {
        for (int k = 1; k <= 7; ++k) {
            // Measured 0.95..1.08 for sizes 1-5 from 60 % on, 0.93..1.04 for size 6 from 100 %
            // on. Size 6 at 60 % (0.84..1.09) and size 7 (0.76..1.18) are not held to it: their
            // lattices are coarser than the slab's undulation (docs/placement.md).
            for (double pen : {0.6, 1.0, 1.4}) {
                if (k > 6 || (k == 6 && pen < 1.0)) continue;
                const Stats carve = clayStroke(clay.get(), ToolOp::Carve, k, pen, angle);
                EXPECT_GE(carve.min, 0.9) << "carve size " << k << " pen " << pen << " " << angle;
                EXPECT_LE(carve.max, 1.1) << "carve size " << k << " pen " << pen << " " << angle;
            }
            // Shallow carves are short of the 10 %: where the undulating surface
            // leaves the tool's bottom the groove spills past its end (measured 0.94..1.16 for
            // sizes 1-3; 1.25..1.44 at most for sizes 4-7).
            if (k <= 3) {
                const Stats carve = clayStroke(clay.get(), ToolOp::Carve, k, 0.2, angle);
                EXPECT_GE(carve.min, 0.9) << "carve size " << k << " pen 0.2 " << angle;
                EXPECT_LE(carve.max, 1.2) << "carve size " << k << " pen 0.2 " << angle;
            }
            // Measured 0.95..1.06; size 7 at 140 % is 0.84..1.06.
            for (double pen : {0.2, 0.6, 1.0, 1.4}) {
                if (k == 7 && pen > 1.0) continue;
                const Stats add = clayStroke(clay.get(), ToolOp::Add, k, pen, angle);
                EXPECT_GE(add.min, 0.9) << "add size " << k << " pen " << pen << " " << angle;
                EXPECT_LE(add.max, 1.1) << "add size " << k << " pen " << pen << " " << angle;
            }
        }
    }
}

TEST(CarveDepth, OnAFinerLatticeCarvesOnClayFollowTheTool) {
    // The change a carve makes to worked clay has the clay's detail, finer than the tool's
    // lattice (docs/placement.md "Finer lattices"): with placement.finer_lattice_levels = 2 the
    // weights go on the lattice two levels down. The same clay (built as always), copied into a
    // sculpture with the setting. Measured at 20 %: sizes 4-6 0.94..1.13 (on the tool's lattice
    // 0.49..1.45); at 60 %: 0.98..1.07 (0.85..1.09). Not yet the 10 % at 20 %.
    const auto clay = makeClay();
    SculptConfig cfg = clay->config();
    cfg.finerLatticeLevels = 2;
    for (double angle : {90.0, 30.0})
        for (int k : {4, 5, 6})
            for (double pen : {0.2, 0.6}) {
                Sculpture finer(cfg);
                clay->store().forEach(
                    [&](const SkeletonEntry& e) { finer.store().set(e.level, e.coord, e.weight); });
                const Stats carve = clayStroke(&finer, ToolOp::Carve, k, pen, angle);
                EXPECT_GE(carve.min, 0.9) << "size " << k << " pen " << pen << " angle " << angle;
                EXPECT_LE(carve.max, pen < 0.5 ? 1.15 : 1.1)
                    << "size " << k << " pen " << pen << " angle " << angle;
            }
}

TEST(CarveDepth, RefinedCarvesOnClayOfStrokesFollowTheTool) {
    // placement.refine_levels = 2 (docs/placement.md "Refining strokes"): each stroke ends by
    // placing, two levels down, what its own lattice left between its targets and the clay.
    // The clay of strokes as a project at that setting builds it (its adds refined too).
    // Measured (stop 47, with the refinement's own fit): sizes 1-5 at 20 % 0.81..1.24 (sizes
    // 2-4 0.93..1.24), sizes 1-6 from 60 % on 0.89..1.08 (without the refinement, on clay built
    // without it: sizes 4-5 at 20 % 0.88..1.45, size 6 at 60 % 0.85..1.09). Not the issue's
    // 10 %; size 6 at 20 % (0.78..1.27) and size 7 below 140 % (0.66..1.55) are not held.
    // VSCULPT_ONLY_SIZE=k VSCULPT_PROBE_PRINT=1 prints size k's shallow grooves probe by probe.
    auto clay = makeClay(2);
    const int only =
        std::getenv("VSCULPT_ONLY_SIZE") ? std::atoi(std::getenv("VSCULPT_ONLY_SIZE")) : 0;
    for (double angle : {90.0, 30.0})
        for (int k = 1; k <= 6; ++k)
            for (double pen : {0.2, 0.6, 1.0, 1.4}) {
                if (only && (k != only || pen > 0.5)) continue;
                if (only) std::printf("size %d pen %.1f angle %.0f\n", k, pen, angle);
                if (k == 6 && pen < 0.5) continue;
                const Stats carve = clayStroke(clay.get(), ToolOp::Carve, k, pen, angle);
                EXPECT_GE(carve.min, pen < 0.5 ? 0.8 : 0.85)
                    << "size " << k << " pen " << pen << " angle " << angle;
                EXPECT_LE(carve.max, pen < 0.5 ? 1.3 : 1.15)
                    << "size " << k << " pen " << pen << " angle " << angle;
            }
}

// Along the ray from + t dir, t from tMin to tMax in steps: where the first solid span begins
// and where it ends (NAN where there is none, or it does not end).
std::pair<double, double> firstSolidSpan(FieldProbe& probe, const Vec3& from, const Vec3& dir,
                                         double tMin, double tMax, double step) {
    double begin = NAN;
    for (double t = tMin; t <= tMax; t += step) {
        const bool in = probe.value(from + t * dir) > 0;
        if (in && std::isnan(begin)) begin = t;
        if (!in && !std::isnan(begin)) return {begin, t};
    }
    return {begin, NAN};
}

// A carve straight down inside the initial sphere's side, leaving a wall w mm thick between
// the tool and the sphere's surface (found by a QA pass at stop 39: on the tool's lattice a
// size-7 carve removed a 16 mm wall whole, sizes 5-6 an 8 mm one; docs/placement.md "What
// remains", "Walls"). The carve's change reaches a support radius past the vertices it writes,
// and near the sphere's steep core that tail is large; the refinement places, on the finer
// lattice, what the tool's pass did beyond the tool, and gives it back. Both faces of the wall
// within a tenth of the tool's radius of the exact ones (measured, probed every 0.25 mm:
// within 0.25 mm for sizes 4-6, size 7's 4 mm wall 1.25 mm too thick on its inner face).
TEST(CarveDepth, ARefinedCarveKeepsTheWallBesideIt) {
    for (int k : {4, 5, 6, 7})
        for (double wall : {4.0, 8.0, 16.0}) {
            SculptConfig cfg;  // the default sphere, steep core included
            cfg.refineLevels = 2;
            Sculpture s(cfg);
            const double rho = 0.5 * s.levels().level(k).diameterMm;
            const double r = cfg.sphereRadiusMm;
            const double x = wall + rho - r;  // the tool's centre
            applyStroke(s, ToolOp::Carve, k,
                        std::vector<Vec3>{Vec3(x, 0, 0), Vec3(x, 0, 20), Vec3(x, 0, 45)});
            FieldProbe probe(s);
            std::ostringstream what;
            what << "size " << k << " wall " << wall;
            // Along x at z = 2: the sphere's surface, the wall, the tool's face, the hole.
            const double z = 2, step = 0.01 * rho;
            const double outer = -std::sqrt(r * r - z * z), inner = x - rho;
            const auto [outerFound, innerFound] =
                firstSolidSpan(probe, Vec3(0, 0, z), Vec3(1, 0, 0), outer - 0.5 * rho, x, step);
            ASSERT_FALSE(std::isnan(outerFound)) << what.str() << ": the wall is gone";
            EXPECT_NEAR(outerFound, outer, 0.1 * rho) << what.str();
            EXPECT_NEAR(innerFound, inner, 0.1 * rho) << what.str();
            // And past the inner face, the hole is empty all the way to the tool's centre.
            for (double t = inner + 0.1 * rho; t <= x; t += step)
                EXPECT_LT(probe.value(Vec3(t, 0, z)), 0) << what.str() << " at x " << t;
        }
}

// A size-5 carve down the axis of a size-6 column (found by a QA pass at stop 37): the column's
// wall, 3.75 mm between the tool (7.5 mm) and the column's face (11.25 mm), is carved through
// on the tool's lattice (nothing is left at z 60); refined, both faces within a tenth of the
// carving tool's radius (measured in 0.25 mm steps: 7.25..11.5).
TEST(CarveDepth, ARefinedCarveDownAColumnKeepsItsWall) {
    SculptConfig cfg;
    cfg.refineLevels = 2;
    Sculpture s(cfg);
    const double column = 0.5 * s.levels().level(6).diameterMm;
    const double rho = 0.5 * s.levels().level(5).diameterMm;
    applyStroke(s, ToolOp::Add, 6, std::vector<Vec3>{Vec3(0, 0, 40), Vec3(0, 0, 70)});
    applyStroke(s, ToolOp::Carve, 5, std::vector<Vec3>{Vec3(0, 0, 80), Vec3(0, 0, 50)});
    FieldProbe probe(s);
    for (double z : {55.0, 60.0, 65.0})
        for (const Vec3& dir : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0) / std::sqrt(2.0)}) {
            std::ostringstream what;
            what << "z " << z << " direction " << dir.x << " " << dir.y;
            const auto [inner, outer] =
                firstSolidSpan(probe, Vec3(0, 0, z), dir, 0, column + rho, 0.01 * rho);
            ASSERT_FALSE(std::isnan(inner)) << what.str() << ": the wall is gone";
            EXPECT_NEAR(inner, rho, 0.1 * rho) << what.str();
            EXPECT_NEAR(outer, column, 0.1 * rho) << what.str();
        }
}

// A carve plunged down the initial sphere's axis, from above it to its centre and to z 20:
// on the tool's lattice the hole's floor stops short (sizes 5-7 to the centre 0.93 / 0.58 /
// 0.59 of the tool's radius past the path's end, docs/placement.md "What remains", "Plunges
// down the normal"); refined, its floor is the tool's within 5 % (measured 0.99..1.01 in
// 0.25 mm steps) and the hole is open all the way up.
TEST(CarveDepth, ARefinedPlungeReachesTheToolsDepth) {
    for (int k : {4, 5, 6, 7})
        for (double end : {0.0, 20.0}) {
            SculptConfig cfg;
            cfg.refineLevels = 2;
            Sculpture s(cfg);
            const double rho = 0.5 * s.levels().level(k).diameterMm;
            applyStroke(s, ToolOp::Carve, k, std::vector<Vec3>{Vec3(0, 0, 55), Vec3(0, 0, end)});
            FieldProbe probe(s);
            std::ostringstream what;
            what << "size " << k << " to z " << end;
            double floor = NAN;
            for (double z = end; z >= end - 1.5 * rho; z -= 0.005 * rho)
                if (probe.value(Vec3(0, 0, z)) > 0) {
                    floor = z;
                    break;
                }
            ASSERT_FALSE(std::isnan(floor)) << what.str() << ": no floor";
            EXPECT_NEAR((end - floor) / rho, 1.0, 0.05) << what.str();
            for (double z = end; z <= 45; z += 0.05 * rho)
                EXPECT_LT(probe.value(Vec3(0, 0, z)), 0) << what.str() << " at z " << z;
        }
}

TEST(CarveDepth, ARefinedCarvesRefinementRunsOnAnotherThreadToTheSameBits) {
    // beginFinish() hands the refinement's samples out (they only read the sculpture) and
    // finish() writes them: the same bits as finish() alone, as applyStroke (a journal's
    // replay) gives, and undo walks back to the start.
    auto clay = makeClay();
    SculptConfig cfg = clay->config();
    cfg.refineLevels = 2;
    auto copy = [&] {
        auto s = std::make_unique<Sculpture>(cfg);
        clay->store().forEach(
            [&](const SkeletonEntry& e) { s->store().set(e.level, e.coord, e.weight); });
        return s;
    };
    auto weights = [](const Sculpture& s) {
        std::map<std::tuple<int, int, int, int>, float> w;
        s.store().forEach([&](const SkeletonEntry& e) {
            w[{e.level, e.coord.x, e.coord.y, e.coord.z}] = e.weight;
        });
        return w;
    };
    const auto start = weights(*clay);
    const auto path = linePath(Vec3(-30, 3, 14), Vec3(30, -4, 15), 1.5);
    auto a = copy();
    auto b = copy();
    StrokeBuilder sa(*a, ToolOp::Carve, 5);
    StrokeBuilder sb(*b, ToolOp::Carve, 5);
    for (auto* st : {&sa, &sb}) {
        st->holdBackChangesBelow(kInteractiveHoldBelow);
        for (const Vec3& p : path)
            st->addSample(p);
    }
    sa.finish();
    std::function<void()> work = sb.beginFinish();
    ASSERT_TRUE(work);
    const size_t writesBefore = weights(*b).size();
    const auto beforeWork = weights(*b);
    std::thread t(work);
    // The frame thread goes on reading while it runs.
    FieldProbe probe(*b);
    double sum = 0;
    for (int i = 0; i < 200; ++i)
        sum += probe.value(Vec3(-20 + 0.2 * i, 0, 12));
    t.join();
    EXPECT_TRUE(std::isfinite(sum));
    EXPECT_EQ(weights(*b), beforeWork) << "the refinement's samples wrote";
    EXPECT_EQ(weights(*b).size(), writesBefore);
    sb.finish();
    EXPECT_EQ(weights(*a), weights(*b));
    const auto ca = sa.takeChanges();
    const auto cb = sb.takeChanges();
    ASSERT_EQ(ca.size(), cb.size());
    int fine = 0;
    for (size_t i = 0; i < ca.size(); ++i) {
        EXPECT_EQ(ca[i].level, cb[i].level);
        EXPECT_EQ(ca[i].coord, cb[i].coord);
        EXPECT_EQ(ca[i].before, cb[i].before);
        EXPECT_EQ(ca[i].after, cb[i].after);
        fine += ca[i].level == 3;
    }
    EXPECT_GT(fine, 100) << "the refinement placed little on the lattice two levels down";
    revertChanges(*a, ca);
    EXPECT_EQ(weights(*a), start);
    // applyStroke (a journal's replay) gives the same bits too.
    auto c = copy();
    applyStroke(*c, ToolOp::Carve, 5, path);
    EXPECT_EQ(weights(*c), weights(*b));
}

TEST(CarveDepth, ADabHasTheToolsSize) {
    // Scale-free: every level gives the same numbers; two levels make sure. The issue's
    // tolerance, 5 %, in every one of 64 directions (the targets alone gave 0.935..0.979; the
    // fit aimed at the tool's surface in empty space gives 0.989..1.014).
    for (int k : {2, 6}) {
        const Stats st = dabRadius(k);
        EXPECT_NEAR(st.mean(), 1.0, 0.02) << "size " << k;
        EXPECT_GE(st.min, 0.95) << "size " << k;
        EXPECT_LE(st.max, 1.05) << "size " << k;
    }
    // A carve dab's pit in the initial sphere is not scale-free (the sphere has one size):
    // every size (size 7, the deepest, is the tightest: 0.952 with the sphere's steep core,
    // 0.959 without, 0.947 with a core of weight 1 and support 1.15 r).
    for (int k = 1; k <= kLevelCount; ++k) {
        const double pit = dabPit(k);
        EXPECT_GE(pit, 0.95) << "size " << k;
        EXPECT_LE(pit, 1.05) << "size " << k;
    }
}

// A stroke's ends are the tool's balls: from its first and its last sample, the surface lies
// one tool radius away in every direction of the cap (within the 5 %), at both ends
// alike. The targets alone left both caps 0.94 long; fitting only the first sample's left the
// end 0.94 and the start 1.02. Straight strokes in three directions, a sample every 0.25 rho.
TEST(CarveDepth, AStrokesEndsAreTheToolsBalls) {
    for (const Vec3& dir : {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0.83, 0.31, -0.46)}) {
        Sculpture s(emptyConfig(PlacementMode::Swept));
        const ToolLevel& tl = s.levels().level(4);
        const double rho = 0.5 * tl.diameterMm;
        const Vec3 d = glm::normalize(dir);
        const Vec3 o = Vec3(0.29, 0.41, -0.17) * tl.spacingMm;
        const Vec3 start = o - 4 * rho * d, end = o + 4 * rho * d;
        applyStroke(s, ToolOp::Add, 4, linePath(start, end, 0.25 * rho));
        FieldProbe probe(s);
        // Directions of the cap: along the stroke and up to 60 degrees off it.
        const Vec3 side = glm::normalize(glm::cross(d, Vec3(0.3, -0.5, 0.8)));
        const Vec3 up = glm::cross(d, side);
        Stats startCap, endCap;
        for (double polar : {0.0, 30.0, 60.0})
            for (int k = 0; k < (polar == 0 ? 1 : 8); ++k) {
                const double th = glm::radians(polar), ph = k * std::numbers::pi / 4;
                const Vec3 off = std::sin(th) * (std::cos(ph) * side + std::sin(ph) * up);
                const Vec3 ahead = std::cos(th) * d + off, behind = -std::cos(th) * d + off;
                endCap.add(firstCrossing(probe, end, ahead, 4 * rho, 0.02 * rho) / rho);
                startCap.add(firstCrossing(probe, start, behind, 4 * rho, 0.02 * rho) / rho);
            }
        for (const Stats* cap : {&startCap, &endCap}) {
            EXPECT_GE(cap->min, 0.95) << (cap == &endCap ? "end" : "start") << " " << dir.x;
            EXPECT_LE(cap->max, 1.05) << (cap == &endCap ? "end" : "start") << " " << dir.x;
        }
        EXPECT_NEAR(startCap.mean(), endCap.mean(), 0.02) << dir.x << " " << dir.y;
    }
}

TEST(CarveDepth, StraightStrokesAreSmooth) {
    // Local radius along a straight stroke within 5 % of D/2 in every direction (ripple and
    // direction bias together). The lattice, tool and support scale together, so one level
    // stands for all.
    for (const Vec3& d : rippleDirections()) {
        const Stats st = strokeRadius(4, d);
        EXPECT_GE(st.min, 0.95) << d.x << " " << d.y << " " << d.z;
        EXPECT_LE(st.max, 1.05) << d.x << " " << d.y << " " << d.z;
    }
}

// Many thin strokes (sizes 1-2, the sizes of zooms 4-5), each starting just inside the
// outermost clay in a random direction (the sphere, thicker strokes, earlier spines) and
// leaving it along the surface normal, as a sculptor pulls spines out of a body.
struct Forest {
    size_t components = 0;
    bool watertight = false;
    double minAxisField = 1e300;  // f along every spine's axis, from its start to its end
    std::vector<std::pair<Aabb, size_t>> pieces;  // each piece's box and corner count
};

Forest spineForest(unsigned seed) {
    SculptConfig cfg = emptyConfig(PlacementMode::Swept);
    cfg.sphereRadiusMm = 14;
    Sculpture s(cfg);
    applyStroke(s, ToolOp::Add, 5, linePath(Vec3(-8, 0, 10), Vec3(8, 4, 14), 1.0));
    applyStroke(s, ToolOp::Add, 4, linePath(Vec3(0, -10, -6), Vec3(6, -18, -10), 1.0));
    std::mt19937 rng(seed);
    std::normal_distribution<double> N(0, 1);
    std::uniform_real_distribution<double> U(0, 1);
    const double outer = 30;
    std::vector<std::pair<Vec3, Vec3>> axes;
    for (int i = 0; i < 120 && axes.size() < 60; ++i) {
        const int level = 1 + i % 2;
        const double rho = 0.5 * s.levels().level(level).diameterMm;
        const Vec3 u = glm::normalize(Vec3(N(rng), N(rng), N(rng)));
        FieldProbe probe(s);
        const double t = firstCrossing(probe, u * outer, -u, outer, 0.05);
        if (t >= outer) continue;
        const Vec3 surface = u * (outer - t);
        const FieldSample fs = probe.sample(surface);
        if (glm::length(fs.gradient) < 1e-9) continue;
        const Vec3 n = -glm::normalize(fs.gradient);  // outward
        const Vec3 start = surface - n * (0.3 + 0.6 * U(rng)) * rho;
        const Vec3 dir = glm::normalize(n + 0.6 * Vec3(N(rng), N(rng), N(rng)));
        const Vec3 end = start + dir * (3 + 6 * U(rng));
        if (glm::length(end) > 26) continue;
        applyStroke(s, ToolOp::Add, level, linePath(start, end, 0.3 * rho));
        axes.emplace_back(start, end);
    }
    EXPECT_GE(axes.size(), 50u);
    Forest out;
    FieldProbe probe(s);
    for (const auto& [a, b] : axes)
        for (int i = 0; i <= 100; ++i)
            out.minAxisField = std::min(out.minAxisField, probe.value(a + (b - a) * (i / 100.0)));
    GridRegion region;
    region.spacingMm = 0.7;
    region.n = 96;
    region.originCell = {-48, -48, -48};
    Polygonizer poly(s, region, 1e-3);
    poly.rebuildAll();
    const Mesh mesh = poly.mesh();
    const MeshTopology topo = analyzeTopology(mesh);
    out.components = topo.components;
    out.watertight = topo.watertight();
    // Union-find over the triangles' corners: where and how big each piece is.
    std::vector<uint32_t> parent(mesh.positions.size());
    for (uint32_t i = 0; i < parent.size(); ++i)
        parent[i] = i;
    auto find = [&](uint32_t x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    for (size_t t = 0; t < mesh.indices.size(); t += 3)
        for (int k = 1; k < 3; ++k)
            parent[find(mesh.indices[t + k])] = find(mesh.indices[t]);
    std::map<uint32_t, std::pair<Aabb, size_t>> pieces;
    for (uint32_t i : mesh.indices) {
        auto& pc = pieces[find(i)];
        pc.first.expand(mesh.positions[i]);
        ++pc.second;
    }
    for (const auto& [root, pc] : pieces)
        out.pieces.push_back(pc);
    return out;
}

// Chains of thin spines: each starts 0.4 of its radius behind the tip of the previous one, on
// its axis (inside the previous tip's nominal cap), and turns. Returns the number of pieces
// of the exported mesh (spacing 0.7 mm).
size_t spineChains(unsigned seed, int refineLevels = 0) {
    SculptConfig cfg = emptyConfig(PlacementMode::Swept);
    cfg.sphereRadiusMm = 10;
    cfg.refineLevels = refineLevels;
    Sculpture s(cfg);
    std::mt19937 rng(seed);
    std::normal_distribution<double> N(0, 1);
    std::uniform_real_distribution<double> U(0, 1);
    for (int chain = 0; chain < 12; ++chain) {
        Vec3 dir = glm::normalize(Vec3(N(rng), N(rng), N(rng)));
        Vec3 tip = dir * 9.0;  // inside the sphere
        for (int link = 0; link < 4; ++link) {
            const int level = 1 + (chain + link) % 2;
            const double rho = 0.5 * s.levels().level(level).diameterMm;
            const Vec3 start = tip - dir * (0.4 * rho);
            dir = glm::normalize(dir + 0.7 * Vec3(N(rng), N(rng), N(rng)));
            const Vec3 end = start + dir * (2 + 2 * U(rng));
            if (glm::length(end) > 26) break;
            applyStroke(s, ToolOp::Add, level, linePath(start, end, 0.3 * rho));
            tip = end;
        }
    }
    GridRegion region;
    region.spacingMm = 0.7;
    region.n = 96;
    region.originCell = {-48, -48, -48};
    Polygonizer poly(s, region, 1e-3);
    poly.rebuildAll();
    return analyzeTopology(poly.mesh()).components;
}

// A carve plunged straight down the surface's normal (found by QA: down the initial sphere's
// axis, sizes 3-6, a lid of clay floated in the hole's mouth, z 31-39 for size 5). There the
// pre-stroke normal runs along the stroke, and the control point of each vertex on the axis lay
// inside the tube, where the fit held the field at c. The hole must be open all the way down
// its axis and the clay one piece. (How deep such a plunge reaches is not held here: ending deep
// inside it stops short of the tool; docs/placement.md "What remains".)
TEST(CarveDepth, APlungeDownTheNormalLeavesAnOpenHole) {
    for (int k : {3, 5, 6, 7})
        for (double end : {0.0, 20.0})
            for (double off : {0.0, 1.0}) {  // on the sphere's axis, and beside it
                SculptConfig cfg;            // the default sphere, steep core included
                cfg.sphereRadiusMm = 40;
                Sculpture s(cfg);
                const double rho = 0.5 * s.levels().level(k).diameterMm;
                // As the QA's script drew it: one segment from above the surface.
                applyStroke(s, ToolOp::Carve, k,
                            std::vector<Vec3>{Vec3(off, 0, 55), Vec3(off, 0, end)});
                FieldProbe probe(s);
                std::ostringstream what;
                what << "size " << k << " to z " << end << " off " << off;
                double worst = -1e300;
                for (double z = end; z <= 42; z += 0.05 * rho)
                    worst = std::max(worst, probe.value(Vec3(off, 0, z)));
                EXPECT_LT(worst, 0) << what.str();
                if (end != 0) continue;  // one mesh per size and side is enough
                GridRegion region;
                region.spacingMm = 0.25 * rho;
                region.n = 16 * int(std::ceil(100 / region.spacingMm / 16));
                const int64_t half = region.n / 2;
                region.originCell = {-half, -half, -half};
                Polygonizer poly(s, region, 1e-2);
                poly.rebuildAll();
                EXPECT_EQ(analyzeTopology(poly.mesh()).components, 1u) << what.str();
            }
}

TEST(CarveDepth, ChainsOfSpinesStayInOnePiece) {
    for (unsigned seed : {3u, 4u, 5u, 6u})
        EXPECT_EQ(spineChains(seed), 1u) << "seed " << seed;
}

// The same at refine_levels 2, where the spines' sizes 1 and 2 have fewer than two levels below
// them: size 2 is refined one level down, size 1 not at all. (Before the refinement had its own
// fit, refined one level down, size 2 left seed 3 in two pieces.)
TEST(CarveDepth, RefinedChainsOfSpinesStayInOnePiece) {
    for (unsigned seed : {3u, 4u, 5u, 6u})
        EXPECT_EQ(spineChains(seed, 2), 1u) << "seed " << seed;
}

// Every spine joins the clay it starts in: material all along its axis, and one piece. Seed
// 14 is the exception that remains (docs/placement.md): the exported mesh has one extra speck
// of about 1 mm, 0.5 mm above the sphere, where the tails of several nearby spines add up in
// the sphere's very flat field (0.05 per mm); every spine there is attached.
// The first strokes of examples/worked-detail.vsc: an add, a carve that tunnels just under
// the sphere's surface, and an add over that tunnel. The add must fill its tool. Inside the
// worked clay the pre-stroke field is flat (gradient 0.02-0.03 per mm), and the vertex's depth
// read at its control point, across the tunnel, put vertices of the empty tunnel inside
// material: the add left 65 % of its change undone (docs/placement.md "Each stroke of a
// worked detail"). The vertex's own field says which side of the old surface it is on.
TEST(CarveDepth, AnAddOverACarvedTunnelFillsItsTool) {
    Sculpture s(SculptConfig{});
    const int level = 4;
    const double rho = 0.5 * s.levels().level(level).diameterMm;
    applyStroke(s, ToolOp::Add, level, std::vector<Vec3>{{-4, -40, -2}, {0, -44, 0}, {4, -40, 2}});
    applyStroke(s, ToolOp::Add, level,
                std::vector<Vec3>{{-5.93, -41.48, -3.22},
                                  {-3.49, -41.78, -2.66},
                                  {-1.06, -42.08, -2.09},
                                  {1.38, -41.78, -1.53},
                                  {3.81, -41.48, -0.97}});
    applyStroke(s, ToolOp::Carve, level,
                std::vector<Vec3>{{0.33, -38.22, -5.80},
                                  {0.27, -38.52, -3.31},
                                  {0.22, -38.82, -0.81},
                                  {0.16, -38.52, 1.69},
                                  {0.10, -38.22, 4.19}});
    const std::vector<Vec3> add{{-7.57, -38.28, -1.80},
                                {-5.17, -38.58, -1.10},
                                {-2.78, -38.88, -0.40},
                                {-0.38, -38.58, 0.30},
                                {2.02, -38.28, 1.01}};
    std::vector<Vec3> empty;  // grid points inside the add's tool that are not clay before it
    {
        FieldProbe probe(s);
        for (double x = -13; x <= 8; x += 0.5)
            for (double y = -45; y <= -32; y += 0.5)
                for (double z = -8; z <= 7; z += 0.5) {
                    const Vec3 p(x, y, z);
                    double d = 1e9;
                    for (size_t i = 1; i < add.size(); ++i)
                        d = std::min(d, distanceToSegment(p, add[i - 1], add[i]));
                    if (d < rho && probe.value(p) <= 0) empty.push_back(p);
                }
    }
    ASSERT_GT(empty.size(), 2000u);  // the tunnel and the air over it
    applyStroke(s, ToolOp::Add, level, add);
    FieldProbe probe(s);
    size_t filled = 0;
    for (const Vec3& p : empty)
        filled += probe.value(p) > 0;
    const double missed = 1 - double(filled) / double(empty.size());
    EXPECT_LT(missed, 0.2);  // measured 0.12 (0.65 when the depth reading could flip sides)
}

TEST(CarveDepth, SpinesStartingInsideClayJoinIt) {
    // Seeds 4, 35 and 38 trapped a void between the spines and the one-skeleton sphere's flat
    // field; with its steep core (initial_sphere.core_weight) only seed 14's remains, of seeds
    // 1-40 (CarveDepth.PrintSpineSeeds).
    for (unsigned seed : {4u, 13u, 14u, 15u, 35u, 38u}) {
        const Forest f = spineForest(seed);
        EXPECT_GT(f.minAxisField, 0.0) << "seed " << seed;
        EXPECT_TRUE(f.watertight) << "seed " << seed;
        if (seed == 14) {
            EXPECT_LE(f.components, 2u);
            for (const auto& [box, corners] : f.pieces)
                if (corners < 1000) {
                    const Vec3 size = box.max - box.min;
                    EXPECT_LT(std::max({size.x, size.y, size.z}), 2.0) << "seed " << seed;
                }
        } else {
            EXPECT_EQ(f.components, 1u) << "seed " << seed;
        }
        if (printTables())
            for (const auto& [box, corners] : f.pieces)
                std::printf("seed %u piece: %zu corners, box (%.2f %.2f %.2f)..(%.2f %.2f %.2f)\n",
                            seed, corners, box.min.x, box.min.y, box.min.z, box.max.x, box.max.y,
                            box.max.z);
    }
}

// The spine forest of SpinesStartingInsideClayJoinIt over seeds 1..N (VSCULPT_SPINE_SEEDS=N):
// how often a forest is more than one piece (docs/placement.md, "What remains").
TEST(CarveDepth, PrintSpineSeeds) {
    const char* n = std::getenv("VSCULPT_SPINE_SEEDS");
    if (!n) GTEST_SKIP() << "set VSCULPT_SPINE_SEEDS=N";
    int bad = 0;
    for (unsigned seed = 1; seed <= unsigned(std::atoi(n)); ++seed) {
        const Forest f = spineForest(seed);
        if (f.components != 1 || !f.watertight || f.minAxisField <= 0) ++bad;
        std::printf("seed %u: %zu components, watertight %d, min axis field %.4f\n", seed,
                    size_t(f.components), int(f.watertight), f.minAxisField);
    }
    std::printf("%d seeds with more than one piece or a detached spine\n", bad);
}

TEST(CarveDepth, PrintSpill) {
    if (!printTables()) GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    Sculpture s(emptyConfig(PlacementMode::Swept));
    const int k = 4;
    const ToolLevel& tl = s.levels().level(k);
    const double rho = 0.5 * tl.diameterMm;
    const Vec3 d = glm::normalize(Vec3(0.83, 0.31, -0.46));
    applyStroke(s, ToolOp::Add, k, linePath(-d * 40.0, d * 40.0, 0.25 * rho));
    FieldProbe probe(s);
    const Vec3 e1 = glm::normalize(glm::cross(d, Vec3(0, 0, 1))), e2 = glm::cross(d, e1);
    std::printf(
        "\nspill: raw field of a tube at distance l from its axis (max over 64 angles x 8 "
        "offsets)\n");
    for (double l : {1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 3.0}) {
        double mx = 0;
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 64; ++i) {
                const double th = 2 * std::numbers::pi * i / 64;
                const Vec3 p = d * (tl.spacingMm * j / 4.0) +
                               (std::cos(th) * e1 + std::sin(th) * e2) * (l * rho);
                mx = std::max(mx, probe.rawSum(p));
            }
        std::printf("l = %.2f rho: %.4f\n", l, mx);
    }
}

// Targets come from the pre-stroke field and the path's closest approach, and weights are a
// fixed function of the final targets: the same straight stroke sampled densely or sparsely
// places the same skeletons, on fresh clay and over earlier strokes, adding and carving.
TEST(CarveDepth, SampleSpacingDoesNotMatter) {
    for (ToolOp op : {ToolOp::Add, ToolOp::Carve}) {
        SculptConfig cfg = emptyConfig(PlacementMode::Swept);
        cfg.sphereRadiusMm = 40;
        Sculpture dense(cfg), sparse(cfg);
        for (Sculpture* s : {&dense, &sparse})
            applyStroke(*s, ToolOp::Add, 5, linePath(Vec3(-30, -5, 35), Vec3(30, 5, 40), 2.0));
        const double D = dense.levels().level(3).diameterMm;
        const Vec3 a(-25, 8, 41), b(25, -6, 38);
        applyStroke(dense, op, 3, linePath(a, b, 0.1 * D));
        applyStroke(sparse, op, 3, linePath(a, b, 0.9 * D));
        ASSERT_EQ(dense.store().vertexCount(), sparse.store().vertexCount()) << toString(op);
        dense.store().forEach([&](const SkeletonEntry& e) {
            const auto w = sparse.store().get(e.level, e.coord);
            ASSERT_TRUE(w.has_value());
            EXPECT_NEAR(*w, e.weight, 1e-5) << toString(op);
        });
    }
}
