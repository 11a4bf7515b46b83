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

/// "inflate", "three-section", "sweep", "cut", "extrude"; std::invalid_argument otherwise.
sketch::SolidConstruction constructionFromName(const std::string& name);

/// Gathers each role's polyline: from the current page first, then the other pages in order
/// (the first polyline with a role wins). A polyline's view is its page's plane, except where
/// the construction fixes it (three-section: outline and Y front, X side, Z top; sweep: section
/// side, path top). Extrude: the closed Extrude polyline is the base, the open one the
/// silhouette. `previous` is the solid cut and extrude change.
sketch::SketchSolidInput sketchSolidInput(sketch::SolidConstruction construction,
                                          const studio::SketchDocument& document,
                                          size_t currentPage,
                                          const std::vector<sketch::SketchPlane>& planes,
                                          const std::optional<sketch::PolyMesh>& previous);

/// The same triangles as a core mesh (no normals).
core::Mesh toMesh(const sketch::TriangleMesh& triangles);

}  // namespace vsculpt::studio
