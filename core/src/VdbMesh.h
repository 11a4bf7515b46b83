// SPDX-License-Identifier: MIT
/// @file VdbMesh.h
/// @brief A mesh as OpenVDB's mesh tools take it (float points, index triples), and OpenVDB's
/// one-time initialisation: shared by the .vdb exporter, solid placement and import repair.
#pragma once

#include "vsculpt/core/Mesh.h"

#include <openvdb/openvdb.h>

#include <mutex>
#include <vector>

namespace vsculpt::core {

/// openvdb::initialize(), once per process (thread-safe).
inline void initializeOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

struct VdbMesh {
    std::vector<openvdb::Vec3s> points;  ///< the mesh's positions as floats, same frame and units
    std::vector<openvdb::Vec3I> triangles;
};

inline VdbMesh toVdbMesh(const Mesh& mesh) {
    VdbMesh out;
    out.points.reserve(mesh.positions.size());
    for (const Vec3& p : mesh.positions)
        out.points.emplace_back(float(p.x), float(p.y), float(p.z));
    out.triangles.reserve(mesh.triangleCount());
    for (size_t t = 0; t < mesh.triangleCount(); ++t)
        out.triangles.emplace_back(mesh.indices[3 * t], mesh.indices[3 * t + 1],
                                   mesh.indices[3 * t + 2]);
    return out;
}

}  // namespace vsculpt::core
