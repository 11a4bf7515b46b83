// Prisms (柱体) swept from planar section polygons along a coordinate axis: the building block
// of the sketch-to-subdivision-surface methods. A prism's Doo–Sabin subdivision cut at its
// mid-plane is exactly the Chaikin subdivision of its section, at every level.
// Units: millimetres. World frame: z up, symmetry plane y = 0 (see ThreeSection.h).
#pragma once

#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace vsculpt::sketch {

// The axis a section is perpendicular to, and along which its prism is swept.
enum class Axis { X, Y, Z };

// Section-plane coordinates (u, v) of each axis, chosen so each section reads naturally:
//   Z (plan):       u = x, v = y
//   X (transverse): u = y, v = z
//   Y (side):       u = x, v = z
// w is the coordinate along the axis.
glm::dvec3 sectionToWorld(Axis axis, const glm::dvec2& uv, double w);
glm::dvec2 worldToSection(Axis axis, const glm::dvec3& p);

// Closed prism with the section's two copies at w = from and w = to (section plane halfway)
// and one quad per section edge; caps are single n-gons. Faces are oriented outward whatever
// the section's orientation. Vertex i is section point i at w = from, vertex n + i the same
// point at w = to (after the section has been made counter-clockwise in (u, v)).
// Throws std::invalid_argument for fewer than 3 points, non-finite values, from ≥ to, zero
// area or a self-intersecting section.
PolyMesh sweepPrism(const Polyline2& section, Axis axis, double from, double to);

// Throws std::invalid_argument (message starts with `what`) unless the closed polygon has at
// least 3 finite points, non-zero area and no two non-adjacent edges touching.
void requireSimplePolygon(const Polyline2& polygon, const char* what);

}  // namespace vsculpt::sketch
