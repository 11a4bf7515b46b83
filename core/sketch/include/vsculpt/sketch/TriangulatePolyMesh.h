// Triangulation of polygon meshes (n-gons, possibly non-planar or non-convex) for consumers that
// take triangles only: the clay converter, DXF 3DFACE export, the viewer. Units: those of the
// input (mm).
#pragma once

#include "vsculpt/sketch/PolyMesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace vsculpt::sketch {

// Indexed triangles; triangles are counter-clockwise seen from outside, like the PolyMesh faces
// they come from. Positions are the PolyMesh's vertices, same order (no points are added).
struct TriangleMesh {
    std::vector<glm::dvec3> positions;
    std::vector<std::uint32_t> indices;  // 3 per triangle
};

// Splits every face into (n − 2) triangles over its own corners, keeping its orientation:
//  * a face whose projection onto its Newell plane is strictly convex is fanned from its
//    first corner, exactly the triangles enclosedVolume() integrates over, so the volume of a
//    mesh of such faces is kept even where the faces are not planar (Doo–Sabin quads);
//  * any other face (the concave merged caps of the three-section solid, cut caps) is
//    ear-clipped in that projection, so no triangle folds over; for planar faces this too keeps
//    the volume.
// Face boundary edges are kept and each added diagonal is used by two triangles in opposite
// directions, so a closed, consistently oriented PolyMesh stays closed and oriented (unless a
// diagonal joins two corners that another face already joins by an edge).
// Throws std::invalid_argument for a face with fewer than 3 corners, an index out of range, or
// a vertex count beyond uint32.
TriangleMesh triangulatePolyMesh(const PolyMesh& mesh);

// The triangles as a PolyMesh (for the PolyMesh checks: isClosedOriented, enclosedVolume).
PolyMesh toPolyMesh(const TriangleMesh& mesh);

}  // namespace vsculpt::sketch
