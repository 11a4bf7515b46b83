// A polygon mesh with n-gon faces: the control meshes of Doo–Sabin subdivision, swept prisms
// and inflated (Teddy) solids. Units: millimetres. Faces list vertex indices counter-clockwise
// seen from outside, so normals point out of a closed solid.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace vsculpt::sketch {

struct PolyMesh {
    std::vector<glm::dvec3> vertices;
    std::vector<std::vector<int>> faces;
};

// Number of distinct undirected edges.
std::size_t countEdges(const PolyMesh& mesh);

// V − E + F.
long eulerCharacteristic(const PolyMesh& mesh);

// True when every edge is used by exactly two faces, once in each direction (closed,
// consistently oriented 2-manifold edges), and every index is in range.
bool isClosedOriented(const PolyMesh& mesh);

// Enclosed volume by the divergence theorem over a fan triangulation of each face; positive
// for outward-oriented closed meshes (mm³).
double enclosedVolume(const PolyMesh& mesh);

}  // namespace vsculpt::sketch
