// SPDX-License-Identifier: MIT
/// @file PickTool.h
/// @brief Tool picking on the field: where a pointer ray puts the tool, how the tool touches
/// the clay (the contact cue), and the surface point under it (the shadow cue). Pure
/// functions of the sculpture: the sculpting window, the sketch window's 3D view and tests
/// use the same ones. Everything is in object space, millimetres.
#pragma once

#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Geometry.h"

#include <optional>

namespace vsculpt::studio {

class Session;

/// How the tool meets the clay.
enum class ToolContact {
    Air = 0,       ///< no clay within the tool's radius (probed along the six axes)
    Touching = 1,  ///< clay within the radius, the centre outside
    Inside = 2,    ///< the tool's centre is inside the clay
};

/// The first parameter t in [0, farMm) at which `origin + t * dir` is inside the clay,
/// sampled every `stepMm` (dir unit length). nullopt when the ray meets no clay.
std::optional<double> marchToSurface(core::FieldProbe& probe, const core::Vec3& origin,
                                     const core::Vec3& dir, double stepMm, double farMm);

/// The contact cue of a tool of `radiusMm` centred at `centre`.
ToolContact toolContact(core::FieldProbe& probe, const core::Vec3& centre, double radiusMm);

struct ToolPick {
    core::Vec3 toolCentre{0.0};            ///< where the tool is, object mm
    std::optional<core::Vec3> surfaceHit;  ///< the clay surface under the pointer, if hit
    ToolContact contact = ToolContact::Air;
    std::optional<core::Vec3> shadow;  ///< the clay straight below the tool (along `down`)
};

/// The pointer's tool: it rests on the first clay surface along the ray (touching it, its
/// centre one radius before the surface), pushed in by `depthOffsetMm` (the scroll wheel;
/// positive goes into the clay). Where the ray meets no clay the tool stays at the distance
/// of the view region's centre. The march steps half the view's grid spacing over 1.5 times
/// the region's diagonal. @param dir unit length; @param down the world's down in object
/// space (unit length).
ToolPick pickTool(const Session& session, const core::Vec3& origin, const core::Vec3& dir,
                  double toolRadiusMm, double depthOffsetMm, const core::Vec3& down);

/// The cues for a tool placed elsewhere (a tracked pen): contact and shadow at `centre`.
ToolPick toolCues(const Session& session, const core::Vec3& centre, double toolRadiusMm,
                  const core::Vec3& down);

}  // namespace vsculpt::studio
