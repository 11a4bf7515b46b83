// SPDX-License-Identifier: MIT
/// @file ViewState.h
/// @brief Where a sculptor left off: the tool, its size, the zoom and its centre, the mirror
/// plane and the sculpture's pose. The windows and the headset keep it in the project
/// (`DIR/view.json`) as they close, and bring it back when they open the project again, so a
/// sculptor who turned the piece and zoomed into a detail finds it as they left it.
///
/// It is not part of the sculpture: the snapshot and the journal never depend on it, a
/// missing or unreadable file costs only the view (the session starts at the defaults and
/// says why), and `vsculpt play` neither reads nor writes it (a script starts from the
/// defaults, docs/playback.md).
#pragma once

#include "vsculpt/core/Geometry.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/studio/Script.h"

#include <filesystem>
#include <optional>
#include <string>

namespace vsculpt::studio {

class Session;
class Studio;

struct ViewState {
    ToolKind tool = ToolKind::Add;
    core::MirrorAxis mirror = core::MirrorAxis::None;
    int size = 7;  ///< tool level 1..7, offered at `zoom`
    int zoom = 1;  ///< 1..5
    /// Object space, mm: the middle of the zoom region (unused at zoom 1).
    core::Vec3 zoomCentreMm{0.0};
    /// The sculpture's pose in the world (mm); the world is the window's or the headset's.
    core::RigidTransform worldFromObject;
    /// Every field exactly (the pose bit for bit).
    bool operator==(const ViewState& o) const {
        return tool == o.tool && mirror == o.mirror && size == o.size && zoom == o.zoom &&
               zoomCentreMm == o.zoomCentreMm &&
               worldFromObject.rotation == o.worldFromObject.rotation &&
               worldFromObject.translation == o.worldFromObject.translation;
    }
};

/// The session's tool, size, zoom (the middle of its region), mirror plane and pose.
ViewState viewStateOf(const Session& session);

/// Sets `state` on the studio: pose, zoom, size, tool, mirror, in that order (a size is offered
/// only at its zooms). Throws SessionError (changing what was set before it) for a size the
/// zoom does not offer or a zoom centre that is not a usable point.
void applyViewState(Studio& studio, const ViewState& state);

/// The file in a project folder: `dir`/view.json.
std::filesystem::path viewStatePath(const std::filesystem::path& dir);

/// The file's text (JSON, one object; the rotation as a unit quaternion w, x, y, z).
std::string viewStateJson(const ViewState& state);

/// Reads the text viewStateJson wrote. Throws std::invalid_argument naming `source` and the
/// field (or the line and column of a JSON error) for anything else: a missing field, an
/// unknown tool or plane, a size or zoom out of range, a centre or translation that is not a
/// usable point, a rotation that is not a unit quaternion (within 1e-6; kept as written).
/// Whether the zoom offers the size depends on the config: applyViewState says.
ViewState parseViewState(const std::string& text, const std::string& source);

/// Writes `dir`/view.json atomically (not flushed to disk: a power loss may take it, never
/// the work). Throws core::FileWriteError naming the file.
void writeViewState(const std::filesystem::path& dir, const ViewState& state);

/// `dir`/view.json when there is one; nothing when there is none. Throws
/// std::invalid_argument (parseViewState) naming the file for one that cannot be read or
/// used.
std::optional<ViewState> readViewState(const std::filesystem::path& dir);

}  // namespace vsculpt::studio
