// SPDX-License-Identifier: MIT
/// @file Config.h
/// @brief Every tunable of the sculpting core, with the thesis's values as defaults, and the
/// loader for `configs/sculpt.json` (documented in docs/config.md).
#pragma once

#include "vsculpt/core/Falloff.h"
#include "vsculpt/core/Geometry.h"

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vsculpt::core {

/// Number of tool-size levels (thesis: 7; level 1 smallest, 7 largest).
inline constexpr int kLevelCount = 7;
/// The level whose diameter is configured directly (D_k = D_4 * growth^(k-4)).
inline constexpr int kReferenceLevel = 4;

/// How tool passes turn into skeletons (docs/placement.md).
enum class PlacementMode {
    Thesis,  ///< the thesis's stacking rules, including its "cannot re-add where carved" limit
    Free,    ///< weights sized to what is there: carve then add works at any size combination
    /// The swept tool's volume added or removed: target field changes from the material's own
    /// slope, deconvolved into weights (docs/placement.md). The default since the mesher
    /// runs off the frame thread (docs/async-mesher.md).
    Swept,
};

const char* toString(PlacementMode m);

/// Support radii given by hand instead of calibrated (the thesis's way).
struct ManualSupport {
    double r4Mm = 0.0;                        ///< support radius of level 4, mm
    std::array<double, kLevelCount> scale{};  ///< L_k, multiplies r4Mm; L_4 must be 1
};

/// Number of zoom levels (thesis: 5, each magnifying 2x).
inline constexpr int kZoomLevels = 5;

struct ZoomConfig {
    /// Grid spacing at zoom 1 as a fraction of the level-6 tool's diameter (thesis: a
    /// one-digit fraction of D_6); it halves with every zoom level.
    double baseSpacingOverD6 = 0.125;
    /// Tool levels offered at each zoom level (thesis: {8-z, 7-z, 6-z}).
    std::array<std::vector<int>, kZoomLevels> allowedSizes{
        std::vector<int>{7, 6, 5}, {6, 5, 4}, {5, 4, 3}, {4, 3, 2}, {3, 2, 1}};
};

struct PolygonizerConfig {
    int gridN = 128;  ///< N: cells per axis of the region on show (thesis: N^3)
    /// Edge roots of exports and ray-traced stills are refined until |f| / |grad f| (the
    /// first-order distance of the vertex from the surface) is below this fraction of the
    /// grid spacing (docs/polygonizer.md).
    double rootTolerance = 0.01;
    /// The same for the mesh on show (the windows, `vsculpt play`'s edits). The window
    /// shades by the field's gradient at each vertex, so a tenth of a cell (under a pixel at
    /// the region's spacing) does not show, and it takes a fifth off the mesher's time per
    /// edit (docs/polygonizer.md, "Two tolerances").
    double viewRootTolerance = 0.1;
};

/// The key names bindings take: GLFW's key names without the GLFW_KEY_ prefix ("A", "7",
/// "F13", "KP_ENTER", "LEFT_SHIFT", "SEMICOLON", ...), every one GLFW defines.
const std::vector<std::string>& keyNames();
/// Actions of the window's keyboard, in configs/sculpt.json "interaction.bindings".
const std::vector<std::string>& bindableActions();
/// Actions of the sketch window's keyboard, "interaction.sketch_bindings" (docs/sketch-window.md).
const std::vector<std::string>& sketchBindableActions();

struct InteractionConfig {
    /// action -> key name (GLFW names without the GLFW_KEY_ prefix: "TAB", "SPACE", "Z", "1").
    std::map<std::string, std::string> bindings{
        {"cycle_tool", "TAB"}, {"step", "SPACE"},   {"zoom_in", "Z"},      {"zoom_out", "X"},
        {"overview", "O"},     {"undo", "U"},       {"redo", "R"},         {"quit", "ESCAPE"},
        {"size_1", "1"},       {"size_2", "2"},     {"size_3", "3"},       {"size_4", "4"},
        {"size_5", "5"},       {"size_6", "6"},     {"size_7", "7"},       {"save", "F5"},
        {"save_as", "F6"},     {"export", "F7"},    {"new_project", "F8"}, {"help", "F1"},
        {"cycle_mirror", "M"}, {"recenter", "HOME"}};
    /// The sketch window's keys, action -> key name (the same names).
    std::map<std::string, std::string> sketchBindings{{"undo", "U"},
                                                      {"redo", "R"},
                                                      {"quit", "ESCAPE"},
                                                      {"mode", "TAB"},
                                                      {"kind_line", "L"},
                                                      {"kind_curve", "C"},
                                                      {"recenter", "F9"},
                                                      {"end_group", "ENTER"},
                                                      {"role_outline", "O"},
                                                      {"role_surface_x", "1"},
                                                      {"role_surface_y", "2"},
                                                      {"role_surface_z", "3"},
                                                      {"role_sweep_section", "S"},
                                                      {"role_sweep_path", "P"},
                                                      {"role_cut", "X"},
                                                      {"role_extrude", "E"},
                                                      {"solid_inflate", "I"},
                                                      {"solid_three_section", "T"},
                                                      {"solid_sweep", "W"},
                                                      {"solid_cut", "K"},
                                                      {"solid_extrude", "J"},
                                                      {"lasso", "A"},
                                                      {"delete", "DELETE"},
                                                      {"move_left", "LEFT"},
                                                      {"move_right", "RIGHT"},
                                                      {"move_up", "UP"},
                                                      {"move_down", "DOWN"},
                                                      {"scale_down", "MINUS"},
                                                      {"scale_up", "EQUAL"},
                                                      {"page_previous", "PAGE_UP"},
                                                      {"page_next", "PAGE_DOWN"},
                                                      {"page_new", "N"},
                                                      {"view_front", "F1"},
                                                      {"view_side", "F2"},
                                                      {"view_top", "F3"},
                                                      {"frame", "HOME"},
                                                      {"history", "H"},
                                                      {"reuse", "G"},
                                                      {"save", "F5"},
                                                      {"save_as", "F6"},
                                                      {"export", "F7"},
                                                      {"new_project", "F8"},
                                                      {"help", "F4"}};
    double depthStepOverDiameter = 0.25;  ///< scroll notch moves the tool by this x D
    double rotateRadPerPixel = 0.01;      ///< right-drag turns the object by this per pixel
};

/// The display: stereo, eyes, and a headset's lenses (the window, docs/window.md).
/// The OpenXR headset path (docs/xr.md): how the controllers sculpt.
struct XrConfig {
    /// Where the sculpture's origin sits in OpenXR's local space (metres, y up, -z ahead of
    /// where the head was at start): a little below the eyes, at arm's length.
    Vec3 sculptureInLocalM{0.0, -0.25, -0.5};
    double penTipMm = 0;            ///< the tool centre this far ahead of the right hand's aim pose
    double triggerThreshold = 0.5;  ///< the trigger engages the tool from this value on
    /// The trigger's analog value pushes the tool this far further along the pen (full
    /// press); 0: off (the trigger only engages).
    double triggerPenetrationMm = 0;
    /// Haptic amplitude on the pen hand while the tool touches the clay / is inside it.
    double hapticTouching = 0.3, hapticInside = 0.8;
    double hapticPulseMs = 20;  ///< each pulse's length; renewed every frame of contact
    /// Samples per pixel of the eyes' images (multisample antialiasing, resolved into the
    /// swapchain image): 1, 2, 4 or 8; 1: off. Silhouettes that shimmer as the head moves
    /// are what a headset shows without it.
    int msaaSamples = 4;
};

struct RenderConfig {
    /// "window" (the desktop window) or "xr" (an OpenXR headset, `vsculpt --xr`).
    std::string output = "window";
    XrConfig xr;
    std::string stereo = "mono";    ///< mono, sbs or anaglyph
    double ipdMm = 63.0;            ///< interpupillary distance
    double verticalFovDeg = 40.0;   ///< per-eye vertical field of view
    int fullscreenMonitor = -1;     ///< -1: a window; 0, 1, ...: full screen on that monitor
    double lensK1 = 0, lensK2 = 0;  ///< radial pre-distortion (sbs only)
    double lensRedScale = 1, lensBlueScale = 1;  ///< chromatic aberration correction
    /// Distance of the on-screen UI from the eyes in stereo, mm; 0: on the zero-parallax
    /// plane (screen depth, the same place in both eyes). docs/window.md, "The on-screen UI".
    double uiDepthMm = 0;
    double uiScale = 1;  ///< size of the UI's text and widgets (1: 13 px text)
    /// Samples per pixel of the desktop window (multisample antialiasing): 1, 2, 4 or 8;
    /// 1: off; 0: auto (4, but 1 on a software rasterizer). A display that offers fewer gives
    /// fewer.
    int msaaSamples = 0;
};

/// One kind of USB device the device layer opens (configs/sculpt.json "devices.match";
/// docs/devices.md). Driver and access names are those of vsculpt::devices.
struct DeviceMatchConfig {
    std::string name;    ///< unique; names the device in messages and recordings
    std::string driver;  ///< spacemouse, polhemus, wacom, hid-digitizer or rift
    std::string access;  ///< hidraw (kernel driver stays) or libusb (claims the interface)
    int vendor = 0;
    std::vector<int> products;
    int interfaceNumber = 0;
    int inEndpoint = 0, outEndpoint = 0;  ///< libusb only; 0 = the interface's first
};

/// Device layer: which devices, transport tuning, and how devices drive sculpting.
struct DevicesConfig {
    std::vector<DeviceMatchConfig> match;  ///< empty = the built-in table (knownDeviceMatches)
    int transfersInFlight = 4;
    double stallTimeoutS = 2.0;
    double rescanIntervalS = 1.0;
    // 3D mouse -> object pose (thesis: the 3D mouse turns and moves the sculpture)
    double mouseFullScale = 350.0;         ///< raw count that means full deflection
    double mouseDeadZone = 0.05;           ///< fraction of full deflection read as zero
    double objectTranslateMmPerS = 150.0;  ///< at full deflection
    double objectRotateDegPerS = 90.0;     ///< at full deflection
    // tracker: stations and calibration (worldFromTracker, the pen tip in the pen sensor)
    int penStation = 1, headStation = 2;
    /// The thesis's 3D mouse built on a tracker receiver: the sculpture follows this station's
    /// motion (hand-held, position control). 0: none (a 3Dconnexion mouse turns it instead).
    int objectStation = 0;
    Vec3 worldFromTrackerTranslationMm{0.0};
    Vec3 worldFromTrackerRotationDeg{0.0};  ///< applied as Rz * Ry * Rx
    Vec3 penTipMm{0.0};                     ///< tip offset in the pen sensor's frame
    /// The thesis: the tool acts whenever the pen moves. false: only while the stylus switch
    /// is pressed (trackers whose records carry it).
    bool penAlwaysEngaged = true;
};

/// The devices vsculpt knows out of the box (3Dconnexion mice, Polhemus trackers, Wacom
/// tablets, Rift headsets), used when the config names none.
const std::vector<DeviceMatchConfig>& knownDeviceMatches();
/// Driver and access names the config accepts.
const std::vector<std::string>& deviceDriverNames();

struct SculptConfig {
    // tools
    double d4Mm = 10.0;                ///< diameter of the level-4 tool, mm
    double growth = 1.5;               ///< r: D_{k+1} / D_k (thesis: a one-digit fraction, 3/2)
    double spacingOverDiameter = 0.5;  ///< sigma: lattice spacing h_k = sigma * D_k (thesis: 1/2)

    // field
    double iso = 0.5;  ///< c in f = sum F - c (thesis: 0.5)
    FalloffParams falloff;
    std::optional<ManualSupport> manualSupport;  ///< empty: calibrate (the default)

    // placement
    PlacementMode placement = PlacementMode::Swept;
    /// Swept mode: strokes place their weights on the lattice this many levels below the
    /// tool's (0..2, never below level 1), so strokes follow the detail of worked clay
    /// (shallow carves of sizes 1-6 0.94..1.14 of their depth at 2, 0.49..1.45 at 0) at 7.6x
    /// the placement time and 14x the skeletons of a stroke at 2 (docs/placement.md "Finer
    /// lattices"). Projects keep the value they were made with.
    int finerLatticeLevels = 0;
    /// Swept mode, experimental: an add or carve ends by placing, on the lattice this many
    /// levels below its own (0..2; a tool with fewer levels below it is not refined), the
    /// residual between its target change and what its own lattice realised
    /// (docs/placement.md "Refining strokes"). At 2 a worked detail's strokes spill a third as
    /// far beyond the tool, but it costs six times the time, the worked detail comes out in 3
    /// pieces and 20 % carves on the sphere reach 1.12 of their depth. Off by default; projects
    /// keep the value they were made with.
    int refineLevels = 0;
    /// Free and swept modes: a smooth stroke ends by giving back, under the tool, the volume
    /// its diffusion took or added (each changed weight moves by delta |its change|, one delta
    /// for the stroke), so smoothing a thin arm or ridge relaxes it instead of dissolving it
    /// (docs/placement.md "Smooth tool"). false: the plain diffusion, which projects and
    /// recordings whose stored config lacks the key keep (parseStoredConfig).
    bool smoothKeepsVolume = true;

    // initial shape: a sphere of point skeletons at its centre
    double sphereRadiusMm = 40.0;  ///< 0 starts from empty space
    Vec3 sphereCenterMm{0.0};
    /// The sphere's steep core: a second point skeleton at its centre of this weight and of
    /// support sphereCoreSupportOverRadius x the radius; the first's support is solved so the
    /// surface stays at the radius. With it the field slopes 1.87x more at the surface (0.035
    /// against 0.019 per mm at r = 40) and keeps its long tail, so the tails of strokes near
    /// the sphere close no voids over crevices (spine forests: 1 seed of 40 with a void, 4
    /// without; docs/placement.md "A steep core"). 0: the one-skeleton sphere, which projects
    /// and recordings whose stored config lacks the key keep (parseStoredConfig).
    /// Thesis mode ignores it: its sphere is the thesis's one skeleton (sphereCoreWeightIn).
    double sphereCoreWeight = 0.7;
    double sphereCoreSupportOverRadius = 1.3;

    ZoomConfig zoom;
    PolygonizerConfig polygonizer;
    InteractionConfig interaction;
    RenderConfig render;
    DevicesConfig devices;

    /// Where the values came from ("built-in defaults" or a file path), for messages.
    std::string source = "built-in defaults";
};

/// The weight of the initial sphere's steep core the sculpture gets: sphereCoreWeight, except
/// in thesis mode, which keeps the thesis's one-skeleton sphere (its carves read the field
/// inside the sphere: docs/placement.md "Thesis mode").
inline double sphereCoreWeightIn(const SculptConfig& cfg) {
    return cfg.placement == PlacementMode::Thesis ? 0.0 : cfg.sphereCoreWeight;
}

/// A user error in a config: message names the file, the line or key, and the reason.
class ConfigError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Parses JSON (comments allowed) over the defaults: keys absent from the text keep their
/// default. Unknown keys, wrong types and invalid values throw ConfigError naming
/// `sourceName`, the key path and the reason.
SculptConfig parseConfig(std::string_view jsonText, const std::string& sourceName);

/// A config stored with a project or a recording: parseConfig, except that keys added since
/// it was written take the values that replay what the version that wrote it did (a stored
/// config lists every key of its version, so an absent key means an older version):
/// initial_sphere.core_weight absent -> 0 (the one-skeleton sphere);
/// placement.smooth_keeps_volume absent -> false (the plain diffusion).
SculptConfig parseStoredConfig(std::string_view jsonText, const std::string& sourceName);

/// Reads and parses a file; a missing or unreadable file is a ConfigError too. An empty path
/// means no file: the built-in defaults (SculptConfig{}, source "built-in defaults"), which
/// equal the values in the shipped configs/sculpt.json (a test checks this).
SculptConfig loadConfig(const std::filesystem::path& path);

/// The config as JSON text that parseConfig() reads back to the same values (projects store
/// it; stats report it).
std::string configToJson(const SculptConfig& cfg);

/// Throws ConfigError("<source>: <key>: <reason>") for the first invalid value.
void validateConfig(const SculptConfig& cfg);

/// The config file to use when no --config names one (docs/config.md):
///  1. $VSCULPT_CONFIG if set and not empty, whether or not it exists (loadConfig then says
///     it cannot be opened: a file the user named is never silently skipped);
///  2. else userConfigPath() if anything is there;
///  3. else an empty path: the built-in defaults (loadConfig({}) returns SculptConfig{}).
/// Nothing is compiled in: an installed vsculpt needs neither the source nor the build tree.
/// Usage: loadConfig(explicitPath.empty() ? defaultConfigPath() : explicitPath).
std::filesystem::path defaultConfigPath();

/// The per-user config file: $XDG_CONFIG_HOME/vsculpt/sculpt.json when $XDG_CONFIG_HOME is an
/// absolute path, else $HOME/.config/vsculpt/sculpt.json; empty without either.
std::filesystem::path userConfigPath();

}  // namespace vsculpt::core
