// SPDX-License-Identifier: MIT
#include "vsculpt/core/PlaceStroke.h"

#include "vsculpt/core/DeconvolutionStencil.h"
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/KeepSmoothedVolume.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/SweptVertices.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
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
// The closed-loop fit spreads a control point's missing change over the vertices around it in
// proportion to H(x / kFitShareWidth), a bump this many times wider than the transfer's main
// lobe: spread this wide, the correction sits where the targets are, near the old surface,
// where a later smooth stroke reaches it (with the transfer's own width, H(x), a carved pit's
// correction sits at its bottom and the smooth tool's roughness test on dabbed clay fails:
// -11 % per pass instead of -15 %); depths are as good (docs/placement.md).
constexpr double kFitShareWidth = 2.5;
// The same on the refinement's lattice (placement.refine_levels), in its own spacings.
constexpr double kFitShareWidthRefining = 1.0;
// A carve's shares narrow to the transfer's own width where the old clay is flat: there the
// wide spread moves the surface beyond the tool by millimetres (an error of 0.01 in a field
// sloping 0.005 per mm is 2 mm), while steep fresh clay needs the wide spread for its shallow
// grooves' depth. Flatness is g = |grad f| at the control point / a fresh stroke's slope at the
// tool: 0.04-0.40 on the initial sphere (sizes 1-7), 0.02-0.15 on worked clay (5th-95th
// percentile). Width 1 up to g = 0.15, kFitShareWidth from 0.25, linear between
// (docs/placement.md "Each stroke of a worked detail").
constexpr double kFlatCarveShareWidth = 1.0;
constexpr double kFlatCarveBelow = 0.15, kSteepCarveAbove = 0.25;
// The fit applies where the old surface lies within this many tool radii of the control point
// (a bump's top is at most 2 radii above it, a groove's bottom 1.4 at the deepest).
// At 3, an add along a carved ring (RayTrace.RaysNeverSlipThroughAClosedMesh's scene) left a
// thin fold of clay where 2 of its 400 000 rays lost the front/back alternation (float
// precision at a 0.2 um wedge); at 2.5 and 2 none do, and depths are the same.
constexpr double kFitReachOverRadius = 2.5;
// The least normalisation of a fit share (see fitCorrection): a vertex takes at most about
// 1 / 0.3 times the shortfall at its aim. Strokes on a lattice two levels down, adds and carves
// alternating over one spot (400 strokes), stay bounded with this floor (max |w| 1.3; skipping
// the fit below 0.1 or 0.3 instead did too, but a floor keeps the correction continuous).
constexpr double kFitNormFloor = 0.3;
// On a lattice finer than the tool's (placement.finer_lattice_levels, and the refinement of
// placement.refine_levels) each stroke re-reads its targets across many vertices, and the
// stencil's response just below zero near the checkerboard frequency (-0.03) is then a loop
// gain above one: adds and carves alternating over one spot grew a checkerboard of weights
// (finer lattice: max |w| 0.54 after 300 strokes, 2.9 after 600, 5.5 after 800, the field
// out of its range). A checkerboard of weights is almost invisible in the field (the blur's
// response there is -0.05), so each changed weight sheds this share of the pre-stroke weights'
// checkerboard around it at hardly any cost to the surface: 0.54 after 600 strokes at 1 (0.5
// left 1.2 on the refinement's lattice, 1 left 0.96).
constexpr double kFineCheckerboardDecay = 1.0;
// The refinement's two lattices can hold large, opposite weights whose fields cancel: the tool's
// pass answers the fine residual it reads at its own vertices, the fine pass cancels the
// answer between them, and nothing pulled the split back. Adds and carves alternating over one
// spot at refine_levels 2 grew so without bound (max |w| 2.1 after 400 strokes, 14 after 800,
// the field out of its range; 5.6 after 800 with the checkerboard decay above). So each
// refined stroke hands this share of the fine weights within its reach to its own lattice:
// the fine weights shed it, the tool's pass adds their field's share to its targets (what it
// can hold of it, it takes over), and the fine residual puts back the rest, so the clay is the
// same to the fine pass's accuracy. At 0.1: max |w| 0.56 after 800 strokes, the field within
// +-0.05 (0.3: 0.58).
constexpr double kRefineLeak = 0.1;
// A carve's fit reaches further: the deepest groove bottom lies 1.4 radii below the
// surface, but inside undulating clay, where the field flattens, the first-order reading puts
// it up to about three times deeper (a size-6 groove at 140 % on the slab of strokes: 0.89
// of its depth at 2.5, 0.93 from 4). A carve never raises the field (the blob and the fold
// above were adds'), and tunnels through the initial sphere keep the tool's radius either
// way (mean radius within 2.5 %).
constexpr double kCarveFitReachOverRadius = 4.0;
// A carve's fit also holds the old surface where the tool does not reach it, within this many
// tool radii of the tool's extreme point: a shallow groove then spills less past where the
// tool leaves undulating clay (with the carve's two-sided fit, sizes 1-5 at 20 %: 1.46 -> 1.42
// at most, size 1 1.22 -> 1.16). Such a point beyond 2 radii + margin of the vertex is dropped,
// so the fit's reach stays the same.
constexpr double kKeepSurfaceReach = 1.0;
// A vertex's depth below the old surface is read from its control point when that lies
// within this many tool radii of the surface, and nearer it than the vertex.
constexpr double kDepthFromControlReach = 1.0;
// A stroke's target field stays within this many times the fresh field's depth (F(0) - c) of
// c: the surface lies where the field crosses c, so nothing deeper matters to it, and targets
// read by extrapolating a steep old field (c + |grad| x depth) would otherwise pile ever larger
// values into clay worked over and over (a random pile of 1 400 strokes, stabilised stencil:
// weights up to 34 without the band, 5.2 with it; docs/placement.md "Stability").
constexpr double kTargetBand = 2.0;

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
}  // namespace

// The change of the field at a point x (lattice units from a vertex) that a unit target change
// at that vertex makes once deconvolved: H(x) = sum_o P(o) F(|x - o| h / R). The fit predicts
// the field between vertices with it. It depends only on the falloff and R / h, so it is
// computed once per process; cubic-symmetric, so tabulated over |x| per axis and read back
// trilinearly.
struct SweptTransfer {
    static constexpr int kPerUnit = 8;  // nodes per lattice spacing
    // Lattice spacings: the fit's neighbourhood of a control point (the main lobe and the
    // first side lobe of H; the deconvolution's further lobes are left out).
    static constexpr double kReach = 2.5;
    static constexpr int kNodes = int(kReach * kPerUnit) + 1;
    std::vector<double> values = std::vector<double>(size_t(kNodes * kNodes * kNodes), 0.0);

    double operator()(const Vec3& x) const {
        double f[3];
        int i[3];
        for (int k = 0; k < 3; ++k) {
            const double a = std::abs(x[k]) * kPerUnit;
            // Written so that a NaN position (a field gone non-finite) reads 0, never an
            // index out of the table.
            if (!(a < kNodes - 1)) return 0.0;
            i[k] = int(a);
            f[k] = a - i[k];
        }
        double sum = 0;
        for (int c = 0; c < 8; ++c) {
            double w = 1;
            int idx = 0;
            for (int k = 0; k < 3; ++k) {
                const int bit = (c >> k) & 1;
                w *= bit ? f[k] : 1 - f[k];
                idx = idx * kNodes + i[k] + bit;
            }
            sum += w * values[size_t(idx)];
        }
        return sum;
    }
};

namespace {
std::shared_ptr<const SweptTransfer> transferTable(
    const std::vector<std::pair<std::array<int, 3>, double>>& taps, const HermiteFalloff& F,
    double spacingOverSupport) {
    using Table = SweptTransfer;
    static std::mutex mutex;
    static std::map<std::array<double, 5>, std::shared_ptr<const Table>> cache;
    const FalloffParams& fp = F.params();
    const std::array<double, 5> key{fp.f0, fp.controlU, fp.controlValue, fp.controlSlope,
                                    spacingOverSupport};
    std::lock_guard lock(mutex);
    auto& entry = cache[key];
    if (entry) return entry;
    auto table = std::make_shared<Table>();
    for (int i = 0; i < Table::kNodes; ++i)
        for (int j = 0; j < Table::kNodes; ++j)
            for (int k = 0; k < Table::kNodes; ++k) {
                const Vec3 x(double(i) / Table::kPerUnit, double(j) / Table::kPerUnit,
                             double(k) / Table::kPerUnit);
                double h = 0;
                for (const auto& [o, w] : taps)
                    h += w * F.value(glm::length(x - Vec3(o[0], o[1], o[2])) * spacingOverSupport);
                table->values[size_t((i * Table::kNodes + j) * Table::kNodes + k)] = h;
            }
    entry = table;
    return entry;
}
}  // namespace

StrokeBuilder::StrokeBuilder(Sculpture& sculpture, ToolOp op, int level, MirrorAxis mirror,
                             int lattice, const StrokeBuilder* coarse)
    : mSculpture(sculpture), mOp(op), mLevel(level), mMirror(mirror), mCoarse(coarse) {
    init(lattice);
}

StrokeBuilder::StrokeBuilder(Sculpture& sculpture, ToolOp op, int level, MirrorAxis mirror)
    : mSculpture(sculpture), mOp(op), mLevel(level), mMirror(mirror) {
    if (level < 1 || level > kLevelCount)
        throw std::invalid_argument("tool level " + std::to_string(level) + " outside 1..7");
    // Swept strokes may place their weights on a finer lattice than the tool's: the change a
    // carve makes to worked clay follows the clay's detail, which the tool's own lattice
    // cannot express (a shallow size-6 carve on clay of strokes: 0.49..1.35 of its depth on
    // the tool's lattice, 0.97..1.10 two levels down; docs/placement.md "Finer lattices").
    // Adds go there too: carves alone on a finer lattice, adds on the tool's, let adds and
    // carves alternating over one spot grow opposite weights on the two lattices without
    // bound (max |w| 97 after 400 strokes, measured).
    if (op == ToolOp::Smooth && sculpture.config().placement == PlacementMode::Thesis)
        throw std::invalid_argument(
            "the smooth tool needs placement mode \"free\" or \"swept\" (thesis mode has unit "
            "weights only)");
    init(sculpture.config().placement == PlacementMode::Swept && op != ToolOp::Smooth
             ? std::max(1, level - sculpture.config().finerLatticeLevels)
             : level);
}

void StrokeBuilder::init(int lattice) {
    Sculpture& sculpture = mSculpture;
    const ToolOp op = mOp;
    mLattice = lattice;
    const ToolLevel& tl = sculpture.levels().level(mLattice);
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
        // the falloff sampled on the lattice; the deconvolution stencil undoes most of that
        // blur (the same at every level: R_k / h_k is). The targets use the stabilised stencil:
        // each stroke reads its targets from the field earlier strokes left, and the plain
        // one's negative response near the checkerboard frequencies made that loop unstable.
        // The fit's corrections keep the plain stencil: they are aimed at points between the
        // vertices, where its sharper response holds shallow grooves (size 7 at 20 % on the
        // sphere: 0.91 of the depth, 0.87-0.90 with the stabilised one), and they act only
        // near the old surface (docs/placement.md, "Stability").
        const HermiteFalloff& F = sculpture.levels().falloff();
        const double supportOverSpacing = tl.supportMm / tl.spacingMm;
        const std::vector<StencilTap> targets =
            deconvolutionStencil(F, supportOverSpacing, kDeconvolveSteps, true);
        const std::vector<StencilTap> corrections =
            deconvolutionStencil(F, supportOverSpacing, kDeconvolveSteps, false);
        std::map<std::array<int, 3>, Tap> merged;
        for (const StencilTap& t : targets)
            merged[t.offset].target = t.weight;
        for (const StencilTap& t : corrections)
            merged[t.offset].correction = t.weight;
        std::vector<std::pair<std::array<int, 3>, double>> taps;
        for (auto& [o, tap] : merged) {
            tap.offset = LatticeCoord{o[0], o[1], o[2]};
            mDeconvolve.push_back(tap);
            if (tap.correction != 0) taps.emplace_back(o, tap.correction);
            mDeconvolveReach = std::max(mDeconvolveReach,
                                        std::sqrt(double(o[0] * o[0] + o[1] * o[1] + o[2] * o[2])));
        }
        mTransfer = transferTable(taps, F, tl.spacingMm / tl.supportMm);
    }
}

StrokeBuilder::~StrokeBuilder() = default;

double StrokeBuilder::coarseChangeAt(const Vec3& pos, Vec3* gradient) const {
    if (!mCoarse) return 0;
    const HermiteFalloff& F = mSculpture.levels().falloff();
    const double support = mSculpture.levels().level(mCoarse->mLattice).supportMm;
    double change = 0;
    mCoarse->forEachDeltaNear(pos, [&](double delta, const Vec3& d, double dist, double u) {
        change += delta * F.value(u);
        if (gradient && dist > 0) *gradient += delta * F.derivative(u) / support * (d / dist);
    });
    return change;
}

FieldSample StrokeBuilder::probeLessCoarse(const Vec3& pos) {
    FieldSample s = mProbe->sample(pos);
    s.value += mSculpture.levels().iso();
    if (mCoarse) {
        Vec3 g(0.0);
        s.value -= coarseChangeAt(pos, &g);
        s.gradient -= g;
    }
    return s;
}

double StrokeBuilder::preStrokeRawSum(const LatticeCoord& v, const Vec3& pos) {
    double raw = mProbe->rawSum(pos) - coarseChangeAt(pos);
    if (mDeltas.empty()) return raw;
    const ToolLevel& tl = mSculpture.levels().level(mLattice);
    const HermiteFalloff& F = mSculpture.levels().falloff();
    for (const LatticeCoord& o : mStencil) {
        auto it = mDeltas.find(LatticeCoord{v.x + o.x, v.y + o.y, v.z + o.z});
        if (it == mDeltas.end()) continue;
        const double d = std::sqrt(double(o.x * o.x + o.y * o.y + o.z * o.z)) * tl.spacingMm;
        raw -= double(it->second) * F.value(d / tl.supportMm);
    }
    return raw;
}

namespace {
// Every vertex of a level's lattice whose support reaches `pos`: visit(coord, pos less the
// vertex, their distance).
template <class Fn>
void forEachVertexReaching(const ToolLevel& tl, const Vec3& pos, Fn&& visit) {
    const Vec3 q = pos / tl.spacingMm;
    const double r = tl.supportMm / tl.spacingMm;
    for (int x = int(std::ceil(q.x - r)); x <= int(std::floor(q.x + r)); ++x)
        for (int y = int(std::ceil(q.y - r)); y <= int(std::floor(q.y + r)); ++y)
            for (int z = int(std::ceil(q.z - r)); z <= int(std::floor(q.z + r)); ++z) {
                const Vec3 d = pos - Vec3(x, y, z) * tl.spacingMm;
                const double dist = glm::length(d);
                if (dist < tl.supportMm) visit(LatticeCoord{x, y, z}, d, dist);
            }
}

// The field at `pos` of one level's lattice weights, weightAt(coord) giving each (optional).
template <class WeightAt>
double latticeFieldAt(const ToolLevels& levels, int level, const Vec3& pos, WeightAt&& weightAt) {
    const ToolLevel& tl = levels.level(level);
    const HermiteFalloff& F = levels.falloff();
    double sum = 0;
    forEachVertexReaching(tl, pos, [&](const LatticeCoord& c, const Vec3&, double dist) {
        if (const std::optional<float> w = weightAt(c)) sum += *w * F.value(dist / tl.supportMm);
    });
    return sum;
}
}  // namespace

template <class Fn>
void StrokeBuilder::forEachDeltaNear(const Vec3& pos, Fn&& visit) const {
    if (mDeltas.empty()) return;
    const ToolLevel& tl = mSculpture.levels().level(mLattice);
    forEachVertexReaching(tl, pos, [&](const LatticeCoord& c, const Vec3& d, double dist) {
        const auto it = mDeltas.find(c);
        if (it != mDeltas.end()) visit(double(it->second), d, dist, dist / tl.supportMm);
    });
}

double StrokeBuilder::preStrokeValueAt(const Vec3& pos) {
    double raw = mProbe->rawSum(pos) - coarseChangeAt(pos);
    const HermiteFalloff& F = mSculpture.levels().falloff();
    forEachDeltaNear(
        pos, [&](double delta, const Vec3&, double, double u) { raw -= delta * F.value(u); });
    return raw - mSculpture.levels().iso();
}

FieldSample StrokeBuilder::preStrokeSampleAt(const Vec3& pos) {
    FieldSample s = probeLessCoarse(pos);
    const HermiteFalloff& F = mSculpture.levels().falloff();
    const double support = mSculpture.levels().level(mLattice).supportMm;
    forEachDeltaNear(pos, [&](double delta, const Vec3& d, double dist, double u) {
        s.value -= delta * F.value(u);
        if (dist > 0) s.gradient -= delta * F.derivative(u) / support * (d / dist);
    });
    return s;
}

FieldSample StrokeBuilder::preStrokeSample(const LatticeCoord& v, const Vec3& pos) {
    FieldSample s = probeLessCoarse(pos);
    if (mDeltas.empty()) return s;
    const ToolLevel& tl = mSculpture.levels().level(mLattice);
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
    // A weight beyond float range would make the field infinite or NaN around it for good:
    // the sample is refused instead (out_of_range: the session cancels the whole stroke and
    // says why, and the sculpture stays as it was).
    if (after && !std::isfinite(*after))
        throw std::out_of_range("a skeleton weight would leave the range of a float (level " +
                                std::to_string(mLattice) + " at lattice (" + std::to_string(v.x) +
                                ", " + std::to_string(v.y) + ", " + std::to_string(v.z) +
                                ")): the clay there is numerically broken");
    SkeletonStore& store = mSculpture.store();
    if (after)
        store.set(mLattice, v, *after);
    else
        store.erase(mLattice, v);
    mDeltas[v] += after.value_or(0.0f) - current.value_or(0.0f);
    auto [it, first] = mChangeIndex.try_emplace(v, mChanges.size());
    if (first)
        mChanges.push_back(SkeletonChange{mLattice, v, current, after});
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
    // A sample sweeps the tool along the segment from the last one: a segment kilometres long
    // (a script's typo) would visit lattice vertices by the hundred million and exhaust memory
    // (a 2 km size-1 segment took 6.4 GB before failing). Refused before anything is placed.
    // (A refinement's samples are the stroke's own, checked on the tool's lattice.)
    const double spacings =
        glm::length(p - a) /
        mSculpture.levels().level(mCoarse ? mCoarse->mLattice : mLattice).spacingMm;
    if (spacings > kMaxSegmentSpacings) {
        std::ostringstream msg;
        msg << "a stroke segment of " << glm::length(p - a) << " mm is more than one step can "
            << "sweep at size " << mLevel << " (" << kMaxSegmentSpacings << " lattice spacings, "
            << kMaxSegmentSpacings * mSculpture.levels().level(mLattice).spacingMm
            << " mm): split the stroke or use a larger size";
        throw std::invalid_argument(msg.str());
    }
    mLast = p;
    if (refinable()) mPath.push_back(p);
    mFinished = false;
    if (mOp == ToolOp::Smooth) return addSmoothSample(a, p);
    return mSculpture.config().placement == PlacementMode::Swept ? addSampleSwept(a, p)
                                                                 : addSampleOnTool(a, p);
}

double StrokeBuilder::levelField(int level, const Vec3& pos) const {
    return latticeFieldAt(mSculpture.levels(), level, pos,
                          [&](const LatticeCoord& c) { return mSculpture.store().get(level, c); });
}

double StrokeBuilder::leakingField(const Vec3& pos) const {
    return latticeFieldAt(mSculpture.levels(), mLattice, pos,
                          [&](const LatticeCoord& c) -> std::optional<float> {
                              const auto it = mLeaking.find(c);
                              if (it == mLeaking.end()) return std::nullopt;
                              return it->second;
                          });
}

double StrokeBuilder::checkerboardOf(const LatticeCoord& v) const {
    // The product of (1 - cos w) / 2 along each axis: 1 at the checkerboard, zero sum, and of
    // sixth order at zero, so the surface's own frequencies are left alone.
    double sum = 0;
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                const LatticeCoord u{v.x + dx, v.y + dy, v.z + dz};
                const auto it = mVisited.find(u);
                const std::optional<float> pre = it != mVisited.end()
                                                     ? it->second.preStroke
                                                     : mSculpture.store().get(mLattice, u);
                sum += (dx ? -0.25 : 0.5) * (dy ? -0.25 : 0.5) * (dz ? -0.25 : 0.5) *
                       pre.value_or(0.0f);
            }
    return sum;
}

double StrokeBuilder::fitCorrection(const Target& t) {
    // Closed loop on the vertex's aim point, where the new surface must pass: the base weights
    // (the targets deconvolved and clamped) give some change of the field there; the surface
    // needs the change that brings the pre-stroke field there to c (the tool's extreme point
    // inside the material) or keeps it at c (the old surface next to a carve that does not
    // reach it). Between vertices, on narrow grooves and caps, the base falls short, and
    // where the tool grazes the surface it spills past the groove's end (the lattice spreads
    // both). The missing change is spread over the vertices around the aim as a correction of
    // their targets, each vertex taking its share from its own aim point and the
    // normalisation assuming its neighbours' aims miss the same (their shares add up there
    // through the transfer H, which predicts the field between vertices). Everything is a
    // function of the final targets, so the result does not depend on sample spacing. An add
    // is one-sided: its fit only raises, never takes back what the targets give (taking back
    // left gaps at the base of spines that start inside clay); a carve's fit also takes back,
    // the weights being clamped so that it never raises the field.
    if (!t.aim) return 0;
    const ToolLevel& tl = mSculpture.levels().level(mLattice);
    const double h = tl.spacingMm;
    const SweptTransfer& H = *mTransfer;
    const HermiteFalloff& F = mSculpture.levels().falloff();
    const double need = t.need;
    const bool add = mOp == ToolOp::Add;
    if (add && need <= 0) return 0;  // the tool's top is inside the material already
    // Only near the old surface (to first order within kFitReachOverRadius tool radii of the
    // aim, kCarveFitReachOverRadius for a carve): far from it (a stroke in the tail of other clay,
    // a tunnel deep in material) the targets alone give the tool's size, and a fit there, aimed at
    // a point at the edge of the swept volume (the tip of a stroke's end cap), raised a whole blob
    // around it (a level-6 column above the snowman's head came out 1.3 times the tool's radius at
    // its end).
    // (In empty space the aim is the tool's own surface: the fit applies there always.)
    if (!t.emptyAim && std::abs(need) > t.controlGrad *
                                            (add ? kFitReachOverRadius : kCarveFitReachOverRadius) *
                                            0.5 * mSculpture.levels().level(mLevel).diameterMm)
        return 0;
    const Vec3 q = *t.aim / h;  // lattice units
    double predicted = 0, norm = 0;
    const double r = std::max(SweptTransfer::kReach, tl.supportMm / h);
    for (int x = int(std::ceil(q.x - r)); x <= int(std::floor(q.x + r)); ++x)
        for (int y = int(std::ceil(q.y - r)); y <= int(std::floor(q.y + r)); ++y)
            for (int z = int(std::ceil(q.z - r)); z <= int(std::floor(q.z + r)); ++z) {
                const Vec3 u(x, y, z);
                const Vec3 d = q - u;
                const double d2 = glm::dot(d, d);
                if (d2 >= r * r) continue;
                const Target* nb = mTargets.find(LatticeCoord{x, y, z});
                if (!nb) continue;
                const double dist = std::sqrt(d2) * h;
                if (dist < tl.supportMm) predicted += nb->base * F.value(dist / tl.supportMm);
                if (nb->share > 0) norm += nb->share * H(d);
            }
    // Each vertex's share is normalised by what the shares around its aim realise there; where
    // few vertices near the aim take a share (on a lattice finer than the tool's, aims lie up
    // to 9 spacings from their vertices and shares vanish beyond 6), that sum nears zero and
    // the quotient ran away (adds and carves on a lattice two levels down blew the weights up
    // to 1e14 within 40 strokes). A floor keeps a vertex's correction within a few times the
    // shortfall; on the tool's lattice it acts at fewer than 1 in 1 000 aims. (A sum that is
    // not positive means the shares cannot reach the aim at all: no correction.)
    if (norm <= 1e-9) return 0;
    norm = std::max(norm, kFitNormFloor);
    // In empty space there is no clay to leave a gap in: the fit there takes back too (with
    // aims at every vertex in empty space, one-sided pushed a stroke's radius to 1.052 of the
    // tool's, two-sided kept it within 1.047).
    // (The refinement's fit takes back as its targets do.)
    const bool oneSided = add && !t.emptyAim && !mCoarse;
    const double aimed = mCoarse ? t.residualNeed : need;
    if (oneSided && aimed <= predicted) return 0;
    const double f = t.change + (aimed - predicted) * t.share / norm;
    return oneSided ? std::max(f, 0.0) - t.change : f - t.change;
}

EditResult StrokeBuilder::addSampleSwept(const Vec3& a, const Vec3& p) {
    const ToolLevels& levels = mSculpture.levels();
    const ToolLevel& tl = levels.level(mLattice);  // the lattice the weights live on
    const HermiteFalloff& F = levels.falloff();
    const double radius = 0.5 * levels.level(mLevel).diameterMm;  // the tool's
    const double margin = kSweptMarginOverRadius * radius;
    const double iso = levels.iso();
    const double uIso = F.inverse(iso);

    // The field of a fresh stroke at distance l from the path: c on the tool's surface, F's
    // shape, zero at the margin; slopeAtTool is its slope there (per mm).
    auto freshField = [&](double l) {
        return F.value(std::max(0.0, uIso + (1 - uIso) * (l - radius) / margin));
    };
    const double slopeAtTool = -F.derivative(uIso) * (1 - uIso) / margin;
    // A smooth signed distance to the swept tool's surface (mm; < 0 inside), saturating at
    // sMax at the margin: the fresh field read as a distance.
    const double sMax = iso / slopeAtTool;
    // Target fields stay within this of c: nothing deeper matters to the surface (kTargetBand).
    const double band = kTargetBand * (freshField(0) - iso);
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
    auto targetChange = [&](const Target& t, const Vec3& pos) {
        const double s = (iso - freshField(t.lateral)) / slopeAtTool;
        // The rule reads the pre-stroke field at the vertex as a depth below the old surface,
        // (phi - c) / G. That first-order reading is poor a tool radius or more inside
        // undulating clay, where the field flattens (on the slab of strokes it read vertices a
        // size-5 tool radius under the surface up to 1.7 mm too deep, and a 20 % groove came
        // out up to 0.7 mm too deep over them). Where the control point q lies within a tool
        // radius of the surface and nearer it than the vertex, the depth is read at q,
        // (phi(q) - c) / |grad phi(q)|, and carried to the vertex along the normal.
        double phi = t.phi;
        if (t.control && t.controlGrad > 0 && t.grad > 0) {
            const double dv = (t.phi - iso) / t.grad;
            const double dq = (t.controlPhi - iso) / t.controlGrad;
            if (std::abs(dq) < std::abs(dv) && std::abs(dq) <= kDepthFromControlReach * radius)
                phi = iso + t.grad * (dq + glm::dot(pos - *t.control, t.gradient) / t.grad);
            // The reading refines how deep the vertex is, never which side of the old surface
            // it is on: its own field says that exactly. In flat worked clay the reading taken
            // across a carved tunnel put vertices of the empty tunnel inside material, and an
            // add over it left 65 % of its change undone (12 % now).
            if ((phi - iso) * (t.phi - iso) < 0) phi = t.phi;
        }
        const bool add = mOp == ToolOp::Add;
        const double slope = std::max(t.grad, (add ? iso - t.phi : t.phi - iso) / sMax);
        // (The refinement reads the vertex's own field: its vertices that decide the surface
        // lie near it, where the field is its own best reading. With the depth reading, clay
        // built with refinement carved shallow grooves of sizes 1-5 0.41..1.53 deep, 0.82..1.25
        // without it.)
        const double from = slope == t.grad && !mCoarse ? phi : t.phi;
        const double want =
            add ? std::clamp(iso - slope * s - from, 0.0, std::max(0.0, iso + band - t.phi))
                : std::clamp(iso + slope * s - from, std::min(0.0, iso - band - t.phi), 0.0);
        const double deadBand = kDeadBand * slope * tl.spacingMm;
        // Outside the tool material stays material (a carve) and empty space stays empty (an
        // add): the field moves at most as the flat-field rule moves it, (phi - c) s / sMax
        // towards c (the refinement's bound, below).
        auto sided = [&](double w) {
            if (s > 0 && !add && t.phi > iso)
                return std::max(w, -(t.phi - iso) * (1 - std::min(1.0, s / sMax)));
            if (s > 0 && add && t.phi < iso)
                return std::min(w, (iso - t.phi) * (1 - std::min(1.0, s / sMax)));
            return w;
        };
        // The refinement places what the coarse pass left between the target and its realised
        // change, both ways, by the same dead band on its own lattice.
        if (mCoarse) {
            // Bounded to the tool's side: the clay's fine residuals leave fields that are steep
            // under the surface and flat beneath, where a stroke's change reaching past the
            // tool opened pockets inside the clay (the worked detail's first 30 strokes:
            // enclosed voids of up to 82 mm3 without the bound, 14 with it; the same bound on
            // the tool's pass too changed nothing, 14.3).
            const double residual = sided(want) - coarseChangeAt(pos) + t.shed;
            return std::abs(residual) < deadBand ? 0.0 : residual;
        }
        // The fine weights this stroke's refinement sheds, to take over.
        if (add) return std::abs(t.phi) > 1e-9 && want + t.shed < deadBand ? 0.0 : want + t.shed;
        return -(want + t.shed) < deadBand ? 0.0 : want + t.shed;
    };

    // The path's closest point to a vertex: on either segment with a mirror plane (on a tie the
    // midpoint, so a vertex on the plane stays symmetric).
    const Vec3 am = mirrored(a, mMirror), pm = mirrored(p, mMirror);
    // The path's closest point to x and the direction from it to the swept tool's extreme
    // point along the unit vector n: across the path where x lies beside a segment (the swept
    // tool is a tube there), n itself beyond a segment's ends (a sphere). On either segment
    // with a mirror plane (on a tie the midpoints, so a vertex on the plane stays symmetric).
    auto onSegment = [&](const Vec3& x, const Vec3& n, const Vec3& s0,
                         const Vec3& s1) -> std::pair<Vec3, Vec3> {
        const Vec3 ab = s1 - s0;
        const double len2 = glm::dot(ab, ab);
        if (len2 <= 0) return {s0, n};
        const double tau = glm::dot(x - s0, ab) / len2;
        const Vec3 foot = s0 + ab * std::clamp(tau, 0.0, 1.0);
        if (tau < 0 || tau > 1) return {foot, n};
        const Vec3 t = ab / std::sqrt(len2);
        const Vec3 across = n - glm::dot(n, t) * t;
        const double l = glm::length(across);
        if (l > 1e-6) return {foot, across / l};
        // n along the stroke: a plunge down the surface's normal (found by QA: straight down the
        // initial sphere's axis a carve left a plug of clay floating in the hole's mouth). Every
        // point of the tube's circle there is as far along n, and n itself points inside the
        // tube, where the fit held the field at c: the new surface passes beside the vertex,
        // at the circle's point nearest it. A vertex on the path has none (no direction).
        const Vec3 lateral = x - foot;
        const double ll = glm::length(lateral);
        return {foot, ll > 1e-6 * tl.spacingMm ? lateral / ll : Vec3(0.0)};
    };
    // Whether a vertex lies as near the mirrored path as the original (to rounding): it is
    // then decided alike for both, so that it stays symmetric.
    auto mirrorTie = [&](double df, double dg) {
        return std::abs(df - dg) <= 1e-9 * (df + dg + tl.spacingMm);
    };
    auto extremeOf = [&](const Vec3& x, const Vec3& n) -> std::pair<Vec3, Vec3> {
        const auto f = onSegment(x, n, a, p);
        if (mMirror == MirrorAxis::None) return f;
        const auto g = onSegment(x, n, am, pm);
        const double df = glm::length(x - f.first), dg = glm::length(x - g.first);
        if (mirrorTie(df, dg)) {
            // A vertex on the plane, as near the path as its image. Where the two feet are one
            // point (the path crosses the plane there), that point, with the directions
            // averaged so the vertex stays symmetric. Where they are apart (a stroke beside
            // the plane and its image, the vertex between them), either one: both give the same
            // value by symmetry, while their midpoint was the extreme point of a tool that is
            // not there, on the plane (found by QA: mirrored eye sockets 16 mm apart joined in
            // a trench 5.7 mm deep between them, deeper than either).
            if (glm::length(f.first - g.first) > 1e-9 * (df + tl.spacingMm)) return f;
            const Vec3 d = f.second + g.second;
            const double l = glm::length(d);
            const bool none = f.second == Vec3(0.0) && g.second == Vec3(0.0);
            return {0.5 * (f.first + g.first), l > 1e-9 ? d / l : none ? Vec3(0.0) : n};
        }
        return df < dg ? f : g;
    };
    // The control point: the swept tool's extreme point into the material (carve) or out of
    // it (add) along the pre-stroke normal at the vertex, the tool centre being the path's
    // closest point to the vertex. Beside a segment that is the tube's extreme point, across
    // the path: the sphere's own, where the surface slopes along the stroke, lies inside the
    // swept tube (on the slab's edge a size-7 groove at 100 % came out 0.71 of its depth). The
    // new surface must pass through it wherever it lies on the old material's far side. In
    // empty space, where there is no normal, an add's is the tool's surface point beyond the
    // vertex (below).
    auto controlOf = [&](Target& t, const Vec3& pos) -> std::optional<Vec3> {
        // (A field that changes by less than 1e-4 over a tool radius is empty space: what is
        // left of the stroke's own subtracted deltas is rounding, with no direction.)
        t.emptyAim = false;
        if (t.grad * radius < 1e-4) {
            // In empty space an add's ends are the swept tool's own balls: there the control
            // point is the tool's surface point on the way from the path's end to the vertex.
            // The targets alone left a dab 5 % small (0.951 of the tool's radius, 0.935..0.979
            // over directions: a ball is the swept shape the lattice blurs most) and a stroke's
            // end caps 0.94 long; with the fit aiming there, 1.002 (0.989..1.014) and 1.02. Only
            // the caps: at the first sample (a dab until the tool moves; the vertices beside
            // the path drop their aims as it passes them) and at the stroke's end (finish()).
            // The tube between keeps its targets (radius 0.958..1.047 of the tool's): aiming
            // there too cost 0.32 instead of 0.07 ms a sample and the mesh trailed a 90 Hz
            // stroke by 34-48 instead of 22-31 ms at p99 (the moving end's corrections
            // rewritten every sample). A carve has nothing to remove in empty space.
            if (mOp != ToolOp::Add || a != p) return std::nullopt;
            // The nearer ball's centre; with a mirror plane a vertex as near the mirrored ball
            // as the original takes no aim, so that it stays symmetric.
            Vec3 centre = a;
            if (mMirror != MirrorAxis::None) {
                const double df = glm::length(pos - a), dg = glm::length(pos - am);
                if (mirrorTie(df, dg)) return std::nullopt;
                if (dg < df) centre = am;
            }
            const Vec3 d = pos - centre;
            const double l = glm::length(d);
            if (l < 1e-6 * radius) return std::nullopt;
            mAnyControl = true;
            t.emptyAim = true;
            return centre + d * (radius / l);
        }
        // The gradient points into the material.
        const Vec3 n = t.gradient * ((mOp == ToolOp::Add ? -1.0 : 1.0) / t.grad);
        const auto [foot, d] = extremeOf(pos, n);
        if (d == Vec3(0.0)) return std::nullopt;  // on the path of a plunge: no extreme point
        mAnyControl = true;
        return foot + d * radius;
    };

    auto setControl = [&](Target& t, const Vec3& pos) {
        t.control = controlOf(t, pos);
        t.aim.reset();
        t.share = 0;
        if (!t.control) return;
        const FieldSample qs = preStrokeSampleAt(*t.control);
        t.controlPhi = qs.value;
        t.controlGrad = glm::length(qs.gradient);
        t.aim = t.control;
        t.keepAim = false;
        t.need = iso - t.controlPhi;
        if (mOp == ToolOp::Carve && t.need > 0) {
            // The tool does not reach the old surface along this normal: the old surface
            // point beyond q (to first order) must stay where it is, so that the groove does
            // not spill past where the tool leaves the clay.
            if (t.controlGrad <= 1e-12 || t.need / t.controlGrad > kKeepSurfaceReach * radius) {
                t.aim.reset();
                return;
            }
            t.aim = *t.control + qs.gradient * (t.need / (t.controlGrad * t.controlGrad));
            t.need = 0;
            t.keepAim = true;
            // The refinement's fit, unclamped, would hold the old surface there even where the
            // first-order step put it inside the swept tool (beside the slab's edge, deep carves
            // came out with lumps of clay left in the groove: size 6 at 140 % 0.38 of its depth).
            if (mCoarse && insideSweptTool(*t.aim, radius)) {
                t.aim.reset();
                return;
            }
            if (glm::length(*t.aim - pos) > 2 * radius + margin) {
                t.aim.reset();
                return;
            }
        }
        double width = kFitShareWidth;
        if (mOp == ToolOp::Carve) {
            const double g = t.controlGrad / slopeAtTool;
            const double steep =
                std::clamp((g - kFlatCarveBelow) / (kSteepCarveAbove - kFlatCarveBelow), 0.0, 1.0);
            width = kFlatCarveShareWidth + steep * (kFitShareWidth - kFlatCarveShareWidth);
        }
        // The refinement's lattice is finer than the tool's: a share as wide in its spacings
        // spreads a correction a quarter as far, and the narrowest is enough (2.5 and 1.5 left
        // shallow carves on clay of strokes up to 1.32 and 1.29 deep at size 4, 1.0 1.24).
        if (mCoarse) width = kFitShareWidthRefining;
        t.share = std::max(0.0, (*mTransfer)((*t.aim - pos) / (tl.spacingMm * width)));
        // What the tool's pass realised at the aim, and the fine weights' shed field there,
        // are the refinement's to make up (both final: it runs after that pass).
        if (mCoarse)
            t.residualNeed = t.need - coarseChangeAt(*t.aim) + kRefineLeak * leakingField(*t.aim);
    };

    std::vector<LatticeCoord> touched;  // new, or their closest approach changed
    for (const SweptVertex& sv : sweptWithMirror(tl.spacingMm, a, p, radius + margin, mMirror)) {
        auto [target, first] = mTargets.tryEmplace(sv.coord);
        Target& t = *target;
        const Vec3 pos = vertexPos(sv.coord, tl.spacingMm);
        if (first) {
            if (mDeferFit) mTargetCoords.push_back(sv.coord);
            const FieldSample fs = preStrokeSample(sv.coord, pos);
            t.phi = fs.value;
            t.gradient = fs.gradient;
            t.grad = glm::length(fs.gradient);
            t.lateral = sv.lateralMm;
            // kRefineLeak: the fine pass puts back what the fine weights shed, the tool's pass
            // takes it over (both pre-stroke, so once per target).
            t.shed = mCoarse       ? kRefineLeak * leakingField(pos)
                     : refinable() ? kRefineLeak * levelField(refineLattice(), pos)
                                   : 0.0;
            setControl(t, pos);
            t.change = targetChange(t, pos);
            touched.push_back(sv.coord);
        } else if (sv.lateralMm < t.lateral) {
            t.lateral = sv.lateralMm;
            setControl(t, pos);
            t.change = targetChange(t, pos);
            touched.push_back(sv.coord);
        } else if (mFinishingCap && !t.emptyAim && sv.lateralMm <= t.lateral + 1e-9 * radius &&
                   t.grad * radius < 1e-4) {
            // The path's end is this vertex's closest point (the end cap; to rounding: the
            // last segment's end a + (p - a) need not be p's bits), in empty space.
            setControl(t, pos);
            if (t.emptyAim) touched.push_back(sv.coord);
        }
    }
    // Each sample collects three sets of targets (whose base weight to recompute, whose fit,
    // whose weight): a target joins a set once, marked with the sample's number (a hash set
    // per sample cost a tenth of placement on a finer lattice).
    const uint32_t sampleMark = ++mSampleMark;
    std::vector<LatticeCoord> affected;  // vertices whose weight must be recomputed
    auto markAffected = [&](const LatticeCoord& v, Target& t) {
        if (t.affectedMark == sampleMark) return;
        t.affectedMark = sampleMark;
        affected.push_back(v);
    };
    // Base weights: the targets deconvolved and clamped, recomputed wherever the deconvolution
    // stencil reaches a changed target. (Each is computed from the targets' changes alone, so
    // the order does not matter.)
    std::vector<std::pair<LatticeCoord, Target*>> baseList;
    for (const LatticeCoord& u : touched)
        for (const Tap& tap : mDeconvolve) {
            const LatticeCoord v{u.x + tap.offset.x, u.y + tap.offset.y, u.z + tap.offset.z};
            Target* t = mTargets.find(v);
            if (!t || t->baseMark == sampleMark) continue;
            t->baseMark = sampleMark;
            baseList.emplace_back(v, t);
        }
    for (const LatticeCoord& v : touched)
        markAffected(v, *mTargets.find(v));
    for (const auto& [v, t] : baseList) {
        double w = 0;
        for (const Tap& tap : mDeconvolve) {
            const Target* u = mTargets.find(
                LatticeCoord{v.x - tap.offset.x, v.y - tap.offset.y, v.z - tap.offset.z});
            if (u) w += tap.target * u->change;
        }
        w = clampToOp(w);
        if (w == t->base) continue;
        t->base = w;
        markAffected(v, *t);
    }
    // The corrections follow the base weights within the support of a vertex's control point
    // and the targets and control points within the transfer's reach of it; the control
    // point lies within 2 radius + margin of the vertex. A carve in empty space has no
    // control points and no corrections. (A correction reads the base weights and shares
    // around it, never another correction, so the order does not matter.)
    // The refinement fits too, on what the tool's pass left at each aim (Target::residualNeed):
    // its targets alone, read at the vertices, carved shallow grooves on the sphere up to 1.12
    // of their depth across the lattice's diagonal (0.97..1.04 with the fit). (Fitted on the
    // whole need, the aims the tool's pass had met were counted twice: grooves 1.3-2.2 deep.)
    if (!touched.empty() && mAnyControl && !mDeferFit) {
        // The aim lies within 2 radius + margin of the vertex (the tool's extreme point, or
        // the old surface next to a carve, dropped beyond).
        const double aimReach = 2 * radius + margin;
        const double reach = (radius + margin) +
                             std::max(mDeconvolveReach * tl.spacingMm + tl.supportMm,
                                      SweptTransfer::kReach * tl.spacingMm) +
                             aimReach;
        for (const SweptVertex& sv : sweptWithMirror(tl.spacingMm, a, p, reach, mMirror)) {
            Target* t = mTargets.find(sv.coord);
            if (!t || t->fitMark == sampleMark) continue;
            t->fitMark = sampleMark;
            const double c = fitCorrection(*t);
            if (c == t->correction) continue;
            t->correction = c;
            const LatticeCoord& u = sv.coord;
            for (const Tap& tap : mDeconvolve) {
                const LatticeCoord v{u.x + tap.offset.x, u.y + tap.offset.y, u.z + tap.offset.z};
                if (Target* n = mTargets.find(v)) markAffected(v, *n);
            }
        }
    }
    return writeWeights(affected);
}

// Adding never lowers the field and carving never raises it: the deconvolution's negative
// side lobes would otherwise notch the clay next to an added stroke (and raise it next to a
// carve), and they add ripple. (The refinement's residual takes back as well as removes: it
// mends where the tool's lattice carved too deep as well as too shallow. Clamped, shallow
// carves on clay of strokes came out up to 1.52 of their depth.)
double StrokeBuilder::clampToOp(double w) const {
    if (mCoarse) return w;
    return mOp == ToolOp::Add ? std::max(w, 0.0) : std::min(w, 0.0);
}

EditResult StrokeBuilder::writeWeights(std::vector<LatticeCoord>& affected) {
    const ToolLevel& tl = mSculpture.levels().level(mLattice);
    SkeletonStore& store = mSculpture.store();
    // In coordinate order, so the writes (and a mesher's replay of them) do not depend on the
    // order the sets were collected in.
    std::sort(affected.begin(), affected.end());

    EditResult result;
    Aabb changed;
    for (const LatticeCoord& v : affected) {
        // The base weight plus the deconvolved corrections, clamped again.
        double w = mTargets.find(v)->base;
        for (const Tap& tap : mDeconvolve) {
            const Target* u = mTargets.find(
                LatticeCoord{v.x - tap.offset.x, v.y - tap.offset.y, v.z - tap.offset.z});
            if (u) w += tap.correction * u->correction;
        }
        w = clampToOp(w);
        // After the clamp: before it, an add could shed only the checkerboard's negative half
        // (the field it lowers is the blur's -0.05 of the weights shed).
        if (mCoarse || mLattice < mLevel) w -= kFineCheckerboardDecay * checkerboardOf(v);
        const std::optional<float> current = store.get(mLattice, v);
        auto [vit, first] = mVisited.try_emplace(v, Visit{current, 0});
        const std::optional<float> before = vit->second.preStroke;
        std::optional<float> after = before;
        const double keep = mCoarse && mLeaking.count(v) ? 1.0 - kRefineLeak : 1.0;
        if (before || std::abs(w) > 1e-9) after = float(keep * double(before.value_or(0.0f)) + w);
        if (after == current) {
            mHeld.erase(v);
            continue;
        }
        if (std::abs(double(after.value_or(0.0f)) - double(current.value_or(0.0f))) < mHoldBelow) {
            mHeld[v] = after;
            continue;
        }
        mHeld.erase(v);
        setWeight(v, current, after);
        const Vec3 pos = vertexPos(v, tl.spacingMm);
        noteChanged(result, changed, pos);
    }
    result.changedRegion = changed.padded(tl.supportMm);
    result.supportMm = tl.supportMm;
    return result;
}

void StrokeBuilder::fitDeferred() {
    // Every target once, on the final targets: the per-sample fit re-fits each target whenever
    // a sample passes within its reach, and on the refinement's lattice (four times finer) that
    // cost more than the rest of the refinement (a size-4 carve's pen lift 43 ms against 30).
    const uint32_t mark = ++mSampleMark;
    std::vector<LatticeCoord> affected;
    if (mAnyControl)
        for (const LatticeCoord& u : mTargetCoords) {
            Target& t = *mTargets.find(u);
            const double c = fitCorrection(t);
            if (c == t.correction) continue;
            t.correction = c;
            for (const Tap& tap : mDeconvolve) {
                const LatticeCoord v{u.x + tap.offset.x, u.y + tap.offset.y, u.z + tap.offset.z};
                Target* n = mTargets.find(v);
                if (!n || n->affectedMark == mark) continue;
                n->affectedMark = mark;
                affected.push_back(v);
            }
        }
    mDeferFit = false;
    mTargetCoords.clear();
    writeWeights(affected);
}

std::vector<SkeletonChange> StrokeBuilder::takeChanges() {
    if (!mFinished && !mChanges.empty())
        throw std::logic_error(
            "StrokeBuilder::takeChanges before finish(): the stroke's end cap "
            "and held-back changes would be missing");
    return std::move(mChanges);
}

int StrokeBuilder::refineLattice() const {
    // As many of the k levels as there are: size 2 at k = 2 refines on level 1.
    return std::max(1, mLattice - mSculpture.config().refineLevels);
}

bool StrokeBuilder::refinable() const {
    // Sizes with fewer than k levels below refine on those there are. (Before the refinement
    // had its own fit, one level down was worse than none: size 2 at k = 2 carved 20 % grooves
    // on the sphere 0.78 of their depth, 0.95 unrefined. With it, 0.95..1.06, and on clay of
    // strokes 0.93..1.13 against 0.98..1.27.) Level 1 has none.
    return mOp != ToolOp::Smooth && !mCoarse &&
           mSculpture.config().placement == PlacementMode::Swept &&
           mSculpture.config().refineLevels > 0 && refineLattice() < mLattice;
}

bool StrokeBuilder::insideSweptTool(const Vec3& x, double radius) const {
    const std::vector<Vec3>& path = mCoarse ? mCoarse->mPath : mPath;
    auto near = [&](const Vec3& a, const Vec3& b) {
        const Vec3 ab = b - a;
        const double len2 = glm::dot(ab, ab);
        const double tau = len2 > 0 ? std::clamp(glm::dot(x - a, ab) / len2, 0.0, 1.0) : 0.0;
        return glm::length(x - (a + tau * ab)) < radius;
    };
    for (size_t i = 0; i < path.size(); ++i) {
        const Vec3& a = path[i == 0 ? 0 : i - 1];
        if (near(a, path[i])) return true;
        if (mMirror != MirrorAxis::None && near(mirrored(a, mMirror), mirrored(path[i], mMirror)))
            return true;
    }
    return false;
}

bool StrokeBuilder::refines() const {
    return refinable() && !mPath.empty();
}

void StrokeBuilder::startRefinement() {
    mRefineStart = finishOnLattice();
    mFine.reset(new StrokeBuilder(mSculpture, mOp, mLevel, mMirror, refineLattice(), this));
    // Every write waits for finish(): the samples only read (the store less the coarse pass),
    // so they may run off the caller's thread, and the same bits come out either way.
    mFine->holdBackChangesBelow(std::numeric_limits<double>::infinity());
}

void StrokeBuilder::sampleRefinement() {
    // The fine weights within the stroke's reach, as they were before it (the fine pass writes
    // nothing before finish()): each sheds kRefineLeak of itself.
    StrokeBuilder& fine = *mFine;
    const double spacing = mSculpture.levels().level(fine.mLattice).spacingMm;
    const double radius = 0.5 * mSculpture.levels().level(mLevel).diameterMm;
    const double reach = (1 + kSweptMarginOverRadius) * radius;
    for (size_t i = 0; i < mPath.size(); ++i)
        for (const SweptVertex& sv :
             sweptWithMirror(spacing, mPath[i == 0 ? 0 : i - 1], mPath[i], reach, mMirror))
            if (const std::optional<float> w = mSculpture.store().get(fine.mLattice, sv.coord))
                fine.mLeaking.emplace(sv.coord, *w);
    fine.mDeferFit = true;
    for (const Vec3& p : mPath)
        fine.addSample(p);
    fine.fitDeferred();
    // Those the samples did not reweigh only shed it (in coordinate order, as every write).
    std::vector<std::pair<LatticeCoord, float>> rest(fine.mLeaking.begin(), fine.mLeaking.end());
    std::sort(rest.begin(), rest.end(),
              [](const auto& l, const auto& r) { return l.first < r.first; });
    for (const auto& [v, w] : rest)
        if (fine.mVisited.emplace(v, Visit{w, 0}).second)
            fine.mHeld[v] = float((1.0 - kRefineLeak) * double(w));
    mFineSampled = true;
}

EditResult StrokeBuilder::finish() {
    if (mRefined || !refines()) return finishOnLattice();
    if (!mFine) startRefinement();
    if (!mFineSampled) sampleRefinement();
    EditResult result = std::move(mRefineStart);
    const EditResult fine = mFine->finish();
    // The mesher re-meshes around each point within one support: the coarse lattice's covers
    // the fine's.
    result.changedRegion.expand(fine.changedRegion);
    result.changedVertices += fine.changedVertices;
    result.changedPoints.insert(result.changedPoints.end(), fine.changedPoints.begin(),
                                fine.changedPoints.end());
    result.supportMm = std::max(result.supportMm, fine.supportMm);
    // Another lattice's vertices: they join the stroke's changes after the coarse ones, so
    // undo (backwards) and redo (forwards) hold.
    for (SkeletonChange& c : mFine->takeChanges())
        mChanges.push_back(std::move(c));
    mFine.reset();
    mRefined = true;
    return result;
}

EditResult StrokeBuilder::finishOnLattice() {
    EditResult result;
    // A swept add's end cap in empty space is fitted to the tool's ball now that it stays
    // where it is (addSampleSwept: during the stroke only the first sample's are).
    if (mOp == ToolOp::Add && mLast && mSculpture.config().placement == PlacementMode::Swept) {
        mFinishingCap = true;
        try {
            result = addSampleSwept(*mLast, *mLast);
        } catch (...) {
            mFinishingCap = false;
            throw;
        }
        mFinishingCap = false;
    }
    if (mOp == ToolOp::Smooth && !mFinished && mSculpture.config().smoothKeepsVolume) {
        if (mSmoothFinish == SmoothFinish::NotStarted) prepareSmoothedVolume();
        if (mSmoothFinish == SmoothFinish::Prepared) estimateSmoothedVolume();
        result = applySmoothedVolume();
    }
    mFinished = true;
    if (mHeld.empty()) return result;
    std::vector<std::pair<LatticeCoord, std::optional<float>>> held(mHeld.begin(), mHeld.end());
    mHeld.clear();
    // In coordinate order, so the writes (and a mesher's replay of them) do not depend on the
    // hash table's.
    std::sort(held.begin(), held.end(),
              [](const auto& l, const auto& r) { return l.first < r.first; });
    const ToolLevel& tl = mSculpture.levels().level(mLattice);
    Aabb changed;
    for (const auto& [v, after] : held) {
        const std::optional<float> current = mSculpture.store().get(mLattice, v);
        if (after == current) continue;
        setWeight(v, current, after);
        noteChanged(result, changed, vertexPos(v, tl.spacingMm));
    }
    result.changedRegion.expand(changed.padded(tl.supportMm));
    result.supportMm = tl.supportMm;
    return result;
}

EditResult StrokeBuilder::addSampleOnTool(const Vec3& a, const Vec3& p) {
    const ToolLevels& levels = mSculpture.levels();
    const ToolLevel& tl = levels.level(mLattice);
    const double radius = 0.5 * tl.diameterMm;
    const double iso = levels.iso();
    const bool thesis = mSculpture.config().placement == PlacementMode::Thesis;
    SkeletonStore& store = mSculpture.store();

    EditResult result;
    Aabb changed;
    for (const SweptVertex& sv : sweptWithMirror(tl.spacingMm, a, p, radius, mMirror)) {
        const std::optional<float> current = store.get(mLattice, sv.coord);
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
    const bool keepVolume = mSculpture.config().smoothKeepsVolume;
    std::vector<SkeletonChange> sampleChanges;  // this sample's, for the volume's preview
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
            if (keepVolume && !after) mSmoothDiffused[size_t(level - 1)].erase(sv.coord);
            if (keepVolume && after) {
                const auto [at, fresh] =
                    mSmoothDiffused[size_t(level - 1)].try_emplace(sv.coord, *after);
                if (fresh)
                    mSmoothOrder.emplace_back(level, sv.coord);
                else
                    at->second = *after;
                sampleChanges.push_back(SkeletonChange{level, sv.coord, pre.at(sv.coord), after});
            }
        }
    }
    if (!sampleChanges.empty()) {
        // A vertex decided twice in one sample (nearer the mirror image's segment) once, last.
        std::unordered_map<LatticeCoord, size_t, LatticeCoordHash> last[kLevelCount];
        std::vector<SkeletonChange> once;
        for (const SkeletonChange& c : sampleChanges) {
            const auto [it, first] = last[c.level - 1].try_emplace(c.coord, once.size());
            if (first)
                once.push_back(c);
            else
                once[it->second] = c;
        }
        previewSmoothedVolume(once, result, changed);
    }
    result.changedRegion = changed.padded(support);
    result.supportMm = support;
    return result;
}

void StrokeBuilder::previewSmoothedVolume(const std::vector<SkeletonChange>& sampleChanges,
                                          EditResult& result, Aabb& changed) {
    // The store holds the diffusion's weights for these vertices now (written just before).
    const VolumeKeepingShift keep = volumeKeepingShift(mSculpture, sampleChanges, 1.0, 0);
    if (keep.shift == 0.0) return;
    SkeletonStore& store = mSculpture.store();
    for (size_t n = 0; n < sampleChanges.size(); ++n) {
        const SkeletonChange& c = sampleChanges[n];
        const float shown = float(double(*c.after) + keep.shift * keep.moves[n]);
        if (shown == *c.after) continue;
        store.set(c.level, c.coord, shown);
        mChanges.push_back(SkeletonChange{c.level, c.coord, c.after, shown});
        noteChanged(result, changed,
                    vertexPos(c.coord, mSculpture.levels().level(c.level).spacingMm));
    }
}

std::function<void()> StrokeBuilder::beginFinish() {
    if (!mRefined && refines()) {
        if (mFine) return {};
        startRefinement();
        return [this] { sampleRefinement(); };
    }
    if (mOp != ToolOp::Smooth || mFinished || !mSculpture.config().smoothKeepsVolume ||
        mSmoothFinish != SmoothFinish::NotStarted)
        return {};
    prepareSmoothedVolume();
    if (mSmoothNet.empty()) {
        mSmoothFinish = SmoothFinish::Estimated;  // shift 0: nothing to estimate
        return {};
    }
    return [this] { estimateSmoothedVolume(); };
}

void StrokeBuilder::prepareSmoothedVolume() {
    // From the diffusion's own weights, whatever the samples' previews wrote: the stroke's
    // correction depends only on the stroke, not on how its samples fell.
    mSmoothNet.clear();
    mSmoothNet.reserve(mSmoothOrder.size());
    for (const auto& [level, coord] : mSmoothOrder) {
        // A vertex the diffusion emptied again later in the stroke stays empty.
        const auto& diffused = mSmoothDiffused[size_t(level - 1)];
        const auto it = diffused.find(coord);
        if (it == diffused.end()) continue;
        mSmoothNet.push_back(
            SkeletonChange{level, coord, mSmoothPre[size_t(level - 1)].at(coord), it->second});
    }
    SkeletonStore& store = mSculpture.store();
    // The estimate reads the store: the diffusion's weights go back first (what the last
    // previews showed is kept to record each vertex's change once).
    mSmoothShown.clear();
    mSmoothShown.reserve(mSmoothNet.size());
    for (const SkeletonChange& c : mSmoothNet) {
        mSmoothShown.push_back(store.get(c.level, c.coord));
        store.set(c.level, c.coord, *c.after);
    }
    mLastVolumeShift = VolumeKeepingShift{};
    mSmoothFinish = SmoothFinish::Prepared;
}

void StrokeBuilder::estimateSmoothedVolume() {
    // Reads the sculpture and mSmoothNet only (beginFinish() may hand this to another thread).
    mLastVolumeShift = volumeKeepingShift(mSculpture, mSmoothNet);
    mSmoothFinish = SmoothFinish::Estimated;
}

EditResult StrokeBuilder::applySmoothedVolume() {
    EditResult result;
    SkeletonStore& store = mSculpture.store();
    const double shift = mLastVolumeShift.shift;
    Aabb changed;
    double support = 0;
    for (size_t n = 0; n < mSmoothNet.size(); ++n) {
        const SkeletonChange& c = mSmoothNet[n];
        const float w = float(double(*c.after) + shift * mLastVolumeShift.moves[n]);
        store.set(c.level, c.coord, w);
        if (mSmoothShown[n] == w) continue;
        mChanges.push_back(SkeletonChange{c.level, c.coord, mSmoothShown[n], w});
        const ToolLevel& tl = mSculpture.levels().level(c.level);
        support = std::max(support, tl.supportMm);
        noteChanged(result, changed, vertexPos(c.coord, tl.spacingMm));
    }
    mSmoothNet.clear();
    mSmoothShown.clear();
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
    // As the session places an interactive stroke, so that a journal replays to the same bits
    // (holding back changes the rounding of the pre-stroke field the decisions read).
    stroke.holdBackChangesBelow(kInteractiveHoldBelow);
    EditResult total;
    auto add = [&](const EditResult& r) {
        total.changedRegion.expand(r.changedRegion);
        total.changedVertices += r.changedVertices;
    };
    for (const Vec3& p : path)
        add(stroke.addSample(p));
    add(stroke.finish());
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
