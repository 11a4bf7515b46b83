// SPDX-License-Identifier: MIT
/// @file ExportDxf.h
/// @brief DXF for CAD tools (seed F-29): triangle surfaces as 3DFACE entities and curves as
/// 3D POLYLINE entities, each on a named layer, in an AutoCAD R12 (AC1009) ASCII file.
///
/// Why these entities: R12 3DFACE and 3D POLYLINE are read by every DXF consumer we know of
/// (ezdxf, LibreCAD, FreeCAD, AutoCAD), need no handles or object tables, and represent any
/// curve whether or not it is planar, so no planarity test (LWPOLYLINE would need one plus an
/// OCS) decides the entity type. A 3DFACE has four corners; a triangle repeats its third.
///
/// Units and axes: DxfOptions::frame, Z-up millimetres by default (CAD's world frame); the unit
/// is written to $INSUNITS (4 mm, 5 cm, 6 m) so CAD scales the drawing on insertion.
/// Coordinates are written with 17 significant digits so a reader gets the doubles back
/// exactly. The file is rendered in memory and written with
/// writeFileAtomically (not durable), so a failed export never leaves a half-written file.
#pragma once

#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/Geometry.h"
#include "vsculpt/core/Mesh.h"

#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace vsculpt::core {

struct DxfOptions {
    /// Layer of surface i: surfaceLayers[i], or surfaceLayer when the list is shorter.
    std::vector<std::string> surfaceLayers;
    std::string surfaceLayer = "surface";
    /// Layer of curve i: curveLayers[i], or curveLayer when the list is shorter.
    std::vector<std::string> curveLayers;
    std::string curveLayer = "curve";
    /// Curve i is a closed polyline (last point joins the first) when closedCurves[i] is true;
    /// open when the list is shorter.
    std::vector<bool> closedCurves;
    /// Frame of every coordinate written, surfaces and curves alike (ExportMesh.h).
    ExportFrame frame;
};

/// Writes the surfaces (every triangle of each mesh, counter-clockwise corners kept) and the
/// curves (object-space points, mm), both turned and scaled into options.frame. Throws
/// std::invalid_argument, naming the surface, curve or layer, for a triangle index out of range, a
/// non-finite coordinate, a curve with fewer than 2 points, a layer name that is empty or holds a
/// character DXF forbids (<>/\":;?*|=`), or nothing to write; ExportError naming the path when the
/// file cannot be written.
void writeDxf(const std::filesystem::path& path, std::span<const Mesh> surfaces,
              std::span<const std::vector<Vec3>> curves, const DxfOptions& options = {});

}  // namespace vsculpt::core
