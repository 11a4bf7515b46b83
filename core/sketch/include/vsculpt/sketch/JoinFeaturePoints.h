// Joining a newer stroke's feature points into an existing feature-point sequence (seed 000
// section 5.3 (2)); the newer points always win where the two overlap. Units: millimetres.
#pragma once

#include "vsculpt/sketch/Polyline.h"

#include <cstddef>

namespace vsculpt::sketch {

/// How the newer sequence lies along the older curve.
enum class Overlap {
    None,     // beyond one end: the sequences are chained
    Partial,  // covers one end of the older curve
    Full,     // lies within the older curve, or covers all of it
    Closes,   // both ends on the older curve, middle beyond an end: it closes a loop
};

struct JoinParams {
    /// Older points closer than this to a newer point are dropped (seed rule (a)); mm. The seed
    /// gives no value.
    double mergeDistance = 3.0;
    /// Newer points within this distance (mm) of the older curve lie on it; the others are off
    /// it, which decides between chaining, partial and full overlap. Not in the seed.
    double overlapDistance = 4.0;
    /// Newer points on the older curve (see overlapDistance) are moved to older + w (newer -
    /// older), older being their closest point on it. Seed: 1 (newer replaces older); below 1
    /// averages overdrawn strokes.
    double newStrokeWeight = 1.0;
    /// Density of the sampled older spline used to locate points along it.
    int samplesPerSpan = 16;
};

struct JoinResult {
    Polyline2 points;
    Overlap overlap = Overlap::None;
    bool reversed = false;         // the newer sequence was reversed to follow the older
    std::size_t olderRemoved = 0;  // older points replaced by the newer ones
};

/// Older points are located by arc length on the natural spline through them and newer points
/// are on the older curve when within overlapDistance of it. Both newer ends on it: Full (the
/// span between them is replaced) or Closes. One end on it: Partial (the older part beyond it,
/// on the side the stroke leaves towards, is replaced). Neither: None (chained at the nearer
/// end), or Full when the middle is on it and the ends lie beyond both older ends. The newer
/// sequence is reversed when needed to run with the older one. Older points within
/// mergeDistance of a newer point are removed as well. When `olderClosed` the older sequence is a
/// loop: it is opened opposite the newer points, joined, and the result is again a loop (first
/// point not repeated). Throws std::invalid_argument for an empty newer sequence, an older one with
/// fewer than 2 points (3 when closed), non-finite points or invalid parameters. With
/// Overlap::Closes (open older only) the result is the older stretch between the newer ends
/// followed by the newer points, to be read as a loop.
JoinResult joinFeaturePoints(const Polyline2& older, bool olderClosed, const Polyline2& newer,
                             const JoinParams& params = {});

}  // namespace vsculpt::sketch
