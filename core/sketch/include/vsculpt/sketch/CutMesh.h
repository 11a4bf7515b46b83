// Teddy cutting (seed paper 003 §3.4): a stroke drawn across the solid's silhouette cuts it;
// the part to the right of the stroke direction (as seen on screen) is kept and the section is
// closed with a flat cap.
//
// The article gives no cutting algorithm. Choice made here (see docs/sketch-teddy.md): the cut
// surface is the plane through the stroke's chord (first point to last point) that contains
// the view direction, so the cut face is flat as the issue asks; a curved stroke cuts along
// its chord. The section is capped by a constrained Delaunay triangulation of its boundary
// loops (no added points), so a section with several loops, or loops inside loops, is capped
// correctly. Units: millimetres.
#pragma once

#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace vsculpt::sketch {

// Orthographic view of the sketch canvas: screen point (u, v) in mm is the world point
// origin + u·right + v·up; the viewer looks along −cross(right, up). right and up must be
// orthonormal. The default is the canvas of inflateOutline: world x right, y up, viewer at +z.
struct SketchView {
    glm::dvec3 origin{0.0, 0.0, 0.0};
    glm::dvec3 right{1.0, 0.0, 0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
};

// Plane { x : dot(normal, x − point) = 0 } with unit normal pointing to the discarded side,
// which is also the outward normal of the cap.
struct CutPlane {
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0, 0.0, 1.0};
};

struct MeshCut {
    // Closed, outward-oriented triangle mesh: the kept part plus the cap.
    PolyMesh mesh;
    // mesh.faces[firstCapFace, end) are the cap triangles (all on the cut plane).
    std::size_t firstCapFace = 0;
    // The section's boundary loops (mesh vertex indices) in the cap's own orientation: outer
    // loops counter-clockwise seen from the discarded side, holes clockwise. An extrusion from
    // the cut face would start here.
    std::vector<std::vector<int>> capLoops;
    CutPlane plane;
};

// The plane a cutting stroke defines in the given view: through the stroke's first and last
// points and the view direction, normal towards the left of the stroke (discarded side).
// Throws std::invalid_argument for fewer than 2 points, non-finite points, coincident first
// and last points, or a view whose right/up are not orthonormal.
CutPlane cutPlaneFromStroke(const Polyline2& stroke, const SketchView& view);

// Keeps the part of a closed, consistently oriented mesh on the side opposite plane.normal
// and caps the section. Faces with more than 3 vertices are fan-triangulated (they are
// assumed planar and convex). Vertices within 1e-9 × (mesh size) of the plane are snapped
// onto it. Several kept components are all returned (Teddy's one-object rule is the caller's
// to enforce). Throws std::invalid_argument when the mesh is not closed and oriented, when the
// plane misses the mesh or discards all of it, or when the section touches itself at a vertex.
MeshCut cutMeshByPlane(const PolyMesh& mesh, const CutPlane& plane);

// Teddy's cut: checks that the stroke starts and ends outside the mesh's silhouette in the
// view (std::invalid_argument otherwise, naming the end), then cuts by cutPlaneFromStroke.
MeshCut cutMesh(const PolyMesh& mesh, const Polyline2& stroke, const SketchView& view);

}  // namespace vsculpt::sketch
