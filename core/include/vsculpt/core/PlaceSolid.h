// SPDX-License-Identifier: MIT
/// @file PlaceSolid.h
/// @brief Turns a closed solid (a triangle mesh, object-space mm) into skeletons of one tool
/// level on that level's lattice, so a sketched solid becomes clay like any stroke: the same
/// field, polygonizer, carving, zoom, undo and journal (docs/sketch-solids.md).
///
/// Each lattice vertex gets a weight from the solid's signed distance there (an antialiased
/// ramp across the boundary, one lattice spacing wide), shifted by an inset calibrated so
/// that a filled half-space's iso-surface lands, on average, on the half-space's boundary.
/// The weights are blended with what is already there by the placement mode's add rule
/// (docs/placement.md): free mode raises the field at each vertex to what the fresh solid
/// gives there, thesis mode fills empty vertices with +1 skeletons.
#pragma once

#include "vsculpt/core/Mesh.h"
#include "vsculpt/core/PlaceStroke.h"

#include <atomic>
#include <span>
#include <stdexcept>
#include <vector>

namespace vsculpt::core {

class Sculpture;
class ToolLevels;

/// Throws std::invalid_argument naming the problem unless `solid` is a closed, consistently
/// outward-oriented triangle mesh: indices a multiple of 3 and in range, every position
/// finite and within 1e6 mm, every edge used by exactly two triangles in opposite
/// directions, and a positive enclosed volume. Normals are ignored.
void validateSolidMesh(const Mesh& solid);

/// The level used when none is given: the largest level whose lattice spacing is at most a
/// quarter of the solid's thickness (its smallest bounding-box extent), so the thinnest part
/// spans at least four lattice spacings; level 1 when even that one is coarser.
int solidLevelFor(const ToolLevels& levels, const Mesh& solid);

/// How a filled half-space comes out, in units of the lattice spacing h (the same at every
/// level: spacing, support and tool size all scale with D_k).
struct SolidCalibration {
    double insetOverSpacing = 0;      ///< the boundary ramp's centre lies this far inside the solid
    double rampOverSpacing = 1;       ///< width of the weight ramp across the boundary (0: a step)
    double interiorWeight = 0;        ///< weight of a vertex deep inside a fresh solid
    double interiorField = 0;         ///< field (without c) deep inside a fresh solid
    double meanErrorOverSpacing = 0;  ///< mean surface offset after the inset (~0)
    double worstDirectionOverSpacing = 0;  ///< worst mean offset of one plane direction
    double maxLocalOverSpacing = 0;        ///< worst single offset (lattice ripple)
    int directions = 0;                    ///< plane directions measured
};

/// The calibration for a sculpture's placement mode and field parameters (computed once per
/// tool-level table and cached; thread-safe).
const SolidCalibration& solidCalibration(const ToolLevels& levels);

struct SolidPlacement {
    int level = 0;                        ///< the level the solid was placed on
    std::vector<SkeletonChange> changes;  ///< in lattice order; undo = revertChanges
    EditResult edit;                      ///< for the polygonizer's incremental update
};

/// What placeSolid throws when its `stop` flag was raised; the sculpture is unchanged then.
class PlacementStopped : public std::runtime_error {
  public:
    PlacementStopped() : std::runtime_error("placement stopped") {}
};

/// Adds the solid to the sculpture (one edit). @param level 1..7, or 0 for solidLevelFor().
/// Throws std::invalid_argument for a bad mesh (validateSolidMesh), a level outside 0..7, a
/// solid less than two lattice spacings across at that level (it would leave no surface), or
/// a solid that would need more than 2^25 lattice vertices at that level (choose a larger
/// one); the sculpture is unchanged then. @param stop when given and raised (by another
/// thread: a cancelled import), the placement ends early with PlacementStopped: the signed
/// distance checks it as it goes (OpenVDB's interrupter), the decisions once per slab.
SolidPlacement placeSolid(Sculpture& sculpture, const Mesh& solid, int level = 0,
                          const std::atomic<bool>* stop = nullptr);

/// Journal replay: sets each vertex to its recorded `after` state (the `before` states are
/// ignored) and returns the changes with the sculpture's present states as `before`. Changes
/// may lie on other levels than `level` (a solid replacing another takes that one's clay
/// away). Throws std::invalid_argument (nothing changed) for a level outside 1..7 or a
/// coordinate beyond the lattice range.
SolidPlacement replaySolid(Sculpture& sculpture, int level,
                           std::span<const SkeletonChange> afterStates);

}  // namespace vsculpt::core
