// SPDX-License-Identifier: MIT
#include "vsculpt/core/PlaceStroke.h"

#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/SweptVertices.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

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

// Swept-mode placement constants (docs/placement.md; the margin, kSweptMarginOverRadius, is in
// the header).
// Richardson steps of the deconvolution that turns target changes into weights: 2 keeps the
// ripple of a straight stroke within 5 % of D/2 (1 leaves dabs 13 % small, 3 ripples 5.9 %).
constexpr int kDeconvolveSteps = 2;
// Near existing skeletons, target changes that would move the surface by less than this
// many lattice spacings are not made (a replayed stroke then adds little).
constexpr double kDeadBand = 0.02;

using Stencil = std::map<std::array<int, 3>, double>;

// A changed vertex at `pos`: into the edit's region and point list.
void noteChanged(EditResult& result, Aabb& changed, const Vec3& pos) {
    changed.expand(pos);
    result.changedPoints.push_back(pos);
    ++result.changedVertices;
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
// the way to the mean of its six lattice neighbours (times the brush profile). Swept mode's
// deconvolved strokes spread their change over twice the tool radius, so their roughness lies
// at lower lattice frequencies, which a step damps less: a longer step there (still stable:
// the highest frequency's amplification is 1 - 2 * 0.75 = -0.5).
double smoothStrength(PlacementMode mode) {
    return mode == PlacementMode::Swept ? 0.75 : 0.5;
}
// A vertex that had no skeleton gets one only when diffusion gives it at least this weight:
// smoothing must not scatter dust-sized skeletons over the whole tool region.
constexpr double kSmoothMinNewWeight = 1e-3;
Stencil convolve(const Stencil& a, const Stencil& b) {
    Stencil c;
    for (const auto& [oa, wa] : a)
        for (const auto& [ob, wb] : b)
            c[{oa[0] + ob[0], oa[1] + ob[1], oa[2] + ob[2]}] += wa * wb;
    return c;
}
}  // namespace

StrokeBuilder::StrokeBuilder(Sculpture& sculpture, ToolOp op, int level, MirrorAxis mirror)
    : mSculpture(sculpture), mOp(op), mLevel(level), mMirror(mirror) {
    if (level < 1 || level > kLevelCount)
        throw std::invalid_argument("tool level " + std::to_string(level) + " outside 1..7");
    if (op == ToolOp::Smooth && sculpture.config().placement == PlacementMode::Thesis)
        throw std::invalid_argument(
            "the smooth tool needs placement mode \"free\" or \"swept\" (thesis mode has unit "
            "weights only)");
    const ToolLevel& tl = sculpture.levels().level(level);
    const int n = int(std::ceil(tl.supportMm / tl.spacingMm));
    const double r2 = tl.supportMm * tl.supportMm;
    for (int x = -n; x <= n; ++x)
        for (int y = -n; y <= n; ++y)
            for (int z = -n; z <= n; ++z)
                if ((x * x + y * y + z * z) * tl.spacingMm * tl.spacingMm < r2)
                    mStencil.push_back(LatticeCoord{x, y, z});
    mProbe = std::make_unique<FieldProbe>(sculpture);
    if (sculpture.config().placement == PlacementMode::Swept && op != ToolOp::Smooth) {
        // The realised change of the field at the vertices is the target change blurred by
        // the falloff sampled on the lattice, K. Weights P * change with
        // P = (1/S) sum_{j=0..n} (I - K/S)^j, S = sum K (n Richardson steps) undo most of
        // that blur; the stencil is the same at every level (R_k / h_k is).
        const HermiteFalloff& F = sculpture.levels().falloff();
        Stencil K;
        double S = 0;
        for (const LatticeCoord& o : mStencil) {
            const double d = std::sqrt(double(o.x * o.x + o.y * o.y + o.z * o.z)) * tl.spacingMm;
            const double k = F.value(d / tl.supportMm);
            if (k <= 0) continue;
            K[{o.x, o.y, o.z}] = k;
            S += k;
        }
        Stencil M;  // I - K/S
        for (const auto& [o, k] : K)
            M[o] = -k / S;
        M[{0, 0, 0}] += 1.0;
        Stencil Q = {{{0, 0, 0}, 1.0}}, P = Q;
        for (int j = 0; j < kDeconvolveSteps; ++j) {
            Q = convolve(Q, M);
            for (const auto& [o, w] : Q)
                P[o] += w;
        }
        for (const auto& [o, w] : P)
            if (std::abs(w) > 1e-12 * S)
                mDeconvolve.push_back(Tap{LatticeCoord{o[0], o[1], o[2]}, w / S});
    }
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

FieldSample StrokeBuilder::preStrokeSample(const LatticeCoord& v, const Vec3& pos) {
    FieldSample s = mProbe->sample(pos);
    s.value += mSculpture.levels().iso();
    if (mDeltas.empty()) return s;
    const ToolLevel& tl = mSculpture.levels().level(mLevel);
    const HermiteFalloff& F = mSculpture.levels().falloff();
    for (const LatticeCoord& o : mStencil) {
        auto it = mDeltas.find(LatticeCoord{v.x + o.x, v.y + o.y, v.z + o.z});
        if (it == mDeltas.end()) continue;
        const double d = std::sqrt(double(o.x * o.x + o.y * o.y + o.z * o.z)) * tl.spacingMm;
        const double u = d / tl.supportMm;
        s.value -= double(it->second) * F.value(u);
        // d/dP of w F(|P - s| / R) with P - s = -o h.
        if (d > 0)
            s.gradient -= double(it->second) * F.derivative(u) / tl.supportMm *
                          (-Vec3(o.x, o.y, o.z) * tl.spacingMm / d);
    }
    return s;
}

void StrokeBuilder::setWeight(const LatticeCoord& v, const std::optional<float>& current,
                              const std::optional<float>& after) {
    SkeletonStore& store = mSculpture.store();
    if (after)
        store.set(mLevel, v, *after);
    else
        store.erase(mLevel, v);
    mDeltas[v] += after.value_or(0.0f) - current.value_or(0.0f);
    auto [it, first] = mChangeIndex.try_emplace(v, mChanges.size());
    if (first)
        mChanges.push_back(SkeletonChange{mLevel, v, current, after});
    else
        mChanges[it->second].after = after;
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
    return mSculpture.config().placement == PlacementMode::Swept ? addSampleSwept(a, p)
                                                                 : addSampleOnTool(a, p);
}

EditResult StrokeBuilder::addSampleSwept(const Vec3& a, const Vec3& p) {
    const ToolLevels& levels = mSculpture.levels();
    const ToolLevel& tl = levels.level(mLevel);
    const HermiteFalloff& F = levels.falloff();
    const double radius = 0.5 * tl.diameterMm;
    const double margin = kSweptMarginOverRadius * radius;
    const double iso = levels.iso();
    const double uIso = F.inverse(iso);
    SkeletonStore& store = mSculpture.store();

    // The field of a fresh stroke at distance l from the path: c on the tool's surface, F's
    // shape, zero at the margin; slopeAtTool is its slope there (per mm).
    auto freshField = [&](double l) {
        return F.value(std::max(0.0, uIso + (1 - uIso) * (l - radius) / margin));
    };
    const double slopeAtTool = -F.derivative(uIso) * (1 - uIso) / margin;
    // A smooth signed distance to the swept tool's surface (mm; < 0 inside), saturating at
    // sMax at the margin: the fresh field read as a distance.
    const double sMax = iso / slopeAtTool;
    // The target change of the field at a vertex, from the pre-stroke field there and the
    // vertex's distance to the path (docs/placement.md). Add raises the field to at least
    // c - slope * s, carve lowers it to at most c + slope * s: the new surface is the tool's
    // where the tool reaches beyond the old surface. The slope is the material's own
    // gradient, so near a surface the old field is moved in parallel and what the tool
    // overlaps is added or removed exactly whatever the field's steepness; where the field is
    // flat or absent, the slope is what reaches the old field at the margin (in empty space,
    // add gives the fresh field itself).
    // Near existing skeletons, changes that would move the surface by less than kDeadBand
    // lattice spacings are not made, so replaying a stroke places nothing new (in empty space
    // the fresh field is kept whole).
    auto targetChange = [&](const Target& t) {
        const double s = (iso - freshField(t.lateral)) / slopeAtTool;
        if (mOp == ToolOp::Add) {
            const double slope = std::max(t.grad, (iso - t.phi) / sMax);
            const double c = std::max(0.0, iso - slope * s - t.phi);
            return std::abs(t.phi) > 1e-9 && c < kDeadBand * slope * tl.spacingMm ? 0.0 : c;
        }
        const double slope = std::max(t.grad, (t.phi - iso) / sMax);
        const double c = std::min(0.0, iso + slope * s - t.phi);
        return -c < kDeadBand * slope * tl.spacingMm ? 0.0 : c;
    };

    std::vector<LatticeCoord> fresh, moved;
    for (const SweptVertex& sv : sweptWithMirror(tl.spacingMm, a, p, radius + margin, mMirror)) {
        auto [it, first] = mTargets.try_emplace(sv.coord);
        Target& t = it->second;
        if (first) {
            const FieldSample fs = preStrokeSample(sv.coord, vertexPos(sv.coord, tl.spacingMm));
            t.phi = fs.value;
            t.grad = glm::length(fs.gradient);
            t.lateral = sv.lateralMm;
            t.change = targetChange(t);
            fresh.push_back(sv.coord);
            if (t.change != 0) moved.push_back(sv.coord);
        } else if (sv.lateralMm < t.lateral) {
            t.lateral = sv.lateralMm;
            const double c = targetChange(t);
            if (c != t.change) {
                t.change = c;
                moved.push_back(sv.coord);
            }
        }
    }
    // Weights follow the target changes: recompute every vertex whose deconvolution stencil
    // reaches a changed target, and every new vertex.
    std::unordered_map<LatticeCoord, char, LatticeCoordHash> affected;
    for (const LatticeCoord& v : fresh)
        affected.emplace(v, 0);
    for (const LatticeCoord& u : moved)
        for (const Tap& tap : mDeconvolve) {
            const LatticeCoord v{u.x + tap.offset.x, u.y + tap.offset.y, u.z + tap.offset.z};
            if (mTargets.count(v)) affected.emplace(v, 0);
        }
    std::vector<LatticeCoord> order;
    order.reserve(affected.size());
    for (const auto& [v, unused] : affected)
        order.push_back(v);
    std::sort(order.begin(), order.end(), [](const LatticeCoord& l, const LatticeCoord& r) {
        return std::tie(l.x, l.y, l.z) < std::tie(r.x, r.y, r.z);
    });

    EditResult result;
    Aabb changed;
    for (const LatticeCoord& v : order) {
        double w = 0;
        for (const Tap& tap : mDeconvolve) {
            auto it = mTargets.find(
                LatticeCoord{v.x - tap.offset.x, v.y - tap.offset.y, v.z - tap.offset.z});
            if (it != mTargets.end()) w += tap.weight * it->second.change;
        }
        // Adding never lowers the field and carving never raises it: the deconvolution's
        // negative side lobes would otherwise notch the clay next to an added stroke (and
        // raise it next to a carve), and they add ripple.
        w = mOp == ToolOp::Add ? std::max(w, 0.0) : std::min(w, 0.0);
        const std::optional<float> current = store.get(mLevel, v);
        auto [vit, first] = mVisited.try_emplace(v, Visit{current, 0});
        const std::optional<float> before = vit->second.preStroke;
        std::optional<float> after = before;
        if (before || std::abs(w) > 1e-9) after = float(double(before.value_or(0.0f)) + w);
        if (after == current) continue;
        setWeight(v, current, after);
        const Vec3 pos = vertexPos(v, tl.spacingMm);
        noteChanged(result, changed, pos);
    }
    result.changedRegion = changed.padded(tl.supportMm);
    result.supportMm = tl.supportMm;
    return result;
}

EditResult StrokeBuilder::addSampleOnTool(const Vec3& a, const Vec3& p) {
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
            // tool's surface. The change is spread as weights scaled by the stroke's gain at
            // this lateral distance, so a uniform change over the swept tube comes out uniform.
            // The field is the one before the stroke, so sample spacing does not matter.
            const double raw = preStrokeRawSum(sv.coord, pos);
            const double lateral = sv.lateralMm / radius;
            const double gain = levels.strokeGain(lateral);
            const double w0 = before.value_or(0.0f);
            // Carving: the wall of the carved tube should be at the tool's surface, where a
            // uniform change reaches only strokeWallValue() of its size, so the change is what
            // brings material there down to the iso level, scaled up by that share.
            const double change = mOp == ToolOp::Add
                                      ? std::max(0.0, levels.strokeCoverage(lateral) - raw)
                                      : -std::max(0.0, raw - iso) / levels.strokeWallValue();
            if (change != 0.0 && gain > 0.0) after = float(w0 + change * gain);
        }
        if (after == current) continue;
        setWeight(sv.coord, current, after);
        noteChanged(result, changed, pos);
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
            const double step = smoothStrength(mSculpture.config().placement) *
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
            noteChanged(result, changed, pos);
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
