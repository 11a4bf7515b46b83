// SPDX-License-Identifier: MIT
/// @file TestScene.h
/// @brief The render tests' sculpture: the initial sphere (r = 30 mm) with a level-5 bar
/// across its front, polygonized on the zoom-1 grid.
#pragma once

#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"

#include <vector>

namespace vsculpt::test {

inline core::Mesh sculptureMesh(int gridN = 64) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 30;
    cfg.polygonizer.gridN = gridN;
    core::Sculpture s(cfg);
    core::applyStroke(s, core::ToolOp::Add, 5,
                      std::vector<core::Vec3>{core::Vec3(-45, -10, 0), core::Vec3(45, -10, 10)});
    core::Polygonizer poly(s, core::zoomRegion(cfg, s.levels(), 1, core::Vec3(0)), 0.125);
    poly.rebuildAll();
    return poly.mesh();
}

}  // namespace vsculpt::test
