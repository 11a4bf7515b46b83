// SPDX-License-Identifier: MIT
/// @file Mesh.h
/// @brief Indexed triangle meshes, their canonical hash and topology checks.
#pragma once

#include "vsculpt/core/Geometry.h"

#include <cstdint>
#include <string>
#include <vector>

namespace vsculpt::core {

/// Indexed triangle mesh in object space (mm). Triangles are counter-clockwise seen from
/// outside (normals point out of the material).
struct Mesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;      ///< unit, one per position (empty when not computed)
    std::vector<uint32_t> indices;  ///< 3 per triangle
    size_t triangleCount() const { return indices.size() / 3; }
};

/// Hash of the mesh as a set of triangles of positions: independent of vertex order,
/// triangle order and which vertex a triangle starts at (orientation is kept). Two meshes
/// with equal hashes have, barring collisions, bitwise identical geometry.
uint64_t canonicalMeshHash(const Mesh& mesh);

struct MeshTopology {
    size_t vertices = 0, edges = 0, triangles = 0;
    size_t boundaryEdges = 0;      ///< used by one triangle
    size_t nonManifoldEdges = 0;   ///< used by more than two
    size_t misorientedEdges = 0;   ///< used twice in the same direction
    size_t components = 0;         ///< connected through shared vertices
    long eulerCharacteristic = 0;  ///< V - E + F over referenced vertices
    /// Closed, 2-manifold and consistently oriented.
    bool watertight() const {
        return triangles > 0 && boundaryEdges == 0 && nonManifoldEdges == 0 &&
               misorientedEdges == 0;
    }
};

MeshTopology analyzeTopology(const Mesh& mesh);

/// Signed volume (mm^3) by the divergence theorem; positive for outward-oriented meshes.
double meshVolume(const Mesh& mesh);
Aabb meshBounds(const Mesh& mesh);

/// Empty when the meshes are equal as canonical triangle sets; otherwise a description of
/// the first difference (the smallest triangle present in one and not the other).
std::string firstMeshDifference(const Mesh& a, const Mesh& b);

}  // namespace vsculpt::core
