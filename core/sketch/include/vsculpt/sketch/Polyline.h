// 2D and 3D polylines shared by the sketch geometry. Units: millimetres on the sketch canvas
// (tablet or window space scaled to mm); canvas x to the right, y up.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <vector>

namespace vsculpt::sketch {

using Polyline2 = std::vector<glm::dvec2>;
using Polyline3 = std::vector<glm::dvec3>;

// Signed area of a closed polygon (last point joins the first); positive counter-clockwise.
double signedArea(const Polyline2& polygon);
// Centroid of the area a closed polygon encloses. @pre signedArea(polygon) != 0.
glm::dvec2 areaCentroid(const Polyline2& polygon);

// Length of the polyline; closed adds the segment from the last point back to the first.
double length(const Polyline2& line, bool closed);
double length(const Polyline3& line, bool closed);

}  // namespace vsculpt::sketch
