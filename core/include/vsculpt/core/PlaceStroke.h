// SPDX-License-Identifier: MIT
/// @file PlaceStroke.h
/// @brief Turns a tool path into skeletons on the tool level's lattice (thesis §3.1.2), under
/// the sculpture's placement mode (docs/placement.md).
///
/// A stroke is the sequence of tool-centre samples between pressing and releasing the tool.
/// Every lattice vertex inside the tool sphere swept between consecutive samples (swept mode:
/// inside that sphere grown by kSweptMarginOverRadius) is visited, so fast strokes leave no
/// gaps. Decisions that depend on the field use the field as it was before the stroke began,
/// so the result does not depend on sample spacing.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Geometry.h"
#include "vsculpt/core/KeepSmoothedVolume.h"
#include "vsculpt/core/LatticeMap.h"

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace vsculpt::core {

class Sculpture;
class FieldProbe;
struct SweptTransfer;  // swept mode: the field a unit target change makes (PlaceStroke.cpp)

/// Add: union with the swept tool. Carve: subtract it. Smooth: relax the surface under the
/// tool toward its local average (not in thesis placement mode; docs/placement.md).
enum class ToolOp { Add, Carve, Smooth };
const char* toString(ToolOp op);

/// Mirror symmetry: every stroke is also applied mirrored across the object-space plane
/// through the origin normal to this axis (x = 0, y = 0 or z = 0). The lattices are symmetric
/// about these planes, so the mirrored half lands on mirrored vertices and the field stays
/// mirror-equal.
enum class MirrorAxis { None, X, Y, Z };
const char* toString(MirrorAxis axis);
/// `p` mirrored across the axis's plane (unchanged for None).
Vec3 mirrored(const Vec3& p, MirrorAxis axis);

/// Swept mode: a stroke changes the field, and places skeletons, within this many tool radii
/// beyond the swept tool's surface (docs/placement.md).
inline constexpr double kSweptMarginOverRadius = 1.0;
/// What interactive strokes hold back until their end (StrokeBuilder::holdBackChangesBelow):
/// a weight change of 1e-3 moves the surface by at most 1e-3 / |grad f|, 0.02 mm on the
/// initial sphere's flat field, 0.004 mm at a size-1 stroke's surface.
inline constexpr double kInteractiveHoldBelow = 1e-3;

/// One vertex's state before and after an edit (nullopt = empty): enough to undo or redo it.
struct SkeletonChange {
    int level = 0;
    LatticeCoord coord;
    std::optional<float> before, after;
};

struct EditResult {
    /// Object-space box outside which f did not change (changed vertices padded by R_k).
    Aabb changedRegion;
    int changedVertices = 0;
    /// Tighter: f changed only within supportMm of these lattice vertices (object space).
    std::vector<Vec3> changedPoints;
    double supportMm = 0;
};

/// An in-progress stroke on one sculpture. Edits the sculpture as samples arrive.
class StrokeBuilder {
  public:
    /// The longest segment between two samples, in lattice spacings of the lattice the
    /// weights go to: addSample refuses a longer one (std::invalid_argument).
    static constexpr double kMaxSegmentSpacings = 20000;
    /// @param level tool level 1..7 (checked: std::invalid_argument)
    /// @param mirror also apply every swept segment mirrored across that plane, as part of
    ///        the same stroke (one undo step; decisions from the same pre-stroke field).
    /// Smooth in thesis placement mode is refused (std::invalid_argument): its skeletons are
    /// unit weights, there is nothing to relax.
    StrokeBuilder(Sculpture& sculpture, ToolOp op, int level, MirrorAxis mirror = MirrorAxis::None);
    ~StrokeBuilder();

    /// Adds a tool-centre sample in object space (mm) and applies the swept segment from the
    /// previous sample. Throws std::invalid_argument for a non-finite or out-of-range point,
    /// or one farther from the previous sample than kMaxSegmentSpacings.
    EditResult addSample(const Vec3& objectPos);
    /// Same for a world-space sample: objectPos = inverse(worldFromObject) * worldPos.
    EditResult addSampleWorld(const Vec3& worldPos, const RigidTransform& worldFromObject);

    /// Interactive strokes (swept mode): a sample's weight changes smaller than `below` (field
    /// units; 0, the default, writes every change at once) are held back and written by
    /// finish(). Each sample recomputes the weights around it from the final targets, so most
    /// of its writes are small adjustments far from the tool (75-86 % under 1e-3), each of
    /// which the mesher would otherwise re-mesh. Every decision reads the pre-stroke field
    /// (the store less this stroke's own written changes), so holding writes back changes no
    /// decision but for rounding: that field is reconstructed from other stored values. The
    /// session and applyStroke (journal replay) both hold back kInteractiveHoldBelow, so a
    /// replay gives the same bits.
    void holdBackChangesBelow(double below) { mHoldBelow = below; }
    /// Writes the changes held back (none without holdBackChangesBelow). Call it once the
    /// last sample is in, before takeChanges(): the stroke is complete only then.
    EditResult finish();
    /// finish() in two parts, so that its costly one can run off the frame thread: a smooth
    /// stroke's volume estimate (placement.smooth_keeps_volume; 12 ms on 2 cores over the
    /// bumpy arm, docs/benchmarks.md). Once the last sample is in, beginFinish() writes the
    /// diffusion's own weights back to the store (what the estimate reads; cheap) and returns
    /// the estimate as work to run, or an empty function when there is none (other tools,
    /// the correction off, a stroke that changed nothing). The work reads the sculpture and
    /// nothing of this builder's but what beginFinish() set aside for it: it may run on any
    /// one thread while the sculpture is only read (its store neither set nor erased) and this
    /// builder is not called. Then finish() writes the corrected weights on the caller's
    /// thread. The result is the same bits as finish() alone.
    /// An add or carve with placement.refine_levels: beginFinish() completes the stroke on
    /// its own lattice and hands out the refinement's samples (they only read), and finish()
    /// writes what they decided (docs/placement.md "Refining strokes").
    std::function<void()> beginFinish();

    /// Every vertex change so far, one per vertex (before: the state before the stroke,
    /// after: the current one); a smooth stroke's in the order made, a vertex again each time
    /// it changed (its volume correction last), so revertChanges and reapplyChanges, which
    /// walk them backwards and forwards, hold for both.
    const std::vector<SkeletonChange>& changes() const { return mChanges; }
    /// f - c at `objectPos` (mm) as it was before this stroke: positive inside that clay.
    /// What a pointer resting on the surface follows while the stroke goes on, so that it
    /// neither climbs the clay the stroke adds nor sinks into what it carves.
    double preStrokeValueAt(const Vec3& objectPos);
    /// Hands the changes over. @pre finish() was called after the last sample (a stroke that
    /// placed something is complete only then): std::logic_error otherwise.
    std::vector<SkeletonChange> takeChanges();
    /// A smooth stroke's volume correction as finish() made it (zero before finish(), for
    /// other tools, and with placement.smooth_keeps_volume off).
    const VolumeKeepingShift& volumeShift() const { return mLastVolumeShift; }

  private:
    /// The refinement's builder (finish()): weights on `lattice`, the residual against
    /// `coarse`'s realised change.
    StrokeBuilder(Sculpture& sculpture, ToolOp op, int level, MirrorAxis mirror, int lattice,
                  const StrokeBuilder* coarse);
    void init(int lattice);
    /// The lattice the refinement places on (placement.refine_levels below this one's);
    /// whether this stroke is refined at all (its op, mode and a lattice of level 1 or above
    /// there), and whether finish() refines it (refinable, with samples).
    int refineLattice() const;
    bool refinable() const;
    bool refines() const;
    /// The refinement in three parts: the stroke completed on its own lattice and the fine
    /// builder made; the fine builder's samples (reads only); finish() writes.
    void startRefinement();
    void sampleRefinement();
    /// finish() on this builder's own lattice.
    EditResult finishOnLattice();
    /// The change this stroke's coarse pass realised at `pos` (refinement only), and its
    /// gradient added to `gradient` when given.
    double coarseChangeAt(const Vec3& pos, Vec3* gradient = nullptr) const;
    /// The checkerboard part of the pre-stroke weights around lattice vertex `v` (a finer
    /// lattice than the tool's sheds it: kFineCheckerboardDecay).
    double checkerboardOf(const LatticeCoord& v) const;
    /// The store's raw sum and gradient at `pos`, less the coarse pass's change (refinement).
    FieldSample probeLessCoarse(const Vec3& pos);
    double preStrokeRawSum(const LatticeCoord& v, const Vec3& pos);
    /// The same at any point (not only at a vertex of the tool's lattice).
    FieldSample preStrokeSampleAt(const Vec3& pos);
    /// Calls visit(delta, pos - vertex, distance, distance / support) for every vertex of the
    /// stroke's lattice whose weight this stroke changed by `delta` and whose support reaches
    /// `pos`.
    template <class Fn>
    void forEachDeltaNear(const Vec3& pos, Fn&& visit) const;
    /// The field (without c) and its gradient before the stroke began.
    FieldSample preStrokeSample(const LatticeCoord& v, const Vec3& pos);
    /// Thesis and free modes: the vertices inside the swept tool decide their weights.
    EditResult addSampleOnTool(const Vec3& a, const Vec3& p);
    EditResult addSampleSwept(const Vec3& a, const Vec3& p);
    EditResult addSmoothSample(const Vec3& a, const Vec3& p);
    /// finish() of a smooth stroke: gives back the volume the diffusion took or added
    /// (KeepSmoothedVolume.h; config placement.smooth_keeps_volume), over the whole stroke,
    /// in three parts: the diffusion's weights back in the store (what the estimate reads),
    /// the estimate (reads only; beginFinish() hands it out), the corrected weights written.
    void prepareSmoothedVolume();
    void estimateSmoothedVolume();
    EditResult applySmoothedVolume();
    /// The same during the stroke, for the vertices one sample changed, on a coarser grid:
    /// what the sculptor sees under the brush until finish() makes the stroke's own.
    void previewSmoothedVolume(const std::vector<SkeletonChange>& sampleChanges, EditResult& result,
                               Aabb& changed);
    /// Sets a vertex's weight (or empties it) and records the change, one per vertex.
    void setWeight(const LatticeCoord& v, const std::optional<float>& current,
                   const std::optional<float>& after);

    Sculpture& mSculpture;
    ToolOp mOp;
    int mLevel;
    int mLattice;  // the level whose lattice the weights are placed on (swept: may be finer)
    MirrorAxis mMirror;
    std::optional<Vec3> mLast;
    std::vector<Vec3> mPath;                 // every sample of a refinable stroke
    const StrokeBuilder* mCoarse = nullptr;  // refinement: the pass whose residual it places
    std::unique_ptr<StrokeBuilder> mFine;    // a refined stroke's refinement, during finish
    bool mFineSampled = false;               // its samples are in
    bool mRefined = false;                   // finish() has written the refinement
    EditResult mRefineStart;                 // what completing the coarse pass changed
    struct Visit {
        std::optional<float> preStroke;  // the vertex's state before this stroke
        double lateral;                  // closest approach of the stroke so far, mm
    };
    // Thesis: a vertex is decided once. Free: a vertex is decided again when the path comes
    // closer to it, always from the pre-stroke state (its weight depends on that distance).
    std::unordered_map<LatticeCoord, Visit, LatticeCoordHash> mVisited;
    // Refinement: the fine weights within the stroke's reach, at their pre-stroke values; each
    // sheds kRefineLeak of itself to the tool's lattice.
    std::unordered_map<LatticeCoord, float, LatticeCoordHash> mLeaking;
    /// The field at `pos` of the weights that shed (refinement), before they do.
    double leakingField(const Vec3& pos) const;
    /// The field at `pos` of the store's weights on one level's lattice.
    double levelField(int level, const Vec3& pos) const;
    std::unordered_map<LatticeCoord, float, LatticeCoordHash> mDeltas;  // weight change per vertex
    std::vector<LatticeCoord> mStencil;  // lattice offsets within the level's support radius
    std::vector<SkeletonChange> mChanges;
    double mHoldBelow = 0;
    // The weight due at each vertex whose change is held back.
    std::unordered_map<LatticeCoord, std::optional<float>, LatticeCoordHash> mHeld;
    std::unordered_map<LatticeCoord, size_t, LatticeCoordHash> mChangeIndex;  // into mChanges

    // Swept mode (docs/placement.md): each vertex near the path gets a target change of the
    // field, decided from the pre-stroke field; weights are the deconvolved target changes.
    struct Target {
        double phi = 0;      // pre-stroke field without c
        double shed = 0;     // refinement: the field of the fine weights' shed share here
        Vec3 gradient{0.0};  // of the pre-stroke field, per mm
        double grad = 0;     // its length
        double lateral = 0;  // closest approach of the path so far, mm
        double change = 0;   // target change of the field at the vertex
        // The control point: the swept tool's extreme point into (carve) or out of (add) the
        // material along the pre-stroke normal, the tool at the path's closest point to this
        // vertex; the new surface must pass through it. Absent where the vertex sees no old
        // surface.
        std::optional<Vec3> control;
        double controlPhi = 0;   // pre-stroke field (without c) there
        double controlGrad = 0;  // and the length of its gradient, per mm
        double base = 0;         // the vertex's weight from the targets alone (clamped)
        double correction = 0;   // added to the target so the surface meets the aim points
        // Where the fit aims: the control point, or for a carve that does not reach the old
        // surface there, the old surface beyond it; absent where there is none. `need` is the
        // change of the field the new surface needs there, `share` the vertex's share of a
        // correction aimed there.
        std::optional<Vec3> aim;
        double need = 0;
        double residualNeed = 0;  // refinement: need less the tool's pass's realised change
        double share = 0;
        bool emptyAim = false;  // the aim is the tool's surface in empty space
        bool keepAim = false;   // the aim is the old surface beyond a carve that misses it
        // The last sample that put this target in each of its sets (base weight to recompute,
        // fit to recompute, weight to write): each joins a set once per sample.
        uint32_t baseMark = 0, fitMark = 0, affectedMark = 0;
    };
    // The correction of a vertex's target that brings the new surface to the aim points
    // around it (docs/placement.md, closed-loop fit).
    double fitCorrection(const Target& t);
    // The refinement fits once, after all its samples (fitDeferred), not at each sample.
    bool mDeferFit = false;
    std::vector<LatticeCoord> mTargetCoords;  // every target, while the fit is deferred
    void fitDeferred();
    // Adding never lowers the field and carving never raises it (the refinement does both).
    double clampToOp(double w) const;
    // The weights of `affected` (sorted here): base plus deconvolved corrections, written or
    // held back.
    EditResult writeWeights(std::vector<LatticeCoord>& affected);
    // Whether x lies inside the tool (radius, mm) swept along the whole stroke's path (the
    // coarse pass's, for a refinement), or its mirror image.
    bool insideSweptTool(const Vec3& x, double radius) const;
    double mDeconvolveReach = 0;  // the longest tap offset, lattice spacings
    bool mAnyControl = false;     // some target of this stroke has a control point
    uint32_t mSampleMark = 0;     // the current sample's number (Target's marks)
    bool mFinishingCap = false;   // finish(): fitting the end cap (addSampleSwept)
    bool mFinished = false;       // finish() was called after the last sample
    VolumeKeepingShift mLastVolumeShift;
    std::shared_ptr<const SweptTransfer> mTransfer;
    LatticeMap<Target> mTargets;
    struct Tap {
        LatticeCoord offset;
        double target = 0;      // of the targets' (stabilised) stencil
        double correction = 0;  // of the fit corrections' (plain) stencil
    };
    // weight(v) = sum of tap.target * change(v - tap.offset) + tap.correction * correction(...)
    std::vector<Tap> mDeconvolve;
    std::unique_ptr<FieldProbe> mProbe;
    // Smooth: per level (1..7), each visited vertex's closest approach and the pre-stroke
    // state of every vertex the stroke changed.
    std::array<std::unordered_map<LatticeCoord, double, LatticeCoordHash>, kLevelCount>
        mSmoothVisited;
    std::array<std::unordered_map<LatticeCoord, std::optional<float>, LatticeCoordHash>,
               kLevelCount>
        mSmoothPre;
    // Smooth with the volume kept: each changed vertex's weight from the diffusion alone
    // (what the store holds less the volume correction) and the order vertices were first
    // changed, so finish() computes the stroke's correction from these, whatever each
    // sample's preview of it wrote.
    std::array<std::unordered_map<LatticeCoord, float, LatticeCoordHash>, kLevelCount>
        mSmoothDiffused;
    std::vector<std::pair<int, LatticeCoord>> mSmoothOrder;
    // finish()'s smooth correction between its parts: the stroke's net changes (before: the
    // pre-stroke state, after: the diffusion's weight), what the store showed at each before
    // the diffusion's weight went back (the last preview), and whether the estimate is made.
    enum class SmoothFinish { NotStarted, Prepared, Estimated };
    SmoothFinish mSmoothFinish = SmoothFinish::NotStarted;
    std::vector<SkeletonChange> mSmoothNet;
    std::vector<std::optional<float>> mSmoothShown;
};

/// Applies a whole stroke (object-space path). Returns the union of the changed regions and
/// appends the vertex changes to `changes` when given.
EditResult applyStroke(Sculpture& sculpture, ToolOp op, int level, std::span<const Vec3> path,
                       std::vector<SkeletonChange>* changes = nullptr,
                       MirrorAxis mirror = MirrorAxis::None);

/// Restores the `before` state of each change, last first (undo). Returns the changed region.
Aabb revertChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes);
/// Re-applies the `after` state of each change, first first (redo).
Aabb reapplyChanges(Sculpture& sculpture, std::span<const SkeletonChange> changes);

}  // namespace vsculpt::core
