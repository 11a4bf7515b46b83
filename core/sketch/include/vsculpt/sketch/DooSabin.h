// Doo–Sabin subdivision of closed polygon meshes with n-gon faces (the surface analogue of
// Chaikin corner cutting; its limit is a quadratic B-spline surface away from extraordinary
// points). Units are those of the input (mm).
#pragma once

#include "vsculpt/sketch/PolyMesh.h"

namespace vsculpt::sketch {

// `levels` Doo–Sabin steps with the classic weights: in a face with n corners v₀…vₙ₋₁ the new
// point for corner i is Σⱼ αⱼ vᵢ₊ⱼ, α₀ = 1/4 + 5/(4n), αⱼ = (3 + 2cos(2πj/n))/(4n) (for quads
// 9/16, 3/16, 1/16, 3/16, which is tensor-product Chaikin). New faces: one per old face
// (same corner count), one quad per old edge and one per old vertex (valence corners), so a
// step maps (V, E, F) to (2E, 4E, F + E + V) and keeps the Euler characteristic.
// Output faces keep the input orientation (counter-clockwise seen from outside).
// Vertex order of one step: the corners of face 0 in face order, then of face 1, and so on.
// Throws std::invalid_argument unless isClosedOriented(mesh), every vertex is used by a face
// and is finite, and levels is in [0, 8].
PolyMesh dooSabin(const PolyMesh& mesh, int levels);

}  // namespace vsculpt::sketch
