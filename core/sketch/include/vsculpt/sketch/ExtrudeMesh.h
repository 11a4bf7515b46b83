// Teddy extrusion (seed paper 003 §3.3, §4.2): a closed base stroke drawn on the surface and a
// second stroke, drawn after rotating the view, giving the silhouette of the protrusion. The
// faces inside the base loop are removed and a sweep of copies of the base loop along the
// silhouette closes the hole again. A silhouette drawn into the solid digs a dent instead.
//
// Choices where the article is silent (docs/sketch-teddy.md):
//  * The base loop follows mesh edges: it is the boundary of the faces that face the base
//    view and whose centroids project inside the base stroke (no surface painting/re-meshing).
//  * The silhouette stroke is cast along the view direction onto the plane through the base
//    loop's centroid g that contains the base normal v and is closest to perpendicular to the
//    view (normal = c − (c·v̂)v̂, c pointing to the viewer). Views within ~11.5° of v
//    (|c − (c·v̂)v̂| < 0.2) are rejected: the cast would magnify pen jitter by over 5×.
//  * Two pointers start at the stroke's ends and move inward; each step advances the one that
//    keeps the pointer segment closest to perpendicular to the stroke at both pointers. Each
//    pointer pair gets a copy of the base loop, scaled uniformly so its extent along the pair
//    equals the pair's distance and centred on the pair's midpoint (not rotated: a sweep).
//    The first pair (the stroke's ends) is the base loop itself; the last copy is closed by a
//    fan to the midpoint of the last pair.
// Units: millimetres.
#pragma once

#include "vsculpt/sketch/CutMesh.h"
#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <utility>
#include <vector>

namespace vsculpt::sketch {

struct ExtrudeParams {
    // Spacing of the silhouette stroke after it is projected and resampled (mm): the pointer
    // steps, hence the spacing of the copies along the protrusion.
    double stepLength = 2.0;
};

struct Extrusion {
    // Closed, consistently oriented mesh (outward for protrusions; a dent's walls face into
    // the dent). Faces [firstNewFace, end) are the swept tube and its tip.
    PolyMesh mesh;
    std::size_t firstNewFace = 0;
    // The base loop (mesh vertex indices, original positions), counter-clockwise around
    // baseNormal.
    std::vector<int> baseLoop;
    // Newell vector of the base loop: its area-weighted normal (|v| = area when planar).
    glm::dvec3 baseNormal{0.0};
    // Plane the silhouette stroke was projected onto, and the projected, resampled stroke.
    glm::dvec3 sweepPlanePoint{0.0};
    glm::dvec3 sweepPlaneNormal{0.0};
    Polyline3 sweepStroke;
    // Pointer pairs (indices into sweepStroke), first the stroke's ends.
    std::vector<std::pair<int, int>> pointerPairs;
};

// Newell's vector ½ Σ pᵢ × pᵢ₊₁ of a closed 3D loop: normal to the loop, length = area for a
// planar loop; counter-clockwise loops point towards the viewer.
glm::dvec3 newellNormal(const Polyline3& loop);

// Faces facing the view (normal towards the viewer) whose centroids project inside the closed
// stroke (screen mm). Throws std::invalid_argument for a stroke with fewer than 3 points or
// non-finite points.
std::vector<int> facesInsideStroke(const PolyMesh& mesh, const Polyline2& stroke,
                                   const SketchView& view);

// Replaces the disk-shaped patch `region` (face indices) of a closed, oriented mesh by a sweep
// of its boundary along the silhouette stroke drawn in `view`. Throws std::invalid_argument
// when the mesh is not closed and oriented, the region is empty, the whole mesh, or not a
// disk (one simple boundary loop, Euler characteristic 1), the view is within ~11.5° of the
// base normal, or the stroke has fewer than 2 distinct points or non-finite points.
Extrusion extrudeRegion(const PolyMesh& mesh, const std::vector<int>& region,
                        const Polyline2& silhouette, const SketchView& view,
                        const ExtrudeParams& params);

// Teddy's extrusion: region = facesInsideStroke(mesh, baseStroke, baseView), then
// extrudeRegion with the silhouette stroke drawn in silhouetteView. To extrude from a cut
// face, call extrudeRegion with the cap faces of a MeshCut.
Extrusion extrudeMesh(const PolyMesh& mesh, const Polyline2& baseStroke, const SketchView& baseView,
                      const Polyline2& silhouette, const SketchView& silhouetteView,
                      const ExtrudeParams& params);

}  // namespace vsculpt::sketch
