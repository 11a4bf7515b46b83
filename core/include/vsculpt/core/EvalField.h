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

#include "vsculpt/core/Geometry.h"

#include <memory>
#include <span>

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
