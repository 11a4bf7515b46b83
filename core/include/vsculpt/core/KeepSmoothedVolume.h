// SPDX-License-Identifier: MIT
/// @file KeepSmoothedVolume.h
/// @brief The smooth tool's volume correction (issue #13: smooth "without growing or
/// shrinking the volume by more than 2 % per pass").
///
/// Diffusing the weights keeps their sum, not the clay's volume: the volume is where the
/// blurred weights exceed the iso value, and a feature a few lattice spacings thick (a size-3
/// arm, a ridge) has its peak lowered below it (measured: 23 % of an arm a pass, gone after
/// four). So a smooth stroke ends by moving every weight it changed by shift * |its change|,
/// one shift for the whole stroke, chosen so that the volume under the stroke is what it was.
/// Where the diffusion changed nothing, nothing moves; where it moved most (the feature being
/// dissolved), most is given back. One scalar for the stroke keeps mirror symmetry exact.
#pragma once

#include <span>

namespace vsculpt::core {

class Sculpture;
struct SkeletonChange;  // PlaceStroke.h

struct VolumeKeepingShift {
    /// Each changed weight w_after becomes w_after + shift * |w_after - w_before|; in
    /// [-1, 1] (1 at most doubles a change outward, -1 inward).
    double shift = 0;
    /// The volume under the stroke before it, after the diffusion and after the shift, mm^3,
    /// as the estimate below measures it (the region where the changes reach: the union of
    /// the changed skeletons' supports).
    double volumeBefore = 0, volumeDiffused = 0, volumeShifted = 0;
    double cellMm = 0;  ///< spacing of the estimate's grid
    int points = 0;     ///< grid points that the changes reach
};

/// The shift that keeps the volume, for changes already written to `sculpture`'s store
/// (`changes[i].after` is the current state, `before` the state before the stroke).
///
/// The volume is estimated on a grid of cell centres, spacing a third of the finest changed
/// level's lattice spacing (coarser where that would exceed about a million points), each
/// point counting the part of its cell inside the clay as clamp(0.5 + f / (|grad f| h), 0, 1),
/// exact for a plane at any offset; the field after a shift is the field now plus the shift
/// times the changes' own field, so the search for it needs one field evaluation per point.
/// Deterministic (the journal replays to the same bits). No changes: shift 0.
VolumeKeepingShift volumeKeepingShift(const Sculpture& sculpture,
                                      std::span<const SkeletonChange> changes);

}  // namespace vsculpt::core
