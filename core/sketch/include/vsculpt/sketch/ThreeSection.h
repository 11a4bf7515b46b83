// Three-section reconstruction (seed 001 §4–5, seed 000 §7.5): a mirror-symmetric solid from an
// outline plus three mutually orthogonal surface lines (面上線). The surface lines, already split
// at their crossings and rotated flat (curves (a)–(d) of the seed), give three axis sections;
// each section becomes an inverse-Chaikin control polygon swept into a prism, and the Boolean
// intersection of the three prisms (相貫体), with coplanar triangles merged back into n-gons,
// is the Doo–Sabin control mesh. Its silhouette along each axis is that axis's section polygon.
//
// Frame and units: millimetres; z up, x front–back, y lateral with the symmetry plane y = 0.
// Section coordinates follow Prism.h: z-section (x, y) plan, x-section (y, z) transverse,
// y-section (x, z) side profile.
#pragma once

#include "vsculpt/sketch/InverseChaikin.h"
#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <vector>

namespace vsculpt::sketch {

struct HiddenBottom {
    double L4;  // virtual length of the invisible part, L4 = L1/L2·L3
    double h4;  // virtual depth of the bottom below z = 0, h4 = (L3 + L4)/L3·h3
};

// The seed's Eq. 1. L1, L2: two visible lengths whose ratio is extrapolated; L3: visible length
// of the lower part; h3: its visible height (all mm, > 0, finite; otherwise
// std::invalid_argument).
HiddenBottom estimateHiddenBottom(double L1, double L2, double L3, double h3);

// Curves (a)–(d) after splitting and rotation, each an open polyline of at least 2 points.
struct SurfaceLines {
    // (a) the line along the back: upper side profile in (x, z), from one end on z = 0 over the
    // top to the other end on z = 0. Reference for lengths (x) and height (z).
    Polyline2 back;
    // (b) the line around the torso: half of the plan section in (x, y), y ≥ 0, from one end on
    // y = 0 to the other. Reference for the half width (y); its x extent is scaled to (a)'s.
    Polyline2 torso;
    // (c) the line across the belly: half transverse section in (y, z), from the top (y = 0)
    // outwards and down to its lowest visible point. Scaled to (b)'s half width and (a)'s
    // height.
    Polyline2 belly;
    // (d) the visible lower side profile in (x, z), z ≤ 0, end to end; its x extent is scaled to
    // (a)'s and its z so that its lowest point is at −h4.
    Polyline2 bottom;
    // Measurements for estimateHiddenBottom.
    double L1 = 1, L2 = 1, L3 = 1, h3 = 1;
};

// The three closed axis sections (section coordinates of Prism.h).
struct ThreeSections {
    Polyline2 z;  // plan: (b) and its mirror image in y = 0
    Polyline2 x;  // transverse: (c) made symmetric, closed by a natural spline through (0, −h4)
    Polyline2 y;  // side: (a) joined to (d) scaled to reach z = −h4
    HiddenBottom bottom{};
};

// Sections from the surface lines. Throws std::invalid_argument for curves with fewer than
// 2 points, non-finite values, or zero extents.
ThreeSections buildSections(const SurfaceLines& lines);

struct ThreeSectionSolid {
    ThreeSections sections;
    // Inverse-Chaikin control polygons of sections z, x, y (in that order); those of z and x
    // are made exactly mirror-symmetric about y = 0 (positive half kept and mirrored).
    Polyline2 polygons[3];
    // Intersection of the three prisms with coplanar facets merged: closed, outward, n-gons.
    PolyMesh controlMesh;
};

// Sections → control polygons → prisms (long enough to cover the others) → intersection.
// Throws std::invalid_argument for bad input and std::runtime_error when the Boolean fails.
ThreeSectionSolid reconstructThreeSections(const SurfaceLines& lines,
                                           const InverseChaikinOptions& options = {});
// The same from sections given directly (a section edited by hand, or a synthetic test).
ThreeSectionSolid reconstructFromSections(const ThreeSections& sections,
                                          const InverseChaikinOptions& options = {});

// Boolean intersection of closed, outward-oriented solids (CGAL corefinement with exact
// constructions), returned with every maximal set of edge-connected coplanar triangles merged
// into one n-gon (when it is a disc) and vertices lying on only two faces removed, so the
// result is a good Doo–Sabin control mesh. Throws std::invalid_argument for fewer than one
// solid or a solid that is not closed and oriented, std::runtime_error when the Boolean fails
// or the intersection is empty.
PolyMesh intersectSolids(const std::vector<PolyMesh>& solids);

}  // namespace vsculpt::sketch
