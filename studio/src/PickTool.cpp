// SPDX-License-Identifier: MIT
#include "vsculpt/studio/PickTool.h"

#include "vsculpt/studio/Session.h"

#include <glm/geometric.hpp>

namespace vsculpt::studio {

using namespace vsculpt::core;

namespace {

// The first t in [0, farMm), stepping stepMm, where value(origin + t dir) > 0 (inside).
template <class Value>
std::optional<double> march(Value&& value, const Vec3& origin, const Vec3& dir, double stepMm,
                            double farMm) {
    if (!(stepMm > 0)) return std::nullopt;
    for (double t = 0; t < farMm; t += stepMm)
        if (value(origin + t * dir) > 0) return t;
    return std::nullopt;
}

}  // namespace

std::optional<double> marchToSurface(FieldProbe& probe, const Vec3& origin, const Vec3& dir,
                                     double stepMm, double farMm) {
    return march([&](const Vec3& p) { return probe.value(p); }, origin, dir, stepMm, farMm);
}

ToolContact toolContact(FieldProbe& probe, const Vec3& centre, double radiusMm) {
    if (probe.value(centre) > 0) return ToolContact::Inside;
    for (const Vec3& d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0),
                          Vec3(0, 0, 1), Vec3(0, 0, -1)})
        if (probe.value(centre + d * radiusMm) > 0) return ToolContact::Touching;
    return ToolContact::Air;
}

namespace {

// The march's step and reach for the view on show: fine enough not to step over a feature
// the view can show, far enough to cross the whole region.
void marchScale(const Session& s, double& step, double& far) {
    const Aabb box = s.region().box();
    far = glm::length(box.max - box.min) * 1.5;
    step = 0.5 * s.region().spacingMm;
}

void addCues(FieldProbe& probe, ToolPick& pick, double radius, const Vec3& down, double step,
             double far) {
    pick.contact = toolContact(probe, pick.toolCentre, radius);
    if (const auto t = marchToSurface(probe, pick.toolCentre, down, step, far))
        pick.shadow = pick.toolCentre + *t * down;
}

}  // namespace

ToolPick pickTool(const Session& s, const Vec3& origin, const Vec3& dir, double radius,
                  double depthOffset, const Vec3& down) {
    double step = 0, far = 0;
    marchScale(s, step, far);
    FieldProbe probe(s.sculpture());
    ToolPick pick;
    double t = 0;
    // While a stroke goes on, the tool rests on the clay as it was before the stroke: on the
    // live clay an add held still climbed its own clay toward the eye (a pillar hundreds of
    // mm long in a second), and a carve sank into the hollow it made.
    const std::optional<double> hit =
        s.inStroke()
            ? march([&](const Vec3& p) { return s.preStrokeValueAt(p); }, origin, dir, step, far)
            : marchToSurface(probe, origin, dir, step, far);
    if (hit) {
        t = *hit;
        pick.surfaceHit = origin + t * dir;
    } else {
        const Aabb box = s.region().box();
        t = glm::length(0.5 * (box.min + box.max) - origin);
    }
    pick.toolCentre = origin + (t - radius + depthOffset) * dir;
    addCues(probe, pick, radius, down, step, far);
    return pick;
}

ToolPick toolCues(const Session& s, const Vec3& centre, double radius, const Vec3& down) {
    double step = 0, far = 0;
    marchScale(s, step, far);
    FieldProbe probe(s.sculpture());
    ToolPick pick;
    pick.toolCentre = centre;
    addCues(probe, pick, radius, down, step, far);
    return pick;
}

}  // namespace vsculpt::studio
