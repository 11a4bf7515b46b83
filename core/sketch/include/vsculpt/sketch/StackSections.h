// Stacking horizontal sections into one control mesh (seed 000 §6.3): each section polygon is
// swept into a short prism along z, and consecutive prisms are joined even when their vertex
// counts differ, by the seed's centroid-sector correspondence. Doo–Sabin keeps every prism's
// mid-plane section exactly (Chaikin polygon at each level), so the surface passes through the
// drawn sections. Units: millimetres; sections in (x, y), z up.
#pragma once

#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <vector>

namespace vsculpt::sketch {

struct StackedSection {
    Polyline2
        polygon;   // control polygon in (x, y), either orientation, star-shaped about its centroid
    double z = 0;  // height of the section plane (the prism's mid-plane)
    double halfHeight = 0;  // the prism spans [z − halfHeight, z + halfHeight], > 0
};

// For rings a (fewer vertices) and b, both counter-clockwise and overlaid at their area
// centroids: the plane around the centroid is cut into one sector per vertex of a by the
// bisectors of consecutive rays to a's vertices; b's vertices correspond to the a-vertex of
// their sector. A sector left empty takes the nearest vertex from the nearer neighbouring sector
// holding two or more (the denser side on a tie), shifting the sectors in between by one.
// Returns, for each vertex i of a, the first index in b of its run and the run length (≥ 1);
// runs are consecutive around b. Throws std::invalid_argument when a has more vertices than b,
// either ring is not a simple counter-clockwise polygon, or b's vertices do not go round the
// centroid in order (ring not star-shaped about it).
struct SectorRun {
    int first;
    int count;
};
std::vector<SectorRun> sectorCorrespondence(const Polyline2& a, const Polyline2& b);

// Closed, outward-oriented control mesh: the prisms of the sections (sorted by z; they must
// not overlap) joined ring to ring by quads between sectors and one fan polygon per sector
// holding several vertices (faces as large as possible, no triangulation), capped by the first
// and last section polygons. Throws std::invalid_argument for fewer than one section, a bad
// polygon, halfHeight ≤ 0 or overlapping prisms.
PolyMesh stackSections(std::vector<StackedSection> sections);

}  // namespace vsculpt::sketch
