// Private: constrained Delaunay triangulation of polygonal regions for Teddy inflation and for
// capping cut sections. Kept behind a plain interface so CGAL is compiled in one translation
// unit only (TeddyCdt.cpp).
#pragma once

#include <glm/vec2.hpp>

#include <array>
#include <vector>

namespace vsculpt::sketch::detail {

// Triangulates the region enclosed by the closed loops (indices into points; each loop's last
// index joins its first). Loop edges are constraints; no points are added. A triangle is kept
// when it lies inside an odd number of loops (outer boundaries and holes alike), so nested
// loops give holes. Returned triangles index points and are counter-clockwise.
// Throws std::invalid_argument when two loops or loop edges cross (CGAL would need to insert
// intersection points) or a loop has fewer than 3 points.
std::vector<std::array<int, 3>> triangulateLoops(const std::vector<glm::dvec2>& points,
                                                 const std::vector<std::vector<int>>& loops);

}  // namespace vsculpt::sketch::detail
