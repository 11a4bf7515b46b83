// SPDX-License-Identifier: MIT
/// @file SketchSolids.h
/// @brief From the sketch document's roles to the solid builder's input, and from its
/// triangles to the core's mesh (docs/sketch-mode.md, "From sketch to solid").
#pragma once

#include "vsculpt/core/Mesh.h"
#include "vsculpt/sketch/SketchSolid.h"
#include "vsculpt/studio/SketchDocument.h"

#include <optional>
#include <string>
#include <vector>

namespace vsculpt::studio {

/// A role as scripts and messages write it: "none", "outline", "surface-x", ..., "extrude".
const char* roleScriptWord(studio::Role role);
/// The role a script word names; std::invalid_argument ("unknown role 'W'") otherwise.
studio::Role roleFromScriptWord(const std::string& word);

/// "inflate", "three-section", "sweep", "cut", "extrude"; std::invalid_argument otherwise.
sketch::SolidConstruction constructionFromName(const std::string& name);

/// One polyline a solid was built from: its page and its stroke or clean-curve id. A solid
/// built again from the same polylines (edited) replaces the first; from others it is a new
/// solid.
struct PolylineRef {
    size_t page = 0;
    bool fromCurve = false;
    int id = -1;
    bool operator==(const PolylineRef&) const = default;
};

/// Gathers each role's polyline: from the current page first, then the other pages in order
/// (the first page with one wins). Two polylines with one role on that page (two outlines)
/// are refused (std::invalid_argument naming the page and the strokes), rather than one
/// silently ignored. A polyline's view is its page's plane; three-section needs its outline and
/// surface-y on a front view, surface-x on a side view and surface-z on a top view, sweep its
/// section on a side view and its path on a top view, and a line on another view is refused
/// (std::invalid_argument naming the page and its view). Extrude: the closed Extrude polyline
/// is the base, the open one the silhouette. `previous` is the solid cut and extrude change.
/// `used`, when given, receives the polylines used, in a fixed order.
sketch::SketchSolidInput sketchSolidInput(sketch::SolidConstruction construction,
                                          const studio::SketchDocument& document,
                                          size_t currentPage,
                                          const std::vector<sketch::SketchPlane>& planes,
                                          const std::optional<sketch::PolyMesh>& previous,
                                          std::vector<PolylineRef>* used = nullptr);

/// The same triangles as a core mesh (no normals).
core::Mesh toMesh(const sketch::TriangleMesh& triangles);

}  // namespace vsculpt::studio
