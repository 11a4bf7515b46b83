// SPDX-License-Identifier: MIT
// Shared fixtures of the app tests: a small, quick config and a temporary folder.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/Mesh.h"
#include "vsculpt/studio/Session.h"

#include <unistd.h>

#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <tuple>

namespace vsculpt::test {

/// The default config with a smaller initial sphere and a coarser view grid (fast tests).
inline core::SculptConfig smallConfig(double sphereRadiusMm = 30) {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = sphereRadiusMm;
    cfg.polygonizer.gridN = 64;
    return cfg;
}

/// The canonical hash of the mesh on show.
inline uint64_t viewHash(const studio::Session& s) {
    return core::canonicalMeshHash(s.view().mesh());
}

/// Every skeleton's weight by (level, x, y, z): two sculptures hold the same clay bit for bit
/// exactly when these are equal.
using Weights = std::map<std::tuple<int, int, int, int>, float>;
inline Weights weightsOf(const core::Sculpture& s) {
    Weights w;
    s.store().forEach([&](const core::SkeletonEntry& e) {
        w[{e.level, e.coord.x, e.coord.y, e.coord.z}] = e.weight;
    });
    return w;
}

/// A temporary folder removed at the end of the test.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        path =
            std::filesystem::temp_directory_path() / ("vsculpt-test-" + std::to_string(::getpid()) +
                                                      "-" + std::to_string(std::random_device{}()));
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
};

}  // namespace vsculpt::test
