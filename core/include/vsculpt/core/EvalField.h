// SPDX-License-Identifier: MIT
/// @file EvalField.h
/// @brief Evaluates the implicit field of a sculpture,
///   f(P) = sum_additive w F_k(|P - s| / R_k) - sum_subtractive ... - c   (weights carry sign),
/// and its gradient. Inside the material f > 0; the surface is f = 0.
///
/// Only skeletons whose support reaches P are visited: per level, the few 4^3 lattice blocks
/// overlapping the ball of radius R_k around P (see SkeletonStore.h). Cost per evaluation therefore
/// depends on the local skeleton density, not on the size of the sculpture.
#pragma once

#include <span>

#include "vsculpt/core/Geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "vsculpt/core/Falloff.h"

namespace vsculpt::core {

class Sculpture;

struct FieldSample {
    double value = 0;    ///< f(P)
    Vec3 gradient{0.0};  ///< grad f(P), per mm
};

/// A reader of one sculpture's field with cached tree accessors. Not thread-safe: give each
/// thread its own probe. Any number of probes may read concurrently while nobody edits.
/// The sculpture must outlive the probe; an edit between calls is fine on the edit's thread
/// (the probe caches where blocks of skeletons live, and notices new ones).
class FieldProbe {
  public:
    explicit FieldProbe(const Sculpture& sculpture);
    ~FieldProbe();
    FieldProbe(FieldProbe&&) noexcept;
    FieldProbe& operator=(FieldProbe&&) = delete;

    /// f(P) at an object-space point (mm).
    double value(const Vec3& objectPos);
    /// f(P) and its gradient.
    FieldSample sample(const Vec3& objectPos);
    /// sum_s w_s F(|P - s|) without the iso offset c: 0 in untouched space.
    double rawSum(const Vec3& objectPos) { return value(objectPos) + mIso; }

  private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
    double mIso;
};

/// Batched evaluation for many points, as the polygonizer calls it from many threads at once
/// (each call uses its own accessors). `values.size()` must equal `points.size()`;
/// `gradients` is either empty (not wanted) or of the same size.
void evalFieldBatch(const Sculpture& sculpture, std::span<const Vec3> points,
                    std::span<double> values, std::span<Vec3> gradients = {});

/// Reference implementation visiting every skeleton; for tests.
FieldSample evalFieldBruteForce(const Sculpture& sculpture, const Vec3& objectPos);

}  // namespace vsculpt::core

namespace vsculpt::core {

/// Field sums in fixed point (issue #14): each skeleton's term w F(d / R) is cut to a
/// multiple of 2^-40 before it is added, so a sum is an exact integer whatever the order of
/// its terms, and a kept sum plus the terms of the skeletons that changed equals a fresh sum
/// bit for bit. The cut (under 1e-12 per term, by truncation) is far below any tolerance of
/// the mesher. 128 bits: weights in clay piled up by many swept strokes reach 1e7 and more
/// (field values of 1e8 measured), past what 64 bits hold at this resolution.
__extension__ using FixedSum = __int128;
inline constexpr double kFixedPerUnit = 0x1p40;
inline FixedSum fixedTerm(double term) {
    const double x = term * kFixedPerUnit;
    if (std::abs(x) < 0x1p62) return static_cast<int64_t>(x);  // one instruction: the usual case
    return static_cast<FixedSum>(std::clamp(x, -0x1p120, 0x1p120));
}
/// f from a fixed-point sum of terms.
inline double fixedToField(FixedSum sum, double iso) {
    // Both conversions round correctly (to nearest), so they agree bit for bit; the 64-bit one
    // is one instruction, the 128-bit one a library call (the polygonizer converts every kept
    // grid value of every rebuilt block).
    const auto narrow = static_cast<int64_t>(sum);
    const double x = narrow == sum ? static_cast<double>(narrow) : static_cast<double>(sum);
    return x / kFixedPerUnit - iso;
}

/// Adds the fixed-point term of one skeleton (centre c, weight w, support radius R given as
/// 1/R and R^2) to every vertex of a regular grid within its support, with the grid laid out
/// as in LocalField::gridValues (at most 16 vertices per axis).
void splatFixed(const HermiteFalloff& falloff, const Vec3& c, double w, double invR, double r2,
                std::span<const double> xs, std::span<const double> ys, std::span<const double> zs,
                FixedSum* out);
/// A skeleton's weight changing from `before` to `after`: subtracts the term splatFixed added
/// for `before` and adds the one for `after`, computed with the same operations, so a kept sum
/// updated this way equals a fresh splat bit for bit.
void splatFixedChange(const HermiteFalloff& falloff, const Vec3& c, double before, double after,
                      double invR, double r2, std::span<const double> xs,
                      std::span<const double> ys, std::span<const double> zs, FixedSum* out);

/// Conservative range of f over a box.
struct FieldBounds {
    double min = 0, max = 0;
    bool mayContainSurface() const { return min <= 0 && max > 0; }
};

/// The skeletons whose support reaches an axis-aligned box, gathered once, for evaluating
/// many points inside the box without any lookups (the polygonizer's blocks).
///
/// For points inside the box (boundary included), value() and sample() return exactly,
/// bit for bit, what FieldProbe returns: the same skeletons are summed in the same order.
/// The sculpture must not change while a LocalField is used.
class LocalField {
  public:
    LocalField(const Sculpture& sculpture, const Aabb& box);

    double value(const Vec3& objectPos) const;
    FieldSample sample(const Vec3& objectPos) const;
    /// Bounds of f over the box from each skeleton's nearest and farthest distance to it:
    /// when the range does not include 0, no surface passes through the box.
    FieldBounds bounds() const;
    size_t skeletonCount() const { return mX.size(); }
    /// f at every vertex of a regular grid, out[(i * ys.size() + j) * zs.size() + k] =
    /// value({xs[i], ys[j], zs[k]}), bit for bit: each skeleton is splatted onto the vertices
    /// within its support only, and every vertex still adds its skeletons in the same order
    /// with the same operations. @pre xs, ys, zs ascending and evenly spaced (a block's grid).
    void gridValues(std::span<const double> xs, std::span<const double> ys,
                    std::span<const double> zs, double* out) const;
    /// The same grid's fixed-point sums of terms (splatFixed), without the iso offset:
    /// f = fixedToField(out[...], iso).
    void gridSums(std::span<const double> xs, std::span<const double> ys,
                  std::span<const double> zs, FixedSum* out) const;

  private:
    /// |p - skeleton|^2 for skeletons base .. base + m - 1 (a loop the compiler vectorises;
    /// the same operations as FieldProbe: (dx*dx + dy*dy) + dz*dz).
    static constexpr size_t kDistanceChunk = 64;
    void squaredDistances(const Vec3& p, size_t base, size_t m, double* out) const;

    const HermiteFalloff* mFalloff;
    double mIso;
    Aabb mBox;
    // Structure of arrays, in FieldProbe's summation order.
    std::vector<double> mX, mY, mZ, mW, mInvR, mR2;
};

}  // namespace vsculpt::core
