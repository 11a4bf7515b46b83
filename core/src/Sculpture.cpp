// SPDX-License-Identifier: MIT
#include "vsculpt/core/Sculpture.h"

#include <map>
#include <mutex>
#include <tuple>

namespace vsculpt::core {

std::shared_ptr<const ToolLevels> toolLevelsFor(const SculptConfig& cfg) {
    // Calibration takes a fraction of a second; sessions and tests build many sculptures from
    // the same parameters, so the table is shared per parameter set.
    using Key = std::tuple<int, double, double, double, double, double, double, double, double,
                           double, std::array<double, kLevelCount>>;
    static std::mutex mutex;
    static std::map<Key, std::shared_ptr<const ToolLevels>> cache;
    const ManualSupport ms = cfg.manualSupport.value_or(ManualSupport{});
    const Key key{int(cfg.placement),
                  cfg.d4Mm,
                  cfg.growth,
                  cfg.spacingOverDiameter,
                  cfg.iso,
                  cfg.falloff.f0,
                  cfg.falloff.controlU,
                  cfg.falloff.controlValue,
                  cfg.falloff.controlSlope,
                  cfg.manualSupport ? ms.r4Mm : -1.0,
                  ms.scale};
    std::lock_guard lock(mutex);
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    auto levels = std::make_shared<const ToolLevels>(cfg);
    cache.emplace(key, levels);
    return levels;
}

Sculpture::Sculpture(const SculptConfig& cfg) : mConfig(cfg) {
    validateConfig(mConfig);
    mLevels = toolLevelsFor(mConfig);
    if (mConfig.sphereRadiusMm > 0) {
        // A point skeleton whose iso-surface is the sphere, F(r / R) = c - core(r), and the
        // steep core of support a r and weight w: core(r) = w F(1 / a) (validateConfig keeps it
        // below c). Without a core R = r / u_c.
        const HermiteFalloff& F = mLevels->falloff();
        const double r = mConfig.sphereRadiusMm;
        const double w = sphereCoreWeightIn(mConfig), a = mConfig.sphereCoreSupportOverRadius;
        const double coreAtSurface = w > 0 ? w * F.value(1 / a) : 0.0;
        const double uOuter = F.inverse(mLevels->iso() - coreAtSurface);
        addPointSkeleton(PointSkeleton{mConfig.sphereCenterMm, r / uOuter, 1.0});
        if (w > 0) addPointSkeleton(PointSkeleton{mConfig.sphereCenterMm, a * r, w});
    }
}

std::unique_ptr<Sculpture> Sculpture::clone() const {
    std::unique_ptr<Sculpture> copy(new Sculpture());
    copy->mConfig = mConfig;
    copy->mLevels = mLevels;
    copy->mStore = mStore.clone();
    copy->mPoints = mPoints;
    copy->worldFromObject = worldFromObject;
    return copy;
}

void Sculpture::addPointSkeleton(const PointSkeleton& s) {
    mPoints.push_back(s);
}

SkeletonCounts Sculpture::counts() const {
    SkeletonCounts c;
    const bool thesis = mConfig.placement == PlacementMode::Thesis;
    mStore.forEach([&](const SkeletonEntry& e) {
        size_t n = 1;
        if (e.weight > 0) {
            ++c.additive;
        } else if (e.weight < 0) {
            ++c.subtractive;
        } else if (thesis) {  // an additive and a subtractive skeleton stacked
            ++c.additive;
            ++c.subtractive;
            n = 2;
        }
        c.byLevel[e.level - 1] += n;
        c.lattice += n;
    });
    c.point = mPoints.size();
    return c;
}

Aabb Sculpture::supportBounds() const {
    // Only what raises the field: a carve's negative weights cannot make surface where no
    // positive one reaches (found by QA: a carve grew "the sculpture is N mm across", and the
    // finest export the grid allows coarsened with it).
    Aabb box;
    for (const PointSkeleton& p : mPoints)
        if (p.weight > 0) box.expand(Aabb{p.centerMm, p.centerMm}.padded(p.supportMm));
    mStore.forEach([&](const SkeletonEntry& e) {
        if (!(e.weight > 0)) return;
        const ToolLevel& l = mLevels->level(e.level);
        const Vec3 pos = Vec3(e.coord.x, e.coord.y, e.coord.z) * l.spacingMm;
        box.expand(Aabb{pos, pos}.padded(l.supportMm));
    });
    return box;
}

}  // namespace vsculpt::core
