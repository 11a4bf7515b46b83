// SPDX-License-Identifier: MIT
/// @file TestScene.h
/// @brief The render tests' sculpture: the initial sphere (r = 30 mm) with a level-5 bar
/// across its front, polygonized on the zoom-1 grid.
#pragma once

#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"

#include <memory>
#include <vector>

namespace vsculpt::test {

/// The sculpture with its polygonizer kept: what a Viewer syncs its chunks from.
struct SculptureView {
    core::SculptConfig cfg;
    std::unique_ptr<core::Sculpture> sculpture;
    std::unique_ptr<core::Polygonizer> poly;
    explicit SculptureView(int gridN = 64) {
        cfg.sphereRadiusMm = 30;
        cfg.polygonizer.gridN = gridN;
        sculpture = std::make_unique<core::Sculpture>(cfg);
        core::applyStroke(
            *sculpture, core::ToolOp::Add, 5,
            std::vector<core::Vec3>{core::Vec3(-45, -10, 0), core::Vec3(45, -10, 10)});
        poly = std::make_unique<core::Polygonizer>(
            *sculpture, core::zoomRegion(cfg, sculpture->levels(), 1, core::Vec3(0)), 0.125);
        poly->rebuildAll();
    }
};

inline core::Mesh sculptureMesh(int gridN = 64) {
    return SculptureView(gridN).poly->mesh();
}

}  // namespace vsculpt::test
