// SPDX-License-Identifier: MIT
/// @file WindowUi.h
/// @brief What the windows' on-screen UI (Dear ImGui, drawn by render::UiLayer) shows and
/// asks for: the sculpting window's palette and status panel, the sketch window's panel, and
/// the parts both share (help overlay, project menu, save-as and export dialogs, recent
/// projects, preferences). Panels return actions named like key bindings ("undo", "size_3",
/// "mode") or the UI's own ("tool_carve", "zoom_2", "open_project", ...); the windows apply
/// them through the same code as keys. Rectangles are reported in UI pixels (top-left
/// origin; the window's pixels in mono) for tests to click on.
#pragma once

#include "vsculpt/core/Config.h"
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/ImportMesh.h"
#include "vsculpt/studio/Interaction.h"
#include "vsculpt/studio/Session.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace vsculpt::app {

class Rig;

/// Panel background (opaque, RGB 0-255) and text colour: tests look for them on screen.
inline constexpr std::array<uint8_t, 3> kUiPanelRgb = {30, 33, 41};
inline constexpr std::array<uint8_t, 3> kUiTextRgb = {236, 238, 242};

struct UiRect {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< UI pixels, top-left origin
    bool contains(double x, double y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    double cx() const { return 0.5 * (x0 + x1); }
    double cy() const { return 0.5 * (y0 + y1); }
};

/// One request from the UI. `path` for open_project, save_as and export; `exportOptions` for
/// export.
struct UiAction {
    std::string name;
    std::filesystem::path path{};
    core::ExportOptions exportOptions{};
    core::ImportOptions importOptions{};
    int importLevel = 0;  ///< the tool level the import is placed on; 0: core::importLevelFor
};

/// The UI's own state between frames (which panels are open, the dialogs' fields) and, for
/// tests, where its panels and buttons were in the last frame.
struct UiState {
    bool help = false;
    bool preferences = false;
    bool recent = false;
    /// Sketch window: the panel's button rows shown (else only its status lines and a row of
    /// toggles); unset until the first frame, which opens them on windows 600 px tall or more.
    std::optional<bool> sketchTools;
    enum class Dialog { None, SaveAs, Export, Import };
    Dialog dialog = Dialog::None;
    bool dialogOpening = false;  ///< the dialog opens (and takes the keyboard) next frame
    std::string pathField;       ///< the dialog's path text
    double importFitMm = 0;      ///< import dialog: scale to this largest extent (0: as is)
    int importLevel = 0;         ///< import dialog: the clay's level (0: auto)
    std::string lastImportPath;  ///< proposed again by the next import dialog
    /// Work running beside the frame that can be cancelled (Studio::importStatus), shown
    /// above the project buttons with a "cancel import" button; the window sets it each frame.
    std::string importing;
    std::string dialogError;    ///< shown in the dialog when its action failed
    bool refocusField = false;  ///< give the path field the keyboard again (after an error)
    int exportUp = 0;           ///< 0: the format's default, 1: +Y, 2: +Z
    int exportUnits = 0;        ///< 0: the format's default, 1: mm, 2: cm, 3: m
    /// The import dialog's own (a file's frame is not the last export's: found by QA, an
    /// import after a +Z / cm export came in ten times too large).
    int importUp = 0;
    int importUnits = 0;
    std::vector<std::filesystem::path> recentList;  ///< refreshed when the list opens
    std::string preferencesNote;                    ///< where Save preferences wrote

    /// Last frame's rectangles: "status", "palette", "help", "dialog", "field:path",
    /// "preferences", "recent", and buttons as "button:LABEL" ("button:carve",
    /// "button:size 3", "button:zoom 2", "button:undo", "button:export...").
    std::map<std::string, UiRect> rects;
    /// The pointer is over one of the last frame's panels (a click there is the UI's).
    bool covers(double x, double y) const;
};

/// What the sculpting window's panels show.
struct SculptUiView {
    studio::ToolKind tool = studio::ToolKind::Add;
    core::MirrorAxis mirror = core::MirrorAxis::None;
    int size = 0;
    double sizeMm = 0;
    std::vector<std::pair<int, double>> offeredSizes;  ///< level, diameter mm (largest first)
    int zoom = 1;
    size_t skeletons = 0;
    double frameMs = 0;
    std::string project;  ///< project folder name, or "no project"
    std::string message;  ///< the last message (an error, what a save did)
    const std::map<std::string, std::string>* bindings = nullptr;  ///< action -> key name
    /// Pixels kept clear at the left and right edges: the stereo shift of each eye's copy
    /// (Viewer::lastUiShiftNdc), so both copies stay whole inside their eye's image.
    float marginPx = 0;
};

/// The session's part of the view: tool, mirror, size, the sizes the zoom offers, zoom,
/// skeletons and project (the caller adds frame time, message, bindings and margin).
SculptUiView sculptUiViewOf(const studio::Session& session, const studio::Interaction& interaction);

/// What the open dialog (export, import or save as) asks for when confirmed: its path, and the
/// export's or the import's own up axis, units (and for an import its fit and clay level).
UiAction dialogAction(const UiState& state);

/// The sculpting window's UI for one frame (between UiLayer::beginFrame and endFrame):
/// the palette along the bottom, the status panel at the top left, and the shared parts.
/// Preferences edit `cfg` in place (the window applies them when "preferences_changed"
/// comes back). `width`, `height`: the UI's size in pixels.
std::vector<UiAction> sculptUi(UiState& state, const SculptUiView& view, core::SculptConfig& cfg,
                               int width, int height);

/// The headset's panel (XrPanelUi.h) for one frame over its whole image (`width` x `height`
/// pixels): the status (tool, size, zoom, mirror, skeletons, frame time, `hands`: what the
/// controllers are doing, the project and the last message), the palette's rows as in the
/// window (tool, undo, redo, mirror, sizes, zoom), "save" and "export" (a .glb into the
/// project, as the window's export key), and a dot where the pen points. Buttons are larger
/// than the window's: they are aimed at with a controller's ray from arm's length.
std::vector<UiAction> headsetUi(UiState& state, const SculptUiView& view, const std::string& hands,
                                int width, int height);

/// What the sketch window's panel shows.
struct SketchUiView {
    std::string page, plane;  ///< page name; front, side or top
    size_t pageIndex = 0, pageCount = 1;
    bool cleanup = false;  ///< clean-up mode (else draft)
    bool curves = false;   ///< clean-up strokes are curves (else lines)
    bool lasso = false;
    size_t strokes = 0, curvesDone = 0, steps = 0;
    double frameMs = 0;
    std::string project, message;
    const std::map<std::string, std::string>* bindings = nullptr;
};

/// The sketch window's panel (mode, stroke kind, role of the last stroke, solids, page) and
/// the shared parts, for one frame over the whole window.
std::vector<UiAction> sketchUi(UiState& state, const SketchUiView& view, core::SculptConfig& cfg,
                               int width, int height);

/// The help overlay's lines: every key binding of `bindings` (action -> key name, sorted by
/// action) and then the mouse bindings of the window (`sketch` picks the sketch window's).
std::vector<std::pair<std::string, std::string>> helpLines(
    const std::map<std::string, std::string>& bindings, bool sketch);

/// Esc (the "quit" binding) with a panel open closes the panel, as it cancels a dialog, rather
/// than the window (found by QA: Esc in the preferences lost their unsaved edits with the
/// window). Closes the help overlay, the recent projects or the preferences, whichever is
/// open, and returns true; false when none is.
bool closeOpenPanel(UiState& state);

/// The UI scale a window of `heightPx` can show: the config's, at most heightPx / 560 (and
/// at least 0.5), so the panels never cover the whole sculpture (found by QA: ui_scale 4 on
/// a 1280x800 window hid the save buttons and the sculpture). At 1 up to 560 px tall.
float fittedUiScale(double configured, int heightPx);

/// The shared actions that only open a dialog or a panel (and so have nothing to report).
bool opensPanel(const std::string& actionName);

/// Applies a UI action both windows share (save, save_as, export, open_project,
/// new_project, save_preferences) on `rig`. Returns true when it was one of them, with the
/// message for the user in `message`; a failed dialog action keeps the dialog open with the
/// error in state.dialogError. `switched`: the rig's studio was replaced (save as, open, new
/// project): references into the old one are gone.
bool applySharedUiAction(const UiAction& action, Rig& rig, UiState& state,
                         const core::SculptConfig& cfg, std::string& message, bool& switched);

/// Writes `cfg` as the user's config file (core::userConfigPath(), atomically) and returns
/// the path. The whole config is written as JSON without comments: a file that was there is
/// replaced (the preferences panel says so before the user saves). Throws on failure.
std::filesystem::path savePreferences(const core::SculptConfig& cfg);

}  // namespace vsculpt::app
