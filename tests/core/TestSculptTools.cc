// SPDX-License-Identifier: MIT
// The smooth tool and mirror symmetry (issue #13): exact symmetry, undo, sample-spacing
// independence, smoothing that reduces surface variation without changing the volume.
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/KeepSmoothedVolume.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <thread>
#include <tuple>
#include <vector>

using namespace vsculpt::core;

namespace {

std::vector<Vec3> path(std::initializer_list<Vec3> points) {
    return points;
}

// Every lattice weight of the sculpture, for exact comparisons.
std::map<std::tuple<int, int, int, int>, float> weights(const Sculpture& s) {
    std::map<std::tuple<int, int, int, int>, float> w;
    s.store().forEach([&](const SkeletonEntry& e) {
        w[{e.level, e.coord.x, e.coord.y, e.coord.z}] = e.weight;
    });
    return w;
}

// Largest |f(p) - f(mirror(p))| over random points around the sculpture.
double mirrorDefect(const Sculpture& s, MirrorAxis axis, int n = 4000) {
    FieldProbe f(s);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-70, 70);
    double worst = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3 p(U(rng), U(rng), U(rng));
        worst = std::max(worst, std::abs(f.value(p) - f.value(mirrored(p, axis))));
    }
    return worst;
}

class Mirror : public ::testing::TestWithParam<MirrorAxis> {};

TEST_P(Mirror, StrokesAreAppliedMirroredAndTheFieldIsMirrorEqual) {
    const MirrorAxis axis = GetParam();
    SculptConfig cfg;
    Sculpture s(cfg);
    // Off the plane, across the plane, a carve and a smooth pass: every operation.
    applyStroke(s, ToolOp::Add, 5, path({{18, -30, 22}, {30, -18, 30}, {36, 4, 26}}), nullptr,
                axis);
    applyStroke(s, ToolOp::Add, 4, path({{-12, -41, 6}, {3, -42, 9}, {14, -41, 12}}), nullptr,
                axis);
    applyStroke(s, ToolOp::Carve, 4, path({{10, -38, -6}, {24, -30, -12}, {37, -6, -14}}), nullptr,
                axis);
    applyStroke(s, ToolOp::Smooth, 5, path({{15, -36, 10}, {30, -22, 18}}), nullptr, axis);
    EXPECT_LE(mirrorDefect(s, axis), 1e-6);
    // The mirrored half is really there: clay at a stroke point and at its mirror image.
    FieldProbe f(s);
    const Vec3 onStroke(30, -18, 30);
    EXPECT_GT(f.value(onStroke), 0);
    EXPECT_GT(f.value(mirrored(onStroke, axis)), 0);
}

TEST_P(Mirror, WithoutItTheSameStrokesAreNotSymmetric) {
    // The check above can fail: one-sided strokes break the sphere's symmetry by far.
    SculptConfig cfg;
    Sculpture s(cfg);
    applyStroke(s, ToolOp::Add, 5, path({{18, -30, 22}, {30, -18, 30}, {36, 4, 26}}));
    EXPECT_GT(mirrorDefect(s, GetParam()), 0.1);
}

TEST_P(Mirror, OneUndoRemovesBothHalves) {
    SculptConfig cfg;
    Sculpture s(cfg);
    const auto start = weights(s);
    std::vector<SkeletonChange> changes;
    applyStroke(s, ToolOp::Add, 5, path({{18, -30, 22}, {36, 4, 26}}), &changes, GetParam());
    EXPECT_GT(weights(s).size(), start.size());
    revertChanges(s, changes);
    EXPECT_EQ(weights(s), start);
    reapplyChanges(s, changes);
    EXPECT_LE(mirrorDefect(s, GetParam()), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Planes, Mirror,
                         ::testing::Values(MirrorAxis::X, MirrorAxis::Y, MirrorAxis::Z));

TEST(Mirror, EveryPlacementModeKeepsTheSymmetry) {
    for (PlacementMode mode : {PlacementMode::Thesis, PlacementMode::Swept}) {
        SculptConfig cfg;
        cfg.placement = mode;
        Sculpture s(cfg);
        applyStroke(s, ToolOp::Add, 5, path({{18, -30, 22}, {30, -18, 30}, {36, 4, 26}}), nullptr,
                    MirrorAxis::X);
        applyStroke(s, ToolOp::Carve, 4, path({{-12, -41, 6}, {3, -42, 9}, {14, -41, 12}}), nullptr,
                    MirrorAxis::X);
        EXPECT_LE(mirrorDefect(s, MirrorAxis::X), 1e-6) << toString(mode);
        FieldProbe f(s);
        EXPECT_GT(f.value(Vec3(-30, -18, 30)), 0) << toString(mode);  // the mirrored add
    }
}

TEST(Mirror, RefinedStrokesKeepTheSymmetry) {
    // placement.refine_levels: the refinement's lattice is symmetric about the planes too,
    // and it places the mirrored residual with the stroke's.
    SculptConfig cfg;
    cfg.refineLevels = 2;
    Sculpture s(cfg);
    std::vector<SkeletonChange> changes;
    applyStroke(s, ToolOp::Add, 5, path({{18, -30, 22}, {30, -18, 30}, {36, 4, 26}}), &changes,
                MirrorAxis::X);
    applyStroke(s, ToolOp::Carve, 4, path({{-12, -41, 6}, {3, -42, 9}, {14, -41, 12}}), &changes,
                MirrorAxis::X);
    EXPECT_LE(mirrorDefect(s, MirrorAxis::X), 1e-6);
    int fine[2] = {0, 0};  // the add's (level 3) and the carve's (level 2)
    for (const SkeletonChange& c : changes)
        if (c.level == 3 || c.level == 2) ++fine[c.level == 2];
    EXPECT_GT(fine[0], 0) << "the add was not refined";
    EXPECT_GT(fine[1], 0) << "the carve was not refined";
}

// A mirrored stroke beside the plane is the stroke and its image, not a trench or ridge
// joining them (found by QA: two eye sockets 16 mm apart, mirrored, joined across the nose
// 5.7 mm deep where two separate strokes left 1.8 mm: a vertex on the plane aimed at the
// midpoint of its two feet, a tool that is not there). The surface on the plane, between the
// two grooves or bumps, is where two separate strokes put it, to a tenth of the tool radius.
TEST(Mirror, AStrokeBesideThePlaneIsTheStrokeAndItsImageNotOneBetween) {
    for (ToolOp op : {ToolOp::Carve, ToolOp::Add}) {
        SCOPED_TRACE(toString(op));
        SculptConfig cfg;  // swept placement, the default sphere of radius 40
        Sculpture mirrored(cfg), separate(cfg);
        const auto stroke = path({{7, -38.923, -6}, {8, -39.192, 0}, {7, -38.923, 6}});
        const auto image = path({{-7, -38.923, -6}, {-8, -39.192, 0}, {-7, -38.923, 6}});
        applyStroke(mirrored, op, 4, stroke, nullptr, MirrorAxis::X);
        applyStroke(separate, op, 4, stroke);
        applyStroke(separate, op, 4, image);
        const double rho = 0.5 * mirrored.levels().level(4).diameterMm;
        // The surface along -y through (x, 0) on and near the plane.
        auto surfaceY = [](const Sculpture& s, double x) {
            FieldProbe f(s);
            double lo = -60, hi = -20;  // outside, inside
            for (int i = 0; i < 60; ++i) {
                const double mid = 0.5 * (lo + hi);
                (f.value(Vec3(x, mid, 0)) > 0 ? hi : lo) = mid;
            }
            return 0.5 * (lo + hi);
        };
        for (double x : {0.0, 2.0, 4.0})
            EXPECT_NEAR(surfaceY(mirrored, x), surfaceY(separate, x), 0.1 * rho) << "x = " << x;
        EXPECT_LE(mirrorDefect(mirrored, MirrorAxis::X), 1e-6);
    }
}

// In empty space an add's caps aim at the tool's ball (docs/placement.md "In empty space"):
// mirrored dabs and strokes, the two halves overlapping across the plane, stay exactly
// symmetric, and the mirrored dab has the tool's size too.
TEST(Mirror, CapsInEmptySpaceStaySymmetric) {
    SculptConfig cfg;
    cfg.sphereRadiusMm = 0;
    Sculpture s(cfg);
    const double rho = 0.5 * s.levels().level(4).diameterMm;
    applyStroke(s, ToolOp::Add, 4, path({{0.3 * rho, 0.2, 0.1}}), nullptr, MirrorAxis::X);
    applyStroke(s, ToolOp::Add, 3, path({{-9, 20, 3}, {4, 24, 5}, {12, 30, 2}}), nullptr,
                MirrorAxis::X);
    applyStroke(s, ToolOp::Add, 5, path({{20, -25, 0}, {35, -30, 8}}), nullptr, MirrorAxis::X);
    EXPECT_LE(mirrorDefect(s, MirrorAxis::X), 1e-6);
    // The dab's far side, away from the plane: one tool radius from its centre (5 %).
    FieldProbe f(s);
    EXPECT_GT(f.value(Vec3((0.3 + 0.95) * rho, 0.2, 0.1)), 0);
    EXPECT_LT(f.value(Vec3((0.3 + 1.05) * rho, 0.2, 0.1)), 0);
    EXPECT_GT(f.value(Vec3(-(0.3 + 0.95) * rho, 0.2, 0.1)), 0);
    EXPECT_LT(f.value(Vec3(-(0.3 + 1.05) * rho, 0.2, 0.1)), 0);
}

TEST(Mirror, TheMeshIsMirrorSymmetric) {
    SculptConfig cfg;
    Sculpture s(cfg);
    applyStroke(s, ToolOp::Add, 5, path({{18, -30, 22}, {30, -18, 30}, {36, 4, 26}}), nullptr,
                MirrorAxis::X);
    applyStroke(s, ToolOp::Carve, 5, path({{10, -38, -6}, {37, -6, -14}}), nullptr, MirrorAxis::X);
    Polygonizer poly(s, zoomRegion(cfg, s.levels(), 1, Vec3(0)), PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    const Mesh mesh = poly.mesh();
    ASSERT_GT(mesh.triangleCount(), 1000u);
    // Every vertex's mirror image lies on the surface exactly where the vertex does.
    FieldProbe f(s);
    double worst = 0;
    for (const Vec3& v : mesh.positions)
        worst = std::max(worst, std::abs(f.value(v) - f.value(mirrored(v, MirrorAxis::X))));
    EXPECT_LE(worst, 1e-6);
    // Both halves have the same surface area and extent (the tetrahedral split of the grid
    // is not itself mirror-symmetric, so triangles differ; the surface does not).
    double left = 0, right = 0;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3 a = mesh.positions[mesh.indices[3 * t]],
                   b = mesh.positions[mesh.indices[3 * t + 1]],
                   c = mesh.positions[mesh.indices[3 * t + 2]];
        const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
        ((a.x + b.x + c.x) > 0 ? right : left) += area;
    }
    EXPECT_NEAR(left / right, 1.0, 0.01);
    const Aabb box = meshBounds(mesh);
    EXPECT_NEAR(box.min.x, -box.max.x, 0.1);
}

// ------------------------------------------------------------------------------ smooth

// Radius of the iso-surface along `dir` from the origin (the sphere's centre).
double radiusAlong(FieldProbe& f, const Vec3& dir) {
    double lo = 20, hi = 70;
    for (int i = 0; i < 50; ++i) {
        const double m = 0.5 * (lo + hi);
        (f.value(dir * m) > 0 ? lo : hi) = m;
    }
    return lo;
}

// Standard deviation of the surface radius over a patch of the sphere's front (-y).
double roughness(const Sculpture& s) {
    FieldProbe f(s);
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int i = -12; i <= 12; ++i)
        for (int j = -12; j <= 12; ++j) {
            const double r = radiusAlong(f, glm::normalize(Vec3(i * 0.02, -1, j * 0.02)));
            sum += r;
            sum2 += r * r;
            ++n;
        }
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

double volume(const Sculpture& s) {
    Polygonizer poly(s, zoomRegion(s.config(), s.levels(), 1, Vec3(0)),
                     PolygonizerConfig{}.rootTolerance);
    poly.rebuildAll();
    return meshVolume(poly.mesh());
}

// A patch of small dabs and pits on the sphere's front: noise a sculptor smooths away.
void roughenPatch(Sculpture& s) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-12, 12);
    for (int k = 0; k < 40; ++k)
        applyStroke(s, ToolOp::Add, 2, path({{U(rng), -40.5, U(rng)}}));
    for (int k = 0; k < 15; ++k)
        applyStroke(s, ToolOp::Carve, 2, path({{U(rng), -41, U(rng)}}));
}

std::vector<Vec3> zigzagOverPatch() {
    std::vector<Vec3> zig;
    for (int row = -3; row <= 3; ++row) {
        zig.push_back(Vec3(-16, -40, row * 4.0));
        zig.push_back(Vec3(16, -40, row * 4.0 + 2));
    }
    return zig;
}

TEST(Smooth, ReducesSurfaceVariationWithoutChangingTheVolume) {
    // Measured: free -20 %, -20 %; swept -20 %, -23 %, volume within 0.05 % (the plain
    // diffusion, before the smooth tool kept the volume under it: free -26 %, -24 %; swept
    // -17 %, -23 %, volume within 0.1 %).
    for (PlacementMode mode : {PlacementMode::Free, PlacementMode::Swept}) {
        SculptConfig cfg;
        cfg.placement = mode;
        Sculpture s(cfg);
        roughenPatch(s);
        const double rough0 = roughness(s), volume0 = volume(s);
        ASSERT_GT(rough0, 1.0) << toString(mode);  // the patch is noisy (mm)
        double previous = rough0;
        for (int pass = 1; pass <= 2; ++pass) {
            applyStroke(s, ToolOp::Smooth, 3, zigzagOverPatch());
            const double rough = roughness(s), v = volume(s);
            if (std::getenv("VSCULPT_PRINT_SMOOTH"))
                std::printf("%s pass %d: roughness %.3f -> %.3f (%+.1f %%), volume %+.3f %%\n",
                            toString(mode), pass, previous, rough, 100 * (rough / previous - 1),
                            100 * (v / volume0 - 1));
            EXPECT_LT(rough, 0.85 * previous) << toString(mode) << " pass " << pass;
            EXPECT_LE(std::abs(v - volume0) / volume0, 0.02) << toString(mode) << " pass " << pass;
            previous = rough;
        }
    }
}

// The clay's volume inside `box`, counted on a grid of `step` (mm^3).
double volumeIn(const Sculpture& s, const Aabb& box, double step) {
    std::vector<Vec3> points;
    for (double z = box.min.z + 0.5 * step; z < box.max.z; z += step)
        for (double y = box.min.y + 0.5 * step; y < box.max.y; y += step)
            for (double x = box.min.x + 0.5 * step; x < box.max.x; x += step)
                points.push_back(Vec3(x, y, z));
    std::vector<double> values(points.size());
    evalFieldBatch(s, points, values);
    return double(std::count_if(values.begin(), values.end(), [](double f) { return f > 0; })) *
           step * step * step;
}

// Found by QA (stop 39): four size-4 smooth passes along a size-3 arm took 23 % of it a pass
// and left it in pieces (radius 3.34 -> 2.93 -> 2.43 -> 1.71 mm, then gone): diffusion keeps
// the weights' sum, not the volume of a feature a few lattice spacings thick. The issue asks
// for at most 2 % a pass; the arm stays whole and keeps its radius.
TEST(Smooth, AThinArmKeepsItsVolumeAndStaysWhole) {
    const auto arm = path({{36, 0, 0}, {50, 0, 0}, {72, 0, 0}});
    const Aabb box{Vec3(38, -8, -8), Vec3(80, 8, 8)};
    auto radiusAt = [](const Sculpture& s, double x) {
        FieldProbe f(s);
        double lo = 0, hi = 8;  // inside, outside
        for (int i = 0; i < 40; ++i) {
            const double m = 0.5 * (lo + hi);
            (f.value(Vec3(x, 0, m)) > 0 ? lo : hi) = m;
        }
        return lo;
    };
    for (bool keep : {true, false}) {
        SCOPED_TRACE(keep ? "keeps volume" : "plain diffusion");
        SculptConfig cfg;
        cfg.smoothKeepsVolume = keep;
        Sculpture sphere(cfg), s(cfg);
        applyStroke(s, ToolOp::Add, 3, arm);
        const double sphereOnly = volumeIn(sphere, box, 0.3);
        const double volume0 = volumeIn(s, box, 0.3) - sphereOnly;
        const double radius0 = radiusAt(s, 60);
        ASSERT_GT(volume0, 900);  // the arm: about pi 3.3^2 x 36 mm
        double previous = volume0;
        for (int pass = 1; pass <= 4; ++pass) {
            applyStroke(s, ToolOp::Smooth, 4, arm);
            const double v = volumeIn(s, box, 0.3) - sphereOnly;
            if (std::getenv("VSCULPT_PRINT_SMOOTH"))
                std::printf(
                    "arm, %s, pass %d: volume %.1f -> %.1f mm^3 (%+.2f %%), radius at x 60 "
                    "%.2f mm\n",
                    keep ? "keeping" : "plain", pass, previous, v, 100 * (v / previous - 1),
                    radiusAt(s, 60));
            if (keep) {
                EXPECT_LE(std::abs(v / previous - 1), 0.02) << "pass " << pass;
            } else if (pass == 1) {
                EXPECT_LT(v, 0.9 * previous);  // what the plain diffusion does: the check can fail
            }
            previous = v;
        }
        if (!keep) continue;
        EXPECT_NEAR(radiusAt(s, 60), radius0, 0.1 * radius0);
        // Whole: clay all along the arm's axis out to its tip.
        FieldProbe f(s);
        for (double x = 38; x <= 74; x += 0.25)
            EXPECT_GT(f.value(Vec3(x, 0, 0)), 0) << "x = " << x;
    }
}

// The correction is the stroke's, made as it ends; each sample shows a preview of it, so the
// arm does not thin under the brush while the stroke goes on and come back when it ends.
TEST(Smooth, WhileTheStrokeGoesOnAThinArmKeepsItsVolume) {
    const Aabb box{Vec3(38, -8, -8), Vec3(80, 8, 8)};
    SculptConfig cfg;
    Sculpture sphere(cfg), s(cfg);
    applyStroke(s, ToolOp::Add, 3, path({{36, 0, 0}, {50, 0, 0}, {72, 0, 0}}));
    const double sphereOnly = volumeIn(sphere, box, 0.3);
    const double volume0 = volumeIn(s, box, 0.3) - sphereOnly;
    StrokeBuilder stroke(s, ToolOp::Smooth, 4);
    stroke.holdBackChangesBelow(kInteractiveHoldBelow);
    const double spacing = 0.25 * s.levels().level(4).diameterMm;  // as a hand moves it
    for (double x = 42; x <= 72; x += spacing) {
        stroke.addSample(Vec3(x, 0, 0));
        if (x < 50) continue;
        const double v = volumeIn(s, box, 0.3) - sphereOnly;
        if (std::getenv("VSCULPT_PRINT_SMOOTH"))
            std::printf("arm during the stroke, at x %.1f: %+.2f %%\n", x, 100 * (v / volume0 - 1));
        EXPECT_LE(std::abs(v / volume0 - 1), 0.05) << "at x = " << x;
    }
    stroke.finish();
    const double v = volumeIn(s, box, 0.3) - sphereOnly;
    EXPECT_LE(std::abs(v / volume0 - 1), 0.02);
    // The undo record walks back to the start through previews and correction alike.
    const std::vector<SkeletonChange> changes = stroke.takeChanges();
    revertChanges(s, changes);
    EXPECT_NEAR(volumeIn(s, box, 0.3) - sphereOnly, volume0, 1e-9);
}

// finish() in two parts (beginFinish): the estimate, run on another thread while this one
// reads the field as a frame would, writes nothing to the store and gives the same bits as
// finish() alone; a stroke with nothing to estimate hands out no work.
TEST(Smooth, ItsPenLiftEstimateRunsOnAnotherThreadToTheSameBits) {
    SculptConfig cfg;
    Sculpture a(cfg), b(cfg);
    for (Sculpture* s : {&a, &b}) {
        applyStroke(*s, ToolOp::Add, 3, path({{36, 0, 0}, {50, 0, 0}, {72, 0, 0}}));
        applyStroke(*s, ToolOp::Add, 1, path({{50, 3.3, 0}}));
    }
    auto smooth = [&](Sculpture& s) {
        auto stroke = std::make_unique<StrokeBuilder>(s, ToolOp::Smooth, 4);
        stroke->holdBackChangesBelow(kInteractiveHoldBelow);
        for (double x = 42; x <= 70; x += 2.5)
            stroke->addSample(Vec3(x, 0, 3.4));
        return stroke;
    };
    auto whole = smooth(a);
    whole->finish();
    auto split = smooth(b);
    const std::function<void()> estimate = split->beginFinish();
    ASSERT_TRUE(estimate);
    const uint64_t writes = b.store().writeCount();
    std::thread worker(estimate);
    FieldProbe frame(b);  // the frame thread reads the clay meanwhile
    double read = 0;
    for (int i = 0; i < 200; ++i)
        read += frame.value(Vec3(40 + 0.1 * i, 0, 3));
    worker.join();
    EXPECT_TRUE(std::isfinite(read));
    EXPECT_EQ(b.store().writeCount(), writes);  // the estimate only read
    split->finish();
    EXPECT_NE(split->volumeShift().shift, 0.0);
    EXPECT_EQ(split->volumeShift().shift, whole->volumeShift().shift);
    EXPECT_EQ(weights(a), weights(b));
    const std::vector<SkeletonChange> ca = whole->takeChanges(), cb = split->takeChanges();
    ASSERT_EQ(ca.size(), cb.size());
    for (size_t i = 0; i < ca.size(); ++i) {
        EXPECT_EQ(ca[i].coord, cb[i].coord);
        EXPECT_EQ(ca[i].before, cb[i].before);
        EXPECT_EQ(ca[i].after, cb[i].after);
    }
    // Undo walks back to the start through the split stroke's record too.
    Sculpture start(cfg);
    applyStroke(start, ToolOp::Add, 3, path({{36, 0, 0}, {50, 0, 0}, {72, 0, 0}}));
    applyStroke(start, ToolOp::Add, 1, path({{50, 3.3, 0}}));
    revertChanges(b, cb);
    EXPECT_EQ(weights(b), weights(start));
    // Adds, and smooth strokes that changed nothing, have no estimate to hand out.
    StrokeBuilder add(a, ToolOp::Add, 4);
    add.addSample(Vec3(0, 0, 45));
    EXPECT_FALSE(add.beginFinish());
    add.finish();
    StrokeBuilder nothing(a, ToolOp::Smooth, 4);
    nothing.addSample(Vec3(-30, -30, 0));
    EXPECT_FALSE(nothing.beginFinish());
    nothing.finish();
    EXPECT_TRUE(nothing.takeChanges().empty());
}

// A size-3 arm with size-1 dabs on it: the surface radius about the arm's axis, sampled
// over its middle (x 44..64 every 0.5 mm, 16 directions), as mean and standard deviation.
struct ArmSurface {
    double mean = 0, deviation = 0;
};
ArmSurface armSurface(const Sculpture& s) {
    FieldProbe f(s);
    double sum = 0, sum2 = 0;
    int n = 0;
    for (double x = 44; x <= 64; x += 0.5)
        for (int a = 0; a < 16; ++a) {
            const double t = a * 6.283185307179586 / 16;
            const Vec3 dir(0, std::cos(t), std::sin(t));
            double lo = 0, hi = 9;  // inside, outside
            for (int i = 0; i < 30; ++i) {
                const double m = 0.5 * (lo + hi);
                (f.value(Vec3(x, 0, 0) + dir * m) > 0 ? lo : hi) = m;
            }
            sum += lo;
            sum2 += lo * lo;
            ++n;
        }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean))};
}

void addBumpsToArm(Sculpture& s) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> angle(0, 6.283185307179586);
    for (double x = 42; x <= 68; x += 2) {
        const double a = angle(rng);
        applyStroke(s, ToolOp::Add, 1, path({{x, 3.3 * std::cos(a), 3.3 * std::sin(a)}}));
    }
}

// Found by QA (stop 40): with the correction as first made (every changed weight moved by the
// shift x |its own change|) smoothing a bumpy arm left it bumpier (s.d. of the radius 0.42 ->
// 0.48 mm in four passes): the volume went back where the diffusion had taken it, onto the
// bumps. Now the level carrying most of the change takes the correction: -7..-11 % a pass (-10..-12
// % when each weight moved by its own change, which opened voids inside worked clay).
TEST(Smooth, ABumpyArmComesOutSmootherAndKeepsItsVolume) {
    const auto arm = path({{36, 0, 0}, {50, 0, 0}, {72, 0, 0}});
    const Aabb box{Vec3(38, -10, -10), Vec3(80, 10, 10)};
    SculptConfig cfg;
    Sculpture sphere(cfg), s(cfg);
    applyStroke(s, ToolOp::Add, 3, arm);
    addBumpsToArm(s);
    const double sphereOnly = volumeIn(sphere, box, 0.3);
    const double volume0 = volumeIn(s, box, 0.3) - sphereOnly;
    const ArmSurface surface0 = armSurface(s);
    ASSERT_GT(surface0.deviation, 0.3);  // bumpy (mm)
    double previous = volume0;
    ArmSurface last = surface0;
    for (int pass = 1; pass <= 4; ++pass) {
        // A pass: four strokes along the arm with the tool's centre on its surface, as a
        // sculptor smooths (along the axis the bumps would sit at the brush's soft edge).
        for (int a = 0; a < 4; ++a) {
            const double t = a * 1.5707963267948966;
            const Vec3 onSurface(0, 3.4 * std::cos(t), 3.4 * std::sin(t));
            applyStroke(s, ToolOp::Smooth, 4,
                        path({Vec3(36, 0, 0) + onSurface, Vec3(72, 0, 0) + onSurface}));
        }
        const double v = volumeIn(s, box, 0.3) - sphereOnly;
        const ArmSurface now = armSurface(s);
        if (std::getenv("VSCULPT_PRINT_SMOOTH"))
            std::printf(
                "bumpy arm, pass %d: volume %+.2f %%, radius %.2f mm, deviation %.3f -> "
                "%.3f mm (%+.1f %%)\n",
                pass, 100 * (v / previous - 1), now.mean, last.deviation, now.deviation,
                100 * (now.deviation / last.deviation - 1));
        EXPECT_LE(std::abs(v / previous - 1), 0.02) << "pass " << pass;
        EXPECT_LT(now.deviation, 0.95 * last.deviation) << "pass " << pass;
        EXPECT_NEAR(now.mean, surface0.mean, 0.15) << "pass " << pass;  // mm
        previous = v;
        last = now;
    }
}

// The correction moves each weight of the carrying level by how much the diffusion changed the
// field at its vertex, not by its own change: a uniform change moves its weights by itself, but
// neighbouring changes of opposite sign (weights of adds and carves drawn together inside the
// clay, where the field hardly moves) move them far less. Moved by |their change|, repeated
// passes over the worked detail's nose lowered the field inside the sphere until a 434 mm^3
// void opened (docs/placement.md, "Smooth tool").
TEST(Smooth, ItsCorrectionMovesAWeightByTheFieldsChangeNotByItsOwn) {
    constexpr int level = 3;
    constexpr float d = 0.2f;
    auto centreMove = [&](bool alternating) {
        SculptConfig cfg;
        Sculpture s(cfg);
        std::vector<SkeletonChange> changes;
        for (int z = -3; z <= 3; ++z)
            for (int y = -3; y <= 3; ++y)
                for (int x = -3; x <= 3; ++x) {
                    const LatticeCoord c{x + 2, y, z};
                    const float w = alternating && (x + y + z) % 2 != 0 ? -d : d;
                    s.store().set(level, c, w);
                    changes.push_back({level, c, std::nullopt, w});
                }
        const VolumeKeepingShift keep = volumeKeepingShift(s, changes);
        for (size_t n = 0; n < changes.size(); ++n)
            if (changes[n].coord == LatticeCoord{2, 0, 0}) return keep.moves[n];
        ADD_FAILURE() << "no centre";
        return 0.0;
    };
    EXPECT_NEAR(centreMove(false), d, 1e-6);
    EXPECT_LT(centreMove(true), 0.5 * d);
}

// A stroke over few grid points is measured finer (kStrokeFinerWithinPoints): a size-7 smooth
// over the worked detail's level-4 nose took 4 000 points at 2.5 mm and misread the nose,
// which grew 11 % in three passes (4 % measured finer). Finer by 1.25 a step, to half the
// spacing at most, within the budget; a stroke that already fills it keeps its grid.
TEST(Smooth, AStrokeOverFewPointsIsMeasuredFiner) {
    constexpr int level = 4;
    SculptConfig cfg;
    Sculpture s(cfg);
    std::vector<SkeletonChange> changes;
    for (int x = 6; x <= 9; ++x) {  // a few changes on the sphere's surface (r 40, h 5 mm)
        s.store().set(level, {x, 0, 0}, 0.1f);
        changes.push_back({level, {x, 0, 0}, std::nullopt, 0.1f});
    }
    const double spacing = s.levels().level(level).spacingMm;
    const VolumeKeepingShift finer = volumeKeepingShift(s, changes);
    const VolumeKeepingShift asked = volumeKeepingShift(s, changes, kStrokeCellOverSpacing, 0);
    EXPECT_NEAR(asked.cellMm, kStrokeCellOverSpacing * spacing, 1e-12);
    EXPECT_LT(finer.cellMm, asked.cellMm / 1.9);  // three steps of 1.25
    EXPECT_GE(finer.cellMm, asked.cellMm / 2);
    EXPECT_GT(finer.points, 5 * asked.points);
    EXPECT_LE(finer.points, kStrokeFinerWithinPoints);
}

// The volume estimate runs over the cores (KeepSmoothedVolume.cpp); a journal must replay to
// the same weights on a machine with any number of them, so the estimate must come out bit for
// bit the same on one thread as on all (its sums added in a fixed order).
TEST(Smooth, ItsVolumeEstimateIsTheSameOnOneCoreAsOnAll) {
    SculptConfig cfg;
    Sculpture s(cfg);
    applyStroke(s, ToolOp::Add, 3, path({{36, 0, 0}, {50, 0, 0}, {72, 0, 0}}));
    addBumpsToArm(s);
    std::vector<SkeletonChange> changes;
    applyStroke(s, ToolOp::Smooth, 4, path({{36, 3.4, 0}, {72, 3.4, 0}}), &changes);
    ASSERT_FALSE(changes.empty());
    const VolumeKeepingShift onAll = volumeKeepingShift(s, changes);
    VolumeKeepingShift onOne;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        onOne = volumeKeepingShift(s, changes);
    }
    ASSERT_GT(onAll.points, 10000);  // enough points to be shared out
    auto bits = [](double v) {
        std::uint64_t b;
        std::memcpy(&b, &v, sizeof b);
        return b;
    };
    EXPECT_EQ(bits(onAll.volumeBefore), bits(onOne.volumeBefore));
    EXPECT_EQ(bits(onAll.volumeDiffused), bits(onOne.volumeDiffused));
    EXPECT_EQ(bits(onAll.shift), bits(onOne.shift));
    EXPECT_EQ(onAll.moves, onOne.moves);
}

// The same for a ridge on the sphere under a larger tool (QA: a size-5 ridge lost 29 % of its
// volume in four size-7 passes, nothing of it spread to its flanks).
TEST(Smooth, ARidgeUnderALargerToolKeepsItsVolume) {
    std::vector<Vec3> ridge;
    for (int i = -4; i <= 4; ++i) {
        const double a = i * 0.12;
        ridge.push_back(Vec3(40 * std::sin(a), -40 * std::cos(a), 0));
    }
    const Aabb box{Vec3(-40, -54, -18), Vec3(40, -22, 18)};
    SculptConfig cfg;
    Sculpture sphere(cfg), s(cfg);
    applyStroke(s, ToolOp::Add, 5, ridge);
    const double sphereOnly = volumeIn(sphere, box, 0.5);
    const double volume0 = volumeIn(s, box, 0.5) - sphereOnly;
    ASSERT_GT(volume0, 3000);
    double previous = volume0;
    for (int pass = 1; pass <= 4; ++pass) {
        applyStroke(s, ToolOp::Smooth, 7, ridge);
        const double v = volumeIn(s, box, 0.5) - sphereOnly;
        if (std::getenv("VSCULPT_PRINT_SMOOTH"))
            std::printf("ridge, pass %d: volume %.1f -> %.1f mm^3 (%+.2f %%)\n", pass, previous, v,
                        100 * (v / previous - 1));
        EXPECT_LE(std::abs(v / previous - 1), 0.02) << "pass " << pass;
        previous = v;
    }
}

// What a smooth stroke costs the frame thread: each sample (diffusion and, with the volume
// kept, its preview) and the end (the stroke's correction). A size-3 arm with 14 size-1 dabs
// on it (found slow by QA), smoothed with size 4 at a hand's sample spacing.
TEST(Smooth, PrintCosts) {
    if (!std::getenv("VSCULPT_PLACEMENT_TABLES")) GTEST_SKIP() << "set VSCULPT_PLACEMENT_TABLES=1";
    for (bool keep : {false, true}) {
        SculptConfig cfg;
        cfg.smoothKeepsVolume = keep;
        Sculpture s(cfg);
        applyStroke(s, ToolOp::Add, 3, path({{36, 0, 0}, {72, 0, 0}}));
        std::mt19937 rng(1);
        std::uniform_real_distribution<double> angle(0, 6.283185307179586);
        for (double x = 42; x <= 68; x += 2) {
            const double a = angle(rng);
            applyStroke(s, ToolOp::Add, 1, path({{x, 3.3 * std::cos(a), 3.3 * std::sin(a)}}));
        }
        for (int pass = 1; pass <= 2; ++pass) {
            StrokeBuilder stroke(s, ToolOp::Smooth, 4);
            stroke.holdBackChangesBelow(kInteractiveHoldBelow);
            std::vector<double> ms;
            const double spacing = 0.25 * s.levels().level(4).diameterMm;
            for (double x = 42; x <= 72; x += spacing) {
                const auto t0 = std::chrono::steady_clock::now();
                stroke.addSample(Vec3(x, 0, 0));
                ms.push_back(
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                        .count());
            }
            const auto t0 = std::chrono::steady_clock::now();
            stroke.finish();
            const double end =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
            std::sort(ms.begin(), ms.end());
            std::printf(
                "smooth %s, pass %d: %zu samples, median %.2f ms, max %.2f ms; finish %.2f "
                "ms (%d grid points, cell %.2f mm)\n",
                keep ? "keeping the volume" : "plain", pass, ms.size(), ms[ms.size() / 2],
                ms.back(), end, stroke.volumeShift().points, stroke.volumeShift().cellMm);
        }
    }
}

TEST(Smooth, SmoothClayAndEmptySpaceStayAsTheyAre) {
    SculptConfig cfg;
    Sculpture s(cfg);  // only the analytic initial sphere: no lattice weights to relax
    const EditResult r = applyStroke(s, ToolOp::Smooth, 5, zigzagOverPatch());
    EXPECT_EQ(r.changedVertices, 0);
    EXPECT_TRUE(weights(s).empty());
}

TEST(Smooth, DoesNotDependOnSampleSpacing) {
    SculptConfig cfg;
    Sculpture coarse(cfg), fine(cfg);
    roughenPatch(coarse);
    roughenPatch(fine);
    applyStroke(coarse, ToolOp::Smooth, 3, path({{-16, -40, 0}, {16, -40, 2}}));
    std::vector<Vec3> dense;
    for (int i = 0; i <= 40; ++i)
        dense.push_back(Vec3(-16 + 32.0 * i / 40, -40, 2.0 * i / 40));
    applyStroke(fine, ToolOp::Smooth, 3, dense);
    const auto a = weights(coarse), b = weights(fine);
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [key, w] : a)
        EXPECT_NEAR(b.at(key), w, 1e-5);
}

TEST(Smooth, UndoRestoresEveryLevel) {
    SculptConfig cfg;
    Sculpture s(cfg);
    roughenPatch(s);
    applyStroke(s, ToolOp::Add, 4, path({{-10, -42, -8}, {10, -42, 8}}));
    const auto before = weights(s);
    std::vector<SkeletonChange> changes;
    applyStroke(s, ToolOp::Smooth, 4, zigzagOverPatch(), &changes);
    bool severalLevels = false;
    for (const SkeletonChange& c : changes)
        severalLevels |= c.level != changes.front().level;
    EXPECT_TRUE(severalLevels);  // the dabs (level 2) and the bar (level 4) both relax
    revertChanges(s, changes);
    EXPECT_EQ(weights(s), before);
}

TEST(Smooth, ThesisModeRefusesIt) {
    SculptConfig cfg;
    cfg.placement = PlacementMode::Thesis;
    Sculpture s(cfg);
    EXPECT_THROW(StrokeBuilder(s, ToolOp::Smooth, 4), std::invalid_argument);
}

}  // namespace
