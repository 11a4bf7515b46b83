// From sketch roles to solids (issue #8): the pure step between the sketch document (strokes with
// roles) and the clay converter (a closed triangle mesh). One call builds the whole solid from
// the role polylines; editing a polyline and calling again gives the edited solid (no state, so
// regeneration after an overdraw is just another call, seed F-27).
//
// Frames and units. Role polylines are canvas millimetres (x right, y up) on one of three
// orthographic views; object space is millimetres, z up, and is right-handed:
//   Front view: canvas (x, y) → object (x, z); viewer at −y looking along +y.
//   Side view:  canvas (x, y) → object (y, z); viewer at +x looking along −x.
//   Top view:   canvas (x, y) → object (x, y); viewer at +z looking along −z.
// The canvas origin of every view is the object origin. For each view, right × up points to
// the viewer, so a counter-clockwise stroke on the canvas is counter-clockwise seen by that
// viewer. The three-section frame of ThreeSection.h is this frame: x front–back, y lateral with
// the symmetry plane y = 0, z up.
//
// Constructions (docs/sketch-mode.md, "From sketch to solid"):
//   Inflate       Teddy inflation of a closed outline drawn on any view; the solid is
//                 mirror-symmetric about that view's canvas plane through the origin.
//   ThreeSection  Outline (front view, closed) + surface lines X (side view: the line across
//                 the belly, (c)), Y (front view: the line along the back, (a)) and Z (top
//                 view: the line around the torso, (b)) → reconstructThreeSections → Doo–Sabin.
//   Sweep         A closed section drawn on the side view swept along an open path drawn on
//                 the top view, with rotation-minimising frames, mitred joints and flat caps.
//   Cut           cutMesh of a previous solid by an open stroke on any view.
//   Extrude       extrudeMesh of a previous solid: a closed base stroke on one view and a
//                 silhouette stroke on another.
#pragma once

#include "vsculpt/sketch/CutMesh.h"
#include "vsculpt/sketch/ExtrudeMesh.h"
#include "vsculpt/sketch/InverseChaikin.h"
#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"
#include "vsculpt/sketch/TeddyInflate.h"
#include "vsculpt/sketch/TriangulatePolyMesh.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace vsculpt::sketch {

enum class SketchPlane { Front, Side, Top };

// "front", "side" or "top": the view's name in sketch.json, scripts and messages.
const char* sketchPlaneName(SketchPlane plane);

// The view's canvas frame as a SketchView (origin 0, right, up), for cutMesh and extrudeMesh.
SketchView sketchPlaneView(SketchPlane plane);
// Canvas mm on the view → object mm on the view's canvas plane (through the origin).
glm::dvec3 canvasToObject(SketchPlane plane, const glm::dvec2& canvas);
Polyline3 canvasToObject(SketchPlane plane, const Polyline2& canvas);

enum class SolidConstruction { Inflate, ThreeSection, Sweep, Cut, Extrude };
const char* constructionName(SolidConstruction construction);  // "inflate", "three-section", ...

// One role polyline as the sketch document hands it over (canvas mm).
struct SketchCurve {
    Polyline2 points;
    bool closed = false;  // the last point joins the first
};

struct SweepParams {
    // The section is resampled to this many equal-length edges (≥ 3).
    int sectionSegments = 24;
    // Path points closer than step/2 are merged and longer segments split, so rings are about
    // `step` mm apart (> 0).
    double step = 2.0;
    // Paths shorter than this are rejected (mm, > 0).
    double minPathLength = 1.0;
    // Doo–Sabin levels applied to the swept control mesh (0 keeps the exact mitred tube).
    int subdivisionLevels = 0;
};

struct SketchSolidParams {
    TeddyParams teddy;
    InverseChaikinOptions inverseChaikin;
    // Doo–Sabin levels applied to the three-section control mesh (0..8).
    int threeSectionLevels = 3;
    SweepParams sweep;
    ExtrudeParams extrude;
};

struct SketchSolidInput {
    SolidConstruction construction = SolidConstruction::Inflate;
    // Inflate: on outlinePlane. ThreeSection: on the front view (outlinePlane is ignored).
    std::optional<SketchCurve> outline;
    SketchPlane outlinePlane = SketchPlane::Front;
    // ThreeSection: open surface lines, planes fixed as described above.
    std::optional<SketchCurve> surfaceLineX, surfaceLineY, surfaceLineZ;
    // Sweep: closed section on the side view, open path on the top view.
    std::optional<SketchCurve> sweepSection, sweepPath;
    // Cut and Extrude: the solid they change (closed, outward oriented; not owned elsewhere:
    // the input holds its own copy).
    std::optional<PolyMesh> previous;
    std::optional<SketchCurve> cutStroke;
    SketchPlane cutPlane = SketchPlane::Front;
    std::optional<SketchCurve> extrudeBase, extrudeSilhouette;
    SketchPlane extrudeBasePlane = SketchPlane::Front;
    SketchPlane extrudeSilhouettePlane = SketchPlane::Side;
    SketchSolidParams params;
};

struct SketchSolid {
    // Closed, consistently outward-oriented polygon mesh (mm, object space): what a later Cut or
    // Extrude takes as `previous`.
    PolyMesh polyMesh;
    // Its triangulation (same vertices), for the clay converter and exports.
    TriangleMesh triangles;
    double volume = 0.0;        // enclosedVolume(polyMesh), mm³, > 0
    glm::dvec3 centroid{0.0};   // centre of the enclosed volume (mm)
    glm::dvec3 boundsMin{0.0};  // axis-aligned bounds of the vertices (mm)
    glm::dvec3 boundsMax{0.0};
};

// Builds the construction's solid. Throws std::invalid_argument naming what is wrong ("outline
// missing", "outline is not closed", "surface line Y missing", "sweep path crosses itself at …",
// "previous solid missing", …) and passes on the messages of the underlying steps (Teddy's
// outline checks, cutMesh's silhouette checks, …) prefixed with the role; std::runtime_error
// when the three-section Boolean fails or a result is not a closed oriented solid (a bug).
SketchSolid buildSketchSolid(const SketchSolidInput& input);

// The sweep on its own: `section` is the closed section in side-view canvas mm, `path` the open
// path in top-view canvas mm. The section's area centroid rides on the path, at the height
// (object z) of that centroid on the side view; at the path's start the section keeps its
// drawn orientation when the path heads towards the side view's viewer (+x): canvas x → the
// frame's side vector, canvas y → its up vector (+z for the horizontal paths of the top view).
// Frames are parallel-transported from segment to segment (the exact rotation-minimising
// frames of a polyline) and each ring lies in the bisector plane of its two segments (mitre),
// which is where the two segments' tubes meet. Path points too close to a sharp turn for the
// mitred rings not to fold are dropped when that moves the path by at most params.step (the
// straight run beside a corner, a rounded corner tighter than the section); otherwise the
// section is too large for the turn and the sweep is rejected. Returns a closed, outward-oriented
// PolyMesh with quad walls and two n-gon caps (subdivided when params.subdivisionLevels > 0).
// Throws std::invalid_argument for: a section that is not a simple closed polygon with area
// (fewer than 3 points, self-intersecting, zero area), a path with fewer than 2 distinct
// points, a self-intersecting path, a path shorter than params.minPathLength, a turn sharper
// than 135° or one the section cannot follow, non-finite values or bad params.
PolyMesh sweepSectionAlongPath(const Polyline2& section, const Polyline2& path,
                               const SweepParams& params);

}  // namespace vsculpt::sketch
