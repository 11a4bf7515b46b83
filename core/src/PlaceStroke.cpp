// SPDX-License-Identifier: MIT
#include "vsculpt/core/PlaceStroke.h"

#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/SweptVertices.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace vsculpt::core {

const char* toString(ToolOp op) {
    return op == ToolOp::Add ? "add" : op == ToolOp::Carve ? "carve" : "smooth";
}

const char* toString(MirrorAxis axis) {
    switch (axis) {
        case MirrorAxis::X:
            return "x";
        case MirrorAxis::Y:
            return "y";
        case MirrorAxis::Z:
            return "z";
        case MirrorAxis::None:
            break;
    }
    return "off";
}

Vec3 mirrored(const Vec3& p, MirrorAxis axis) {
    Vec3 q = p;
    if (axis != MirrorAxis::None) q[int(axis) - 1] = -q[int(axis) - 1];
    return q;
}

namespace {
Vec3 vertexPos(const LatticeCoord& c, double spacing) {
    return Vec3(c.x, c.y, c.z) * spacing;
}

// The lattice vertices swept by the segment a-p and, with a mirror plane, by its mirror image
// too, in the same pass: each vertex keeps its closest approach to either segment (callers
// take the smallest lateral distance), so a vertex and its mirror image are decided alike.
std::vector<SweptVertex> sweptWithMirror(double spacing, const Vec3& a, const Vec3& p,
                                         double radius, MirrorAxis mirror) {
    std::vector<SweptVertex> swept = sweptVertices(spacing, a, p, radius);
    if (mirror != MirrorAxis::None) {
        const std::vector<SweptVertex> image =
            sweptVertices(spacing, mirrored(a, mirror), mirrored(p, mirror), radius);
        swept.insert(swept.end(), image.begin(), image.end());
    }
    return swept;
}

// Smooth tool (docs/placement.md): each pass moves every weight under the tool this share of
// the way to the mean of its six lattice neighbours (times the brush profile).
constexpr double kSmoothStrength = 0.5;
// A vertex that had no skeleton gets one only when diffusion gives it at least this weight:
// smoothing must not scatter dust-sized skeletons over the whole tool region.
constexpr double kSmoothMinNewWeight = 1e-3;
}  // namespace

StrokeBuilder::StrokeBuilder(Sculpture& sculpture, ToolOp op, int level, MirrorAxis mirror)
    : mSculpture(sculpture), mOp(op), mLevel(level), mMirror(mirror) {
    if (level < 1 || level > kLevelCount)
        throw std::invalid_argument("tool level " + std::to_string(level) + " outside 1..7");
    if (op == ToolOp::Smooth && sculpture.config().placement == PlacementMode::Thesis)
        throw std::invalid_argument(
            "the smooth tool needs placement mode \"free\" (thesis mode has unit weights only)");
    const ToolLevel& tl = sculpture.levels().level(level);
    const int n = int(std::ceil(tl.supportMm / tl.spacingMm));
    const double r2 = tl.supportMm * tl.supportMm;
    for (int x = -n; x <= n; ++x)
        for (int y = -n; y <= n; ++y)
            for (int z = -n; z <= n; ++z)
                if ((x * x + y * y + z * z) * tl.spacingMm * tl.spacingMm < r2)
                    mStencil.push_back(LatticeCoord{x, y, z});
    mProbe = std::make_unique<FieldProbe>(sculpture);
}

StrokeBuilder::~StrokeBuilder() = default;

double StrokeBuilder::preStrokeRawSum(const LatticeCoord& v, const Vec3& pos) {
    double raw = mProbe->rawSum(pos);
    if (mDeltas.empty()) return raw;
    const ToolLevel& tl = mSculpture.levels().level(mLevel);
    const HermiteFalloff& F = mSculpture.levels().falloff();
    for (const LatticeCoord& o : mStencil) {
        auto it = mDeltas.find(LatticeCoord{v.x + o.x, v.y + o.y, v.z + o.z});
        if (it == mDeltas.end()) continue;
        const double d = std::sqrt(double(o.x * o.x + o.y * o.y + o.z * o.z)) * tl.spacingMm;
        raw -= double(it->second) * F.value(d / tl.supportMm);
    }
    return raw;
}

EditResult StrokeBuilder::addSample(const Vec3& p) {
    if (!isUsablePoint(p)) {
        std::ostringstream msg;
        msg << "tool sample (" << p.x << ", " << p.y << ", " << p.z
            << ") mm is not finite or lies beyond 1e6 mm of the object origin";
        throw std::invalid_argument(msg.str());
    }
    const Vec3 a = mLast.value_or(p);
    mLast = p;
    if (mOp == ToolOp::Smooth) return addSmoothSample(a, p);

    const ToolLevels& levels = mSculpture.levels();
    const ToolLevel& tl = levels.level(mLevel);
    const double radius = 0.5 * tl.diameterMm;
    const double iso = levels.iso();
    const bool thesis = mSculpture.config().placement == PlacementMode::Thesis;
    SkeletonStore& store = mSculpture.store();

    EditResult result;
    Aabb changed;
    for (const SweptVertex& sv : sweptWithMirror(tl.spacingMm, a, p, radius, mMirror)) {
        const std::optional<float> current = store.get(mLevel, sv.coord);
        auto [it, first] = mVisited.try_emplace(sv.coord, Visit{current, sv.lateralMm});
        if (!first) {
            if (thesis || sv.lateralMm >= it->second.lateral) continue;
            it->second.lateral = sv.lateralMm;
        }
        const std::optional<float> before = it->second.preStroke;
        const Vec3 pos = vertexPos(sv.coord, tl.spacingMm);
        std::optional<float> after = before;
        if (thesis) {
            // Thesis §3.1.2: add fills empty vertices only; carve stacks a subtractive skeleton
            // on a same-level additive one, or places one on an empty vertex inside material.
            if (mOp == ToolOp::Add) {
                if (!before) after = 1.0f;
            } else if (before && *before == 1.0f) {
                after = 0.0f;
            } else if (!before && preStrokeRawSum(sv.coord, pos) - iso > 0) {
                after = -1.0f;
            }
        } else {
            // Free mode (docs/placement.md): add raises the field at the vertex to at least
            // what a fresh stroke gives there; carve lowers it so the carved wall is at the
            // tool's surface.
            // The change is spread as weights scaled by the stroke's gain at this lateral
            // distance, so a uniform change over the swept tube comes out uniform. The field
            // is the one before the stroke, so sample spacing does not matter.
            const double raw = preStrokeRawSum(sv.coord, pos);
            const double lateral = sv.lateralMm / radius;
            const double gain = levels.strokeGain(lateral);
            const double w0 = before.value_or(0.0f);
            // Carving: the wall of the carved tube should be at the tool's surface, where a
            // uniform change reaches only strokeWallValue() of its size, so the change is
            // what brings material there down to the iso level, scaled up by that share.
            const double change = mOp == ToolOp::Add
                                      ? std::max(0.0, levels.strokeCoverage(lateral) - raw)
                                      : -std::max(0.0, raw - iso) / levels.strokeWallValue();
            if (change != 0.0 && gain > 0.0) after = float(w0 + change * gain);
        }
        if (after == current) continue;
        if (after)
            store.set(mLevel, sv.coord, *after);
        else
            store.erase(mLevel, sv.coord);
        mDeltas[sv.coord] += after.value_or(0.0f) - current.value_or(0.0f);
        mChanges.push_back(SkeletonChange{mLevel, sv.coord, current, after});
        changed.expand(pos);
        result.changedPoints.push_back(pos);
        ++result.changedVertices;
    }
    result.changedRegion = changed.padded(tl.supportMm);
    result.supportMm = tl.supportMm;
    return result;
}

EditResult StrokeBuilder::addSmoothSample(const Vec3& a, const Vec3& p) {
    // Diffusion of the weights on every level up to the tool's, each on its own lattice: the
    // field is the sum of each level's weights blurred by its kernel, so smoothing the weights
    // smooths the field, fine detail (on fine levels) included, and a discrete Laplacian keeps
    // the sum of the weights, hence the clay's volume, nearly unchanged. Everything is decided
    // from the weights before the stroke, so the result does not depend on sample spacing.
    const ToolLevels& levels = mSculpture.levels();
    const double radius = 0.5 * levels.level(mLevel).diameterMm;
    SkeletonStore& store = mSculpture.store();
    EditResult result;
    Aabb changed;
    double support = 0;
    for (int level = 1; level <= mLevel; ++level) {
        const ToolLevel& tl = levels.level(level);
        support = std::max(support, tl.supportMm);
        auto& visited = mSmoothVisited[size_t(level - 1)];
        auto& pre = mSmoothPre[size_t(level - 1)];
        auto preStroke = [&](const LatticeCoord& c) -> double {
            const auto it = pre.find(c);
            return it != pre.end() ? it->second.value_or(0.0f) : store.get(level, c).value_or(0.0f);
        };
        for (const SweptVertex& sv : sweptWithMirror(tl.spacingMm, a, p, radius, mMirror)) {
            auto [it, first] = visited.try_emplace(sv.coord, sv.lateralMm);
            if (!first) {
                if (sv.lateralMm >= it->second) continue;
                it->second = sv.lateralMm;
            }
            const double w = preStroke(sv.coord);
            double neighbours = 0;
            for (int axis = 0; axis < 3; ++axis)
                for (int sign = -1; sign <= 1; sign += 2) {
                    LatticeCoord n = sv.coord;
                    (axis == 0 ? n.x : axis == 1 ? n.y : n.z) += sign;
                    neighbours += preStroke(n);
                }
            const double step = kSmoothStrength *
                                strokeProfile(PlacementMode::Free, sv.lateralMm / radius) *
                                (neighbours / 6.0 - w);
            const std::optional<float> current = store.get(level, sv.coord);
            const std::optional<float> before = pre.count(sv.coord) ? pre.at(sv.coord) : current;
            std::optional<float> after = before;
            if (before || std::abs(w + step) >= kSmoothMinNewWeight) after = float(w + step);
            if (after == current) continue;
            pre.try_emplace(sv.coord, current);
            if (after)
                store.set(level, sv.coord, *after);
            else
                store.erase(level, sv.coord);
            mChanges.push_back(SkeletonChange{level, sv.coord, current, after});
            const Vec3 pos = vertexPos(sv.coord, tl.spacingMm);
            changed.expand(pos);
            result.changedPoints.push_back(pos);
            ++result.changedVertices;
        }
    }
    result.changedRegion = changed.padded(support);
    result.supportMm = support;
    return result;
}

EditResult StrokeBuilder::addSampleWorld(const Vec3& worldPos,
                                         const RigidTransform& worldFromObject) {
    return addSample(worldFromObject.inverse().apply(worldPos));
}

EditResult applyStroke(Sculpture& sculpture, ToolOp op, int level, std::span<const Vec3> path,
                       std::vector<SkeletonChange>* changes, MirrorAxis mirror) {
    StrokeBuilder stroke(sculpture, op, level, mirror);
    EditResult total;
    for (const Vec3& p : path) {
        const EditResult r = stroke.addSample(p);
        total.changedRegion.expand(r.changedRegion);
        total.changedVertices += r.changedVertices;
    }
    if (changes) {
        auto c = stroke.takeChanges();
        changes->insert(changes->end(), c.begin(), c.end());
    }
    return total;
}

namespace {
Aabb restore(Sculpture& s, const SkeletonChange& c, const std::optional<float>& state) {
    if (state)
        s.store().set(c.level, c.coord, *state);
    else
        s.store().erase(c.level, c.coord);
    const ToolLevel& tl = s.levels().level(c.level);
    const Vec3 pos = vertexPos(c.coord, tl.spacingMm);
    return Aabb{pos, pos}.padded(tl.supportMm);
}
}  // namespace

Aabb revertChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes) {
    Aabb box;
    for (auto it = changes.rbegin(); it != changes.rend(); ++it)
        box.expand(restore(sculpture, *it, it->before));
    return box;
}

Aabb reapplyChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes) {
    Aabb box;
    for (const SkeletonChange& c : changes)
        box.expand(restore(sculpture, c, c.after));
    return box;
}

}  // namespace vsculpt::core
