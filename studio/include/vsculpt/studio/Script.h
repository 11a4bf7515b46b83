// SPDX-License-Identifier: MIT
/// @file Script.h
/// @brief The playback script format (docs/playback.md): plain text, one command per line,
/// `#` comments, millimetres. Parsing checks syntax; rules that depend on the session's
/// state (a size not offered at the current zoom) are checked when the command runs, and
/// reported with the same file:line prefix.
#pragma once

#include "vsculpt/core/Geometry.h"
#include "vsculpt/core/ImportMesh.h"
#include "vsculpt/core/PlaceStroke.h"

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vsculpt::studio {

/// "file:line: message". The line is 1-based; 0 when the error concerns the whole file.
class ScriptError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

enum class ToolKind { Add, Carve, Smooth, Select };
/// "add", "carve", "smooth", "select": the names scripts and view.json use.
const char* toString(ToolKind tool);
/// The tool of that name (toString's), if any.
std::optional<ToolKind> toolKindNamed(std::string_view name);
/// The mirror plane of that name: "x", "y", "z", "off" (core::toString's), if any.
std::optional<core::MirrorAxis> mirrorAxisNamed(std::string_view name);

/// One pen sample of a scripted sketch stroke (docs/playback.md, "Sketch commands"): canvas
/// mm (whatever the page's view), optional pressure 0..1 and time in seconds.
struct PenPoint {
    double x = 0, y = 0;
    std::optional<double> pressure, time;
};

/// A sketch-mode command (docs/playback.md). Syntax is checked when parsing; whether it
/// applies (an unknown stroke id, a missing role) when it runs.
struct SketchCommand {
    enum class Verb {
        Page,         ///< page NAME [GROUP]: select the page of that name, or add it
        Mode,         ///< mode draft|cleanup
        Kind,         ///< kind line|curve
        Pen,          ///< pen X,Y[,P[,T]] ...: one stroke
        EndGroup,     ///< endgroup
        Tick,         ///< tick T: the clock (the clean-up pause trigger)
        CanvasZoom,   ///< canvas zoom F X Y
        CanvasPan,    ///< canvas pan DX DY
        CanvasReset,  ///< canvas reset
        Select,       ///< select ID ... | select none
        SelectLasso,  ///< select lasso X,Y X,Y X,Y ...
        SelectNear,   ///< select near X Y TOL
        Move,         ///< move DX DY
        Scale,        ///< scale F
        Delete,       ///< delete
        Role,         ///< role ROLE stroke ID | curve ID | last
        Reuse,        ///< reuse ID
        Solid,        ///< solid inflate|three-section|sweep|cut|extrude [level K]
        ModelLine,    ///< model-line W H X,Y ...: drawn on the model in a W x H front view
    };
    Verb verb = Verb::EndGroup;
    std::string name, group;  ///< page name and group; role name; solid construction
    bool flag = false;        ///< mode cleanup; kind line
    std::vector<PenPoint> pen;
    std::vector<double> numbers;  ///< zoom F X Y, pan, near X Y TOL, move, scale, tick, lasso
    std::vector<int> ids;         ///< select, role target, reuse
    enum class Target { Stroke, Curve, Last } target = Target::Last;
    int level = 0;  ///< solid level, 0: chosen from the solid's size
};

struct ScriptCommand {
    enum class Kind {
        Tool,
        Size,
        Zoom,
        Object,
        Space,
        Stroke,
        Undo,
        Redo,
        Save,
        Sketch,
        Import,
        Mirror,
        Probe,  ///< probe x y z: says what the clay is there (logged)
        Expect  ///< expect inside|outside x y z: fails the run when the clay is not so there
    };
    Kind kind = Kind::Undo;
    int line = 0;  ///< where the command starts
    ToolKind tool = ToolKind::Add;
    core::MirrorAxis mirror = core::MirrorAxis::None;  ///< mirror
    int value = 0;                   ///< size K / zoom Z / import level K (0: from the mesh's size)
    bool hasPoint = false;           ///< zoom with a centre
    core::Vec3 point{0.0};           ///< zoom centre; probe and expect point (read as strokes are)
    bool expectInside = true;        ///< expect inside (false: outside)
    core::RigidTransform pose;       ///< object
    bool world = false;              ///< space
    std::vector<core::Vec3> points;  ///< stroke
    SketchCommand sketch;            ///< sketch commands
    /// import: the mesh file, resolved against the script's folder when relative (the
    /// script's source name is taken as its path), and the frame/size options.
    std::filesystem::path file;
    core::ImportOptions importOptions;
};

struct Script {
    std::string source;
    std::vector<ScriptCommand> commands;
};

/// @param sourceName the script's path (or a name): error messages start with it, and
/// relative `import` paths are resolved against its folder.
Script parseScript(std::string_view text, const std::string& sourceName);
/// Reads and parses the file; ScriptError when it cannot be read, for a bad line (with its
/// number), and for an `import` whose mesh file cannot be opened (checked here, before any
/// command runs).
Script loadScript(const std::filesystem::path& path);

}  // namespace vsculpt::studio
