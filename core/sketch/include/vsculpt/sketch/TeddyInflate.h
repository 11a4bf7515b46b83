// Teddy inflation (Igarashi et al., SIGGRAPH 99; seed paper 003 §4.1): a closed outline drawn
// on the canvas becomes a closed, rounded solid whose wide parts are fat and narrow parts thin.
//
// Pipeline: validate → resample to an even edge length → constrained Delaunay triangulation
// (CDT) → classify triangles (terminal / sleeve / junction) → chordal axis → prune short
// branches (diameter-circle test, fans) → split the remaining triangles along the spine →
// lift the spine (height ∝ mean distance to the perimeter vertices joined to it) → lift every
// spine-to-perimeter edge as a quarter ellipse → sew front and back sheets into one mesh.
//
// Frames and units: millimetres. The outline lies on the canvas plane z = 0 (canvas x right,
// y up, viewer at +z). The solid is mirror-symmetric about z = 0; perimeter vertices stay at
// z = 0 and are shared by the front (z ≥ 0) and back (z ≤ 0) sheets.
#pragma once

#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <glm/vec2.hpp>

#include <array>
#include <vector>

namespace vsculpt::sketch {

struct TeddyParams {
    // Target length of the resampled outline's edges (mm). The outline is resampled to
    // max(minSegments, round(perimeter / edgeLength)) equal segments.
    double edgeLength = 2.0;
    int minSegments = 8;
    // Spine height = heightScale × mean distance from the spine vertex to the perimeter
    // vertices joined to it (the article leaves the constant open; 1 makes a circle a sphere).
    double heightScale = 1.0;
    // Segments per quarter ellipse lifted over each spine-to-perimeter edge (≥ 1). Samples are
    // even in the ellipse's angle so the steep part near the perimeter gets as many as the top.
    int ellipseSegments = 6;
};

enum class TeddyTriangleClass {
    Terminal,  // two outline edges: a branch tip
    Sleeve,    // one outline edge: the body of a branch
    Junction,  // no outline edge: where three branches meet
};

// Graph on the canvas plane: points and undirected edges between them (indices into points).
struct TeddyGraph2 {
    std::vector<glm::dvec2> points;
    std::vector<std::array<int, 2>> edges;
};

// Everything inflateOutlineDetailed computes, for tests and for a UI that shows the steps.
struct TeddyInflation {
    // Validated, resampled, counter-clockwise outline (the input reversed if it was clockwise).
    Polyline2 outline;
    // CDT of the outline: counter-clockwise triangles indexing outline, and their classes.
    std::vector<std::array<int, 3>> cdtTriangles;
    std::vector<TeddyTriangleClass> classes;
    // Chordal axis before pruning: midpoints of the internal CDT edges, plus the centroid of
    // each junction triangle joined to its three edge midpoints.
    TeddyGraph2 chordalAxis;
    // Pruned spine; spineHeights[i] is the lift of spine.points[i] (mm, > 0).
    TeddyGraph2 spine;
    std::vector<double> spineHeights;
    // Flat triangulation that is lifted: vertices are outline points [0, outline.size())
    // followed by spine points (spine.points[i] is flatVertices[outline.size() + i]).
    // Counter-clockwise triangles; each has one or two spine vertices.
    std::vector<glm::dvec2> flatVertices;
    std::vector<std::array<int, 3>> flatTriangles;
    // The closed, outward-oriented triangle mesh.
    PolyMesh mesh;
};

// Validates and resamples a closed outline (the last point joins the first; a repeated closing
// point is dropped) into `segments` equal-length segments along its arc length, starting at the
// first point, counter-clockwise. Throws std::invalid_argument for non-finite coordinates,
// fewer than 3 distinct points, zero area, or a self-intersection (the message names the two
// crossing segments and the crossing point), also when the resampling itself self-intersects.
Polyline2 resampleOutline(const Polyline2& outline, int segments);

// Runs the whole pipeline and keeps the intermediate results. Throws std::invalid_argument for a
// bad outline (see resampleOutline) or bad parameters.
TeddyInflation inflateOutlineDetailed(const Polyline2& outline, const TeddyParams& params);

// The inflated mesh only: closed, consistently outward-oriented triangles, Euler
// characteristic 2.
PolyMesh inflateOutline(const Polyline2& outline, const TeddyParams& params);

}  // namespace vsculpt::sketch
