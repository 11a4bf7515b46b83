// SPDX-License-Identifier: MIT
#include "vsculpt/core/PlaceSolid.h"

#include "VdbMesh.h"
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Sculpture.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace vsculpt::core {

namespace {

constexpr int64_t kMaxSolidVertices = int64_t(1) << 25;

// Weight of a fresh solid at a vertex `s` lattice spacings inside its boundary (negative:
// outside).
double freshWeight(const SolidCalibration& cal, double s) {
    if (cal.rampOverSpacing <= 0) return s >= cal.insetOverSpacing ? cal.interiorWeight : 0.0;
    const double t = 0.5 + (s - cal.insetOverSpacing) / cal.rampOverSpacing;
    return cal.interiorWeight * std::clamp(t, 0.0, 1.0);
}

// Lattice sums in units of the lattice spacing (spacing 1, support rh).
struct UnitLattice {
    const HermiteFalloff* falloff;
    double rh;
    int reach;

    // sum over lattice vertices v of weight(v) * F(|x - v| / rh)
    template <class WeightFn>
    double field(const Vec3& x, WeightFn&& weight) const {
        double sum = 0;
        const int cx = int(std::floor(x.x)), cy = int(std::floor(x.y)), cz = int(std::floor(x.z));
        for (int i = cx - reach; i <= cx + reach + 1; ++i)
            for (int j = cy - reach; j <= cy + reach + 1; ++j)
                for (int k = cz - reach; k <= cz + reach + 1; ++k) {
                    const Vec3 v(i, j, k);
                    const double d = glm::length(x - v);
                    if (d >= rh) continue;
                    const double w = weight(v);
                    if (w != 0) sum += w * falloff->value(d / rh);
                }
        return sum;
    }
};

SolidCalibration calibrate(const ToolLevels& levels) {
    const ToolLevel& l1 = levels.level(1);
    const UnitLattice lat{&levels.falloff(), l1.supportMm / l1.spacingMm,
                          int(std::ceil(l1.supportMm / l1.spacingMm))};
    const double iso = levels.iso();
    std::mt19937_64 rng(20261124);
    std::uniform_real_distribution<double> unit(0.0, 1.0);

    SolidCalibration cal;
    const bool thesis = levels.mode() == PlacementMode::Thesis;
    cal.rampOverSpacing = thesis ? 0.0 : 1.0;

    // Deep inside a solid every vertex carries the interior weight; average the lattice sum
    // over positions because it ripples with the lattice.
    double latticeSum = 0;
    const int sumSamples = 64;
    for (int i = 0; i < sumSamples; ++i)
        latticeSum +=
            lat.field(Vec3(unit(rng), unit(rng), unit(rng)), [](const Vec3&) { return 1.0; });
    latticeSum /= sumSamples;
    if (thesis) {
        cal.interiorWeight = 1.0;
        cal.interiorField = latticeSum;
    } else {
        // The same interior level as a fresh stroke's path, so solids and strokes blend alike
        // under the add rule.
        cal.interiorField = levels.strokeCoverage(0.0);
        cal.interiorWeight = cal.interiorField / latticeSum;
    }
    if (cal.interiorField <= iso)
        throw std::logic_error("solid calibration: interior field does not reach the iso level");

    // Filled half-spaces n.x >= o in many directions and offsets: where does f = c cross a
    // line along n? t* > 0 means the surface lies inside the half-space.
    struct Line {
        Vec3 n, p0;
        int direction;
    };
    std::vector<Line> lines;
    const int directions = 32, perDirection = 8;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int d = 0; d < directions; ++d) {
        const double z = 1.0 - (d + 0.5) / directions;  // upper hemisphere: -n is the same set
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const Vec3 n(r * std::cos(golden * d), r * std::sin(golden * d), z);
        for (int k = 0; k < perDirection; ++k)
            lines.push_back({n, Vec3(unit(rng), unit(rng), unit(rng)), d});
    }
    cal.directions = directions;
    auto crossing = [&](const Line& line, const SolidCalibration& c) {
        const double o = glm::dot(line.n, line.p0);
        auto f = [&](double t) {
            return lat.field(line.p0 + t * line.n, [&](const Vec3& v) {
                return freshWeight(c, glm::dot(line.n, v) - o);
            });
        };
        double lo = -4.0, hi = 4.0;
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (f(mid) < iso ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    };
    auto meanCrossing = [&](const SolidCalibration& c) {
        std::vector<double> t(lines.size());
        tbb::parallel_for(size_t(0), lines.size(), [&](size_t i) { t[i] = crossing(lines[i], c); });
        double sum = 0;
        for (double v : t)
            sum += v;
        return std::make_pair(sum / double(t.size()), t);
    };
    // The mean crossing grows with the inset: bisect for zero.
    double lo = -2.0, hi = 2.0;
    for (int it = 0; it < 30; ++it) {
        cal.insetOverSpacing = 0.5 * (lo + hi);
        (meanCrossing(cal).first < 0 ? lo : hi) = cal.insetOverSpacing;
    }
    cal.insetOverSpacing = 0.5 * (lo + hi);
    const auto [mean, t] = meanCrossing(cal);
    cal.meanErrorOverSpacing = mean;
    std::vector<double> perDir(directions, 0.0);
    for (size_t i = 0; i < lines.size(); ++i) {
        perDir[lines[i].direction] += t[i] / perDirection;
        cal.maxLocalOverSpacing = std::max(cal.maxLocalOverSpacing, std::abs(t[i]));
    }
    for (double v : perDir)
        cal.worstDirectionOverSpacing = std::max(cal.worstDirectionOverSpacing, std::abs(v));
    return cal;
}

int checkedLevel(int level, bool allowZero) {
    if (level < (allowZero ? 0 : 1) || level > kLevelCount)
        throw std::invalid_argument("solid level " + std::to_string(level) + " outside " +
                                    (allowZero ? "0" : "1") + "..7");
    return level;
}

}  // namespace

void validateSolidMesh(const Mesh& solid) {
    if (solid.indices.empty()) throw std::invalid_argument("solid mesh has no triangles");
    if (solid.indices.size() % 3 != 0)
        throw std::invalid_argument("solid mesh: " + std::to_string(solid.indices.size()) +
                                    " indices, not a multiple of 3");
    for (size_t i = 0; i < solid.positions.size(); ++i)
        if (!isUsablePoint(solid.positions[i]))
            throw std::invalid_argument("solid mesh: position " + std::to_string(i) +
                                        " is not finite or lies beyond 1e6 mm");
    for (size_t i = 0; i < solid.indices.size(); ++i) {
        if (solid.indices[i] >= solid.positions.size())
            throw std::invalid_argument("solid mesh: index " + std::to_string(i) + " (" +
                                        std::to_string(solid.indices[i]) + ") out of range");
    }
    // Every directed edge once, and its reverse present: sorted keys rather than a hash map,
    // several times faster on the millions of edges of an imported scan.
    std::vector<uint64_t> directed;
    directed.reserve(solid.indices.size());
    for (size_t t = 0; t < solid.triangleCount(); ++t)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = solid.indices[3 * t + e], b = solid.indices[3 * t + (e + 1) % 3];
            if (a == b)
                throw std::invalid_argument("solid mesh: triangle " + std::to_string(t) +
                                            " repeats a vertex");
            directed.push_back(uint64_t(a) << 32 | b);
        }
    tbb::parallel_sort(directed.begin(), directed.end());
    auto edgeName = [](uint64_t k) {
        return std::to_string(k >> 32) + "-" + std::to_string(k & 0xffffffffu);
    };
    for (size_t i = 1; i < directed.size(); ++i)
        if (directed[i] == directed[i - 1])
            throw std::invalid_argument(
                "solid mesh is not consistently oriented or not manifold: edge " +
                edgeName(directed[i]) + " used twice in one direction");
    for (uint64_t k : directed)
        if (!std::binary_search(directed.begin(), directed.end(), k << 32 | k >> 32))
            throw std::invalid_argument("solid mesh is not closed: edge " + edgeName(k) +
                                        " has one triangle");
    const double volume = meshVolume(solid);
    if (!(volume > 0))
        throw std::invalid_argument("solid mesh encloses no positive volume (" +
                                    std::to_string(volume) + " mm^3): empty or inside-out");
}

int solidLevelFor(const ToolLevels& levels, const Mesh& solid) {
    const Aabb b = meshBounds(solid);
    const Vec3 e = b.max - b.min;
    const double thickness = std::min({e.x, e.y, e.z});
    int best = 0, finest = 1;
    for (int k = 1; k <= kLevelCount; ++k) {
        const double h = levels.level(k).spacingMm;
        if (h < levels.level(finest).spacingMm) finest = k;
        if (h <= 0.25 * thickness && (best == 0 || h > levels.level(best).spacingMm)) best = k;
    }
    return best ? best : finest;
}

const SolidCalibration& solidCalibration(const ToolLevels& levels) {
    // Keyed by everything the calibration reads, not by address: tables may be rebuilt.
    using Key = std::tuple<int, double, double, double, double>;
    static std::mutex mutex;
    static std::map<Key, SolidCalibration> cache;
    const ToolLevel& l1 = levels.level(1);
    const Key key{int(levels.mode()), l1.supportMm / l1.spacingMm, levels.iso(),
                  levels.strokeCoverage(0.0), levels.falloff().value(0.5)};
    std::lock_guard lock(mutex);
    auto it = cache.find(key);
    if (it == cache.end()) it = cache.emplace(key, calibrate(levels)).first;
    return it->second;
}

namespace {
/// OpenVDB's interrupter interface over a stop flag (may be null: never interrupted).
struct StopFlag {
    const std::atomic<bool>* flag = nullptr;
    bool raised() const { return flag && flag->load(std::memory_order_relaxed); }
    void start(const char* = nullptr) {}
    void end() {}
    bool wasInterrupted(int = -1) { return raised(); }
};
}  // namespace

SolidPlacement placeSolid(Sculpture& sculpture, const Mesh& solid, int level,
                          const std::atomic<bool>* stop) {
    StopFlag stopFlag{stop};
    validateSolidMesh(solid);
    const ToolLevels& levels = sculpture.levels();
    level = checkedLevel(level, true);
    if (level == 0) level = solidLevelFor(levels, solid);
    const ToolLevel& tl = levels.level(level);
    const double h = tl.spacingMm;
    const SolidCalibration& cal = solidCalibration(levels);
    const bool thesis = levels.mode() == PlacementMode::Thesis;

    // Vertices up to this far outside the solid (in spacings) can carry weight.
    const double outside = std::max(0.0, 0.5 * cal.rampOverSpacing - cal.insetOverSpacing) + 1.0;
    const Aabb bounds = meshBounds(solid);
    // Smaller than two spacings a solid leaves no surface (measured: a ball 2.5 mm across at
    // level 1's 1.48 mm leaves none, 3 mm one 1.2 mm across) yet would make an undo step of
    // invisible weights (found by QA: an STL in metres imported as mm, a tiny outline).
    const double across = std::max(
        {bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y, bounds.max.z - bounds.min.z});
    if (across < 2 * h) {
        char b[96];
        std::snprintf(b, sizeof b,
                      "%.3g mm across, less than two lattice spacings of level %d (%.3g", across,
                      level, h);
        throw std::invalid_argument(
            std::string("solid only ") + b + " mm): it would leave no clay; " +
            (level > 1 ? std::string("choose a finer level or make it larger")
                       : std::string("make it larger")));
    }
    LatticeCoord lo, hi;
    int64_t count = 1;
    for (int a = 0; a < 3; ++a) {
        const double l = std::floor(bounds.min[a] / h - outside);
        const double u = std::ceil(bounds.max[a] / h + outside);
        if (l < -kMaxLatticeCoord || u > kMaxLatticeCoord)
            throw std::invalid_argument(
                "solid lies beyond the lattice range of level " + std::to_string(level) +
                (level < kLevelCount ? " (choose a larger level)" : " (make it smaller)"));
        (&lo.x)[a] = int32_t(l);
        (&hi.x)[a] = int32_t(u);
        count *= int64_t(u - l + 1);
        if (count > kMaxSolidVertices)
            throw std::invalid_argument(
                "solid too large for level " + std::to_string(level) + " (" +
                [&] {
                    char b[32];
                    std::snprintf(b, sizeof b, "%.4g", tl.spacingMm);
                    return std::string(b);
                }() +
                " mm spacing): more than 2^25 lattice vertices; " +
                (level < kLevelCount ? std::string("choose a larger level")
                                     : std::string("make it smaller (level 7 is the largest)")));
    }
    const int nx = hi.x - lo.x + 1, ny = hi.y - lo.y + 1, nz = hi.z - lo.z + 1;

    // Signed distance at every lattice vertex: OpenVDB's mesh-to-volume on a grid whose voxel
    // centres are this level's lattice vertices (index i <-> i * h). Beyond the narrow band the
    // sign is all that matters, and the flood fill supplies it.
    initializeOpenVdb();
    const auto xform = openvdb::math::Transform::createLinearTransform(h);
    // The sign comes from OpenVDB's inside/outside flood fill, not from the winding.
    const auto [points, tris] = toVdbMesh(solid);
    const float band =
        float(std::ceil(outside + std::abs(cal.insetOverSpacing) + cal.rampOverSpacing) + 2.0);
    const openvdb::FloatGrid::Ptr sdf =
        openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
            stopFlag, *xform, points, tris, std::vector<openvdb::Vec4I>{}, band, band);
    // An interrupted conversion returns what it had: not a distance field to decide from.
    if (stopFlag.raised()) throw PlacementStopped();

    // Fresh-solid weights, dense over the box (z-major like the loops below).
    auto index = [&](int x, int y, int z) {
        return (size_t(z - lo.z) * size_t(ny) + size_t(y - lo.y)) * size_t(nx) + size_t(x - lo.x);
    };
    std::vector<float> fresh(size_t(nx) * ny * nz, 0.0f);
    tbb::parallel_for(lo.z, hi.z + 1, [&](int z) {
        auto acc = sdf->getConstAccessor();
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                const double s = -double(acc.getValue(openvdb::Coord(x, y, z))) / h;
                fresh[index(x, y, z)] = float(freshWeight(cal, s));
            }
    });

    // Decide every vertex from the field as it was before the solid (two passes), so the result
    // does not depend on the visiting order.
    struct Decision {
        LatticeCoord c;
        std::optional<float> before, after;
    };
    std::vector<std::vector<Decision>> slabs(static_cast<size_t>(nz));
    SkeletonStore& store = sculpture.store();
    const int reach = int(std::ceil(tl.supportMm / h));
    std::vector<std::pair<LatticeCoord, double>> stencil;  // offset, F(|o| h / R)
    for (int x = -reach; x <= reach; ++x)
        for (int y = -reach; y <= reach; ++y)
            for (int z = -reach; z <= reach; ++z) {
                const double d = std::sqrt(double(x * x + y * y + z * z)) * h;
                if (d < tl.supportMm)
                    stencil.push_back(
                        {LatticeCoord{x, y, z}, levels.falloff().value(d / tl.supportMm)});
            }
    tbb::parallel_for(
        tbb::blocked_range<int>(lo.z, hi.z + 1, 1), [&](const tbb::blocked_range<int>& r) {
            std::unique_ptr<FieldProbe> probe;
            for (int z = r.begin(); z != r.end(); ++z) {
                if (stopFlag.raised()) return;  // thrown below, once every task has ended
                std::vector<Decision>& out = slabs[size_t(z - lo.z)];
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x) {
                        const double w = fresh[index(x, y, z)];
                        if (w <= 0) continue;
                        const LatticeCoord c{x, y, z};
                        const std::optional<float> before = store.get(level, c);
                        std::optional<float> after = before;
                        if (thesis) {
                            // Thesis rules: a solid fills empty vertices, like an add stroke.
                            if (!before) after = 1.0f;
                        } else {
                            // Free mode, as for strokes: raise the field at the vertex to what the
                            // fresh solid gives there, spread by the solid's own gain w / T.
                            double fieldOfFresh = 0;
                            for (const auto& [o, f] : stencil) {
                                const int ox = x + o.x, oy = y + o.y, oz = z + o.z;
                                if (ox < lo.x || ox > hi.x || oy < lo.y || oy > hi.y || oz < lo.z ||
                                    oz > hi.z)
                                    continue;
                                fieldOfFresh += fresh[index(ox, oy, oz)] * f;
                            }
                            if (!probe) probe = std::make_unique<FieldProbe>(sculpture);
                            const double raw = probe->rawSum(Vec3(x, y, z) * h);
                            const double change = std::max(0.0, fieldOfFresh - raw);
                            if (change > 0 && fieldOfFresh > 0)
                                after = float(before.value_or(0.0f) + change * w / fieldOfFresh);
                        }
                        if (after != before) out.push_back({c, before, after});
                    }
            }
        });

    if (stopFlag.raised()) throw PlacementStopped();  // nothing was written yet
    SolidPlacement result;
    result.level = level;
    Aabb changed;
    for (const auto& slab : slabs)
        for (const Decision& d : slab) {
            store.set(level, d.c, *d.after);
            result.changes.push_back(SkeletonChange{level, d.c, d.before, d.after});
            const Vec3 pos = Vec3(d.c.x, d.c.y, d.c.z) * h;
            changed.expand(pos);
            result.edit.changedPoints.push_back(pos);
        }
    result.edit.changedVertices = int(result.changes.size());
    result.edit.changedRegion = changed.padded(tl.supportMm);
    result.edit.supportMm = tl.supportMm;
    return result;
}

SolidPlacement replaySolid(Sculpture& sculpture, int level,
                           std::span<const SkeletonChange> afterStates) {
    checkedLevel(level, false);
    for (const SkeletonChange& c : afterStates) {
        // A replacing solid also takes the previous solid's clay away, on its level.
        checkedLevel(c.level, false);
        for (int32_t v : {c.coord.x, c.coord.y, c.coord.z})
            if (v < -kMaxLatticeCoord || v > kMaxLatticeCoord)
                throw std::invalid_argument("solid replay: lattice coordinate " +
                                            std::to_string(v) + " beyond +-2^22");
    }
    const ToolLevel& tl = sculpture.levels().level(level);
    SolidPlacement result;
    result.level = level;
    Aabb changed;
    for (const SkeletonChange& c : afterStates) {
        SkeletonChange applied{c.level, c.coord, sculpture.store().get(c.level, c.coord), c.after};
        if (c.after)
            sculpture.store().set(c.level, c.coord, *c.after);
        else
            sculpture.store().erase(c.level, c.coord);
        const double h = sculpture.levels().level(c.level).spacingMm;
        const Vec3 pos = Vec3(c.coord.x, c.coord.y, c.coord.z) * h;
        changed.expand(pos);
        result.edit.changedPoints.push_back(pos);
        result.changes.push_back(applied);
    }
    result.edit.changedVertices = int(result.changes.size());
    // Changes may sit on several levels: pad by the largest support among them.
    double support = tl.supportMm;
    for (const SkeletonChange& c : afterStates)
        support = std::max(support, sculpture.levels().level(c.level).supportMm);
    result.edit.changedRegion = changed.padded(support);
    result.edit.supportMm = support;
    return result;
}

}  // namespace vsculpt::core
