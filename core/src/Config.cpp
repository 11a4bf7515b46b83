// SPDX-License-Identifier: MIT
#include "vsculpt/core/Config.h"

#include "vsculpt/core/HomeFolder.h"
#include "vsculpt/core/InvalidJson.h"
#include "vsculpt/core/JsonNesting.h"
#include "vsculpt/core/NearestName.h"
#include "vsculpt/core/PrintableText.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

namespace vsculpt::core {

using nlohmann::json;

const char* toString(PlacementMode m) {
    return m == PlacementMode::Thesis ? "thesis" : m == PlacementMode::Swept ? "swept" : "free";
}

namespace {

/// $NAME, or nullptr when it is unset or empty.
const char* envValue(const char* name) {
    const char* v = std::getenv(name);
    return v != nullptr && *v != '\0' ? v : nullptr;
}

}  // namespace

std::filesystem::path userConfigPath() {
    // XDG Base Directory: a relative $XDG_CONFIG_HOME is invalid and ignored.
    if (const char* xdg = envValue("XDG_CONFIG_HOME");
        xdg && std::filesystem::path(xdg).is_absolute())
        return std::filesystem::path(xdg) / "vsculpt" / "sculpt.json";
    if (const std::filesystem::path home = homeFolder(); !home.empty())
        return home / ".config" / "vsculpt" / "sculpt.json";
    return {};
}

std::filesystem::path defaultConfigPath() {
    // Named by the user: used even if it does not exist, so loadConfig reports it (exit 2).
    if (const char* env = envValue("VSCULPT_CONFIG")) return env;
    // The per-user file counts when anything is there (a dangling link or a directory too:
    // loadConfig then says why it cannot be read instead of silently ignoring it).
    const std::filesystem::path user = userConfigPath();
    std::error_code ec;
    if (!user.empty() && std::filesystem::exists(std::filesystem::symlink_status(user, ec)))
        return user;
    return {};  // the built-in defaults
}

namespace {

/// Walks one JSON object, remembering which keys were read so unknown ones can be reported.
/// An old bisection bracket over the root tolerance that places vertices about as exactly.
constexpr double kLegacyBracketOverRootTolerance = 12.5;

class Section {
  public:
    Section(const json& obj, std::string path, const std::string& source)
        : mObj(obj), mPath(std::move(path)), mSource(source) {
        if (!mObj.is_object()) fail(mPath.empty() ? "top level" : mPath, "expected an object");
    }

    [[noreturn]] void fail(const std::string& key, const std::string& why) const {
        // Keys and values are quoted from the file: escape what a terminal would act on.
        throw ConfigError(mSource + ": " + printableText(key, 160) + ": " +
                          printableText(why, 240));
    }
    std::string keyPath(const std::string& key) const {
        return mPath.empty() ? key : mPath + "." + key;
    }
    const json* find(const std::string& key) {
        mSeen.insert(key);
        auto it = mObj.find(key);
        return it == mObj.end() ? nullptr : &*it;
    }
    void number(const std::string& key, double& out) {
        if (const json* v = find(key)) {
            if (!v->is_number()) fail(keyPath(key), "expected a number, got " + v->dump());
            out = v->get<double>();
        }
    }
    void vec3(const std::string& key, Vec3& out) {
        if (const json* v = find(key)) {
            if (!v->is_array() || v->size() != 3 || !(*v)[0].is_number() || !(*v)[1].is_number() ||
                !(*v)[2].is_number())
                fail(keyPath(key), "expected [x, y, z] in mm, got " + v->dump());
            out = Vec3((*v)[0].get<double>(), (*v)[1].get<double>(), (*v)[2].get<double>());
        }
    }
    Section sub(const std::string& key) {
        const json* v = find(key);
        static const json kEmpty = json::object();
        return Section(v ? *v : kEmpty, keyPath(key), mSource);
    }
    bool has(const std::string& key) const { return mObj.contains(key); }
    const std::string& source() const { return mSource; }
    void rejectUnknown() const {
        for (auto it = mObj.begin(); it != mObj.end(); ++it) {
            if (it.key().rfind("_", 0) == 0) continue;  // "_comment" style keys are allowed
            if (mSeen.count(it.key())) continue;
            // Every key this section knows was looked up (find() remembers it, present or
            // not): the nearest of those is what a typo meant.
            const std::vector<std::string> known(mSeen.begin(), mSeen.end());
            const std::string near = nearestName(it.key(), known);
            fail(keyPath(it.key()),
                 near.empty() ? "unknown key" : "unknown key (did you mean '" + near + "'?)");
        }
    }

  private:
    const json& mObj;
    std::string mPath;
    const std::string& mSource;
    std::set<std::string> mSeen;
};

// An integer within lo..hi. (nlohmann's get<int>() wraps a larger one: 4294967296 read as 0.)
bool isIntegerIn(const json& v, long long lo, long long hi) {
    if (v.is_number_unsigned()) {
        const unsigned long long u = v.get<unsigned long long>();
        return hi >= 0 && u <= static_cast<unsigned long long>(hi) &&
               static_cast<long long>(u) >= lo;
    }
    return v.is_number_integer() && v.get<long long>() >= lo && v.get<long long>() <= hi;
}

/// A multisample count: 1, 2, 4 or 8 (1: off), and 0 (auto) where `autoAllowed`.
bool isSampleCount(long long n, bool autoAllowed) {
    return (autoAllowed && n == 0) || (n >= 1 && n <= 8 && std::has_single_bit(unsigned(n)));
}

// USB ids are written either as numbers or as "0x046d" strings.
int usbId(const Section& sec, const std::string& key, const json& v) {
    long value = -1;
    if (v.is_number_integer()) {
        value = v.get<long>();
    } else if (v.is_string()) {
        const std::string text = v.get<std::string>();
        char* end = nullptr;
        value = std::strtol(text.c_str(), &end, 0);
        if (text.empty() || *end != '\0') value = -1;
    }
    if (value < 0 || value > 0xffff)
        sec.fail(key,
                 "expected a USB id 0..0xffff (a number or a \"0x1234\" string), got " + v.dump());
    return static_cast<int>(value);
}

void parseDevices(Section dev, DevicesConfig& out) {
    if (const json* v = dev.find("transfers_in_flight")) {
        if (!isIntegerIn(*v, 1, 32))
            dev.fail("devices.transfers_in_flight", "expected an integer 1..32, got " + v->dump());
        out.transfersInFlight = v->get<int>();
    }
    dev.number("stall_timeout_s", out.stallTimeoutS);
    dev.number("rescan_interval_s", out.rescanIntervalS);
    Section mouse = dev.sub("object_from_3d_mouse");
    mouse.number("full_scale", out.mouseFullScale);
    mouse.number("dead_zone", out.mouseDeadZone);
    mouse.number("translate_mm_per_s", out.objectTranslateMmPerS);
    mouse.number("rotate_deg_per_s", out.objectRotateDegPerS);
    mouse.rejectUnknown();
    Section tracker = dev.sub("tracker");
    for (const char* key : {"pen_station", "head_station", "object_station"}) {
        if (const json* v = tracker.find(key)) {
            const int lo = std::string(key) == "object_station" ? 0 : 1;
            if (!isIntegerIn(*v, lo, 16))
                tracker.fail(
                    std::string("devices.tracker.") + key,
                    "expected a station number " + std::to_string(lo) + "..16, got " + v->dump());
            const std::string k = key;
            (k == "pen_station"    ? out.penStation
             : k == "head_station" ? out.headStation
                                   : out.objectStation) = v->get<int>();
        }
    }
    tracker.vec3("world_from_tracker_translation_mm", out.worldFromTrackerTranslationMm);
    tracker.vec3("world_from_tracker_rotation_deg", out.worldFromTrackerRotationDeg);
    tracker.vec3("pen_tip_mm", out.penTipMm);
    if (const json* v = tracker.find("always_engaged")) {
        if (!v->is_boolean())
            tracker.fail("devices.tracker.always_engaged",
                         "expected true or false, got " + v->dump());
        out.penAlwaysEngaged = v->get<bool>();
    }
    tracker.rejectUnknown();

    if (const json* list = dev.find("match")) {
        if (!list->is_array()) dev.fail("devices.match", "expected a list of devices");
        out.match.clear();
        for (size_t i = 0; i < list->size(); ++i) {
            const std::string at = "devices.match[" + std::to_string(i) + "]";
            Section m((*list)[i], at, dev.source());
            DeviceMatchConfig d;
            auto text = [&](const char* key, std::string& field, bool required) {
                const json* v = m.find(key);
                if (!v) {
                    if (required) m.fail(at + "." + key, "missing");
                    return;
                }
                if (!v->is_string() || v->get<std::string>().empty())
                    m.fail(at + "." + key, "expected a non-empty string, got " + v->dump());
                field = v->get<std::string>();
            };
            text("name", d.name, true);
            text("driver", d.driver, true);
            d.access = "hidraw";
            text("access", d.access, false);
            const auto& drivers = deviceDriverNames();
            if (std::find(drivers.begin(), drivers.end(), d.driver) == drivers.end())
                m.fail(at + ".driver",
                       "unknown driver '" + d.driver +
                           "' (known: spacemouse, polhemus, wacom, hid-digitizer, rift)");
            if (d.access != "hidraw" && d.access != "libusb")
                m.fail(at + ".access",
                       "expected \"hidraw\" or \"libusb\", got \"" + d.access + "\"");
            const json* vendor = m.find("vendor");
            if (!vendor) m.fail(at + ".vendor", "missing");
            d.vendor = usbId(m, at + ".vendor", *vendor);
            const json* products = m.find("products");
            if (!products || !products->is_array() || products->empty())
                m.fail(at + ".products", "expected a non-empty list of USB product ids");
            for (const json& p : *products)
                d.products.push_back(usbId(m, at + ".products", p));
            auto integer = [&](const char* key, int& field, int lo, int hi) {
                const json* v = m.find(key);
                if (!v) return;
                const int value = v->is_string()            ? usbId(m, at + "." + key, *v)
                                  : isIntegerIn(*v, lo, hi) ? v->get<int>()
                                                            : -1;
                if (value < lo || value > hi)
                    m.fail(at + "." + key, "expected " + std::to_string(lo) + ".." +
                                               std::to_string(hi) + ", got " + v->dump());
                field = value;
            };
            integer("interface", d.interfaceNumber, 0, 255);
            integer("in_endpoint", d.inEndpoint, 0, 255);
            integer("out_endpoint", d.outEndpoint, 0, 255);
            if (d.inEndpoint && !(d.inEndpoint & 0x80))
                m.fail(at + ".in_endpoint", "an IN endpoint address has bit 0x80 set");
            if (d.outEndpoint & 0x80)
                m.fail(at + ".out_endpoint", "an OUT endpoint address has bit 0x80 clear");
            for (const auto& other : out.match)
                if (other.name == d.name) m.fail(at + ".name", "'" + d.name + "' is used twice");
            m.rejectUnknown();
            out.match.push_back(d);
        }
    }
    dev.rejectUnknown();
}

}  // namespace

const std::vector<std::string>& deviceDriverNames() {
    static const std::vector<std::string> names = {"spacemouse", "polhemus", "wacom",
                                                   "hid-digitizer", "rift"};
    return names;
}

const std::vector<DeviceMatchConfig>& knownDeviceMatches() {
    // devices_report.md §1.1 (Polhemus operational PIDs and endpoints), §2.1 (3Dconnexion),
    // §3 (Wacom), §4.1 (Oculus). HID devices default to hidraw so the desktop keeps them.
    static const std::vector<DeviceMatchConfig> known = {
        {"spacemouse-logitech",
         "spacemouse",
         "hidraw",
         0x046d,
         {0xc603, 0xc605, 0xc606, 0xc621, 0xc623, 0xc625, 0xc626, 0xc627, 0xc628, 0xc629, 0xc62b},
         0,
         0,
         0},
        {"spacemouse-3dconnexion",
         "spacemouse",
         "hidraw",
         0x256f,
         {0xc62e, 0xc62f, 0xc631, 0xc632, 0xc633, 0xc635, 0xc636, 0xc638, 0xc63a, 0xc641},
         0,
         0,
         0},
        {"polhemus-liberty-hs", "polhemus", "libusb", 0x0f44, {0xff20, 0xef20}, 0, 0x88, 0x04},
        {"polhemus", "polhemus", "libusb", 0x0f44, {0x0002, 0xff12, 0xef12}, 0, 0x82, 0x02},
        {"rift", "rift", "hidraw", 0x2833, {0x0001, 0x0021, 0x0031}, 0, 0, 0},
        {"wacom-tablet",
         "hid-digitizer",
         "hidraw",
         0x056a,
         {0x0042, 0x0314, 0x0315, 0x0374, 0x0375, 0x037a, 0x037b},
         0,
         0,
         0},
    };
    return known;
}

namespace {

SculptConfig parseConfigText(std::string_view jsonText, const std::string& sourceName,
                             bool stored) {
    if (const auto deep = jsonNestingBeyond(jsonText)) throw ConfigError(sourceName + ":" + *deep);
    json root;
    // A key given twice in one object: JSON keeps the last silently, so the first setting the
    // user wrote would be ignored without a word. Found while parsing, named by its path.
    struct Frame {
        bool object = false;
        std::string name;
        std::set<std::string> keys;
    };
    std::vector<Frame> frames;
    std::string lastKey, duplicate;
    const auto findDuplicates = [&](int, json::parse_event_t event, json& parsed) {
        using E = json::parse_event_t;
        if (event == E::object_start || event == E::array_start) {
            frames.push_back(Frame{event == E::object_start, lastKey, {}});
            lastKey.clear();
        } else if (event == E::object_end || event == E::array_end) {
            if (!frames.empty()) frames.pop_back();
        } else if (event == E::key) {
            lastKey = parsed.get<std::string>();
            if (!frames.empty() && frames.back().object &&
                !frames.back().keys.insert(lastKey).second && duplicate.empty()) {
                for (size_t i = 1; i < frames.size(); ++i)
                    duplicate += frames[i].name.empty()
                                     ? "[]"
                                     : (duplicate.empty() ? "" : ".") + frames[i].name;
                duplicate += (duplicate.empty() ? "" : ".") + lastKey;
            }
        } else {
            lastKey.clear();
        }
        return true;
    };
    try {
        root = json::parse(jsonText, findDuplicates, /*allow_exceptions=*/true,
                           /*ignore_comments=*/true);
    } catch (const json::exception& e) {
        // A syntax error, or a number past a double's range (1e400): where, and what.
        throw ConfigError(invalidJsonMessage(sourceName, jsonText, e));
    }

    if (!duplicate.empty())
        throw ConfigError(sourceName + ": " + duplicate +
                          ": given twice in one object (JSON would keep only the last)");

    SculptConfig cfg;
    cfg.source = sourceName;
    Section top(root, "", sourceName);

    Section tools = top.sub("tools");
    if (const json* v = tools.find("levels")) {
        if (!isIntegerIn(*v, kLevelCount, kLevelCount))
            tools.fail("tools.levels", "vsculpt has exactly 7 tool levels (got " + v->dump() + ")");
    }
    tools.number("d4_mm", cfg.d4Mm);
    tools.number("growth", cfg.growth);
    tools.number("lattice_spacing_over_diameter", cfg.spacingOverDiameter);
    tools.rejectUnknown();

    Section field = top.sub("field");
    field.number("iso", cfg.iso);
    Section fo = field.sub("falloff");
    fo.number("f0", cfg.falloff.f0);
    fo.number("control_u", cfg.falloff.controlU);
    fo.number("control_value", cfg.falloff.controlValue);
    fo.number("control_slope", cfg.falloff.controlSlope);
    fo.rejectUnknown();
    if (const json* v = field.find("support")) {
        if (v->is_string()) {
            if (v->get<std::string>() != "calibrate")
                field.fail("field.support",
                           "expected \"calibrate\" or an object, got " + v->dump());
        } else {
            Section sup(*v, "field.support", sourceName);
            ManualSupport ms;
            sup.number("r4_mm", ms.r4Mm);
            const json* scale = sup.find("scale");
            if (!scale || !scale->is_array() || scale->size() != kLevelCount)
                sup.fail("field.support.scale", "expected an array of 7 numbers L_1..L_7");
            for (int k = 0; k < kLevelCount; ++k) {
                if (!(*scale)[k].is_number())
                    sup.fail("field.support.scale[" + std::to_string(k) + "]", "expected a number");
                ms.scale[k] = (*scale)[k].get<double>();
            }
            if (!sup.has("r4_mm")) sup.fail("field.support.r4_mm", "required with a manual scale");
            sup.rejectUnknown();
            cfg.manualSupport = ms;
        }
    }
    field.rejectUnknown();

    Section placement = top.sub("placement");
    if (const json* v = placement.find("mode")) {
        const std::string m = v->is_string() ? v->get<std::string>() : "";
        if (m == "thesis")
            cfg.placement = PlacementMode::Thesis;
        else if (m == "free")
            cfg.placement = PlacementMode::Free;
        else if (m == "swept")
            cfg.placement = PlacementMode::Swept;
        else
            placement.fail("placement.mode",
                           "expected \"thesis\", \"free\" or \"swept\", got " + v->dump());
    }
    if (const json* v = placement.find("finer_lattice_levels")) {
        if (!isIntegerIn(*v, 0, 2))
            placement.fail("placement.finer_lattice_levels",
                           "expected an integer 0..2, got " + v->dump());
        cfg.finerLatticeLevels = v->get<int>();
    }
    if (const json* v = placement.find("refine_levels")) {
        if (!isIntegerIn(*v, 0, 2))
            placement.fail("placement.refine_levels", "expected an integer 0..2, got " + v->dump());
        cfg.refineLevels = v->get<int>();
    }
    // Together they refine up to four levels below the tool: never measured, and adds and
    // carves alternating over one spot leave the field's bound there (docs/placement.md, "What
    // making it the default would take"). A project that was made so still opens as it was.
    if (!stored && cfg.finerLatticeLevels > 0 && cfg.refineLevels > 0)
        placement.fail("placement.refine_levels",
                       "cannot be combined with placement.finer_lattice_levels (" +
                           std::to_string(cfg.finerLatticeLevels) +
                           "): set one of them to 0 (docs/placement.md)");
    if (stored && !placement.find("smooth_keeps_volume")) cfg.smoothKeepsVolume = false;
    if (const json* v = placement.find("smooth_keeps_volume")) {
        if (!v->is_boolean())
            placement.fail("placement.smooth_keeps_volume",
                           "expected true or false, got " + v->dump());
        cfg.smoothKeepsVolume = v->get<bool>();
    }
    placement.rejectUnknown();

    Section sphere = top.sub("initial_sphere");
    sphere.number("radius_mm", cfg.sphereRadiusMm);
    sphere.vec3("center_mm", cfg.sphereCenterMm);
    if (stored && !sphere.find("core_weight")) cfg.sphereCoreWeight = 0;
    sphere.number("core_weight", cfg.sphereCoreWeight);
    sphere.number("core_support_over_radius", cfg.sphereCoreSupportOverRadius);
    sphere.rejectUnknown();

    Section zoom = top.sub("zoom");
    if (const json* v = zoom.find("levels")) {
        if (!isIntegerIn(*v, kZoomLevels, kZoomLevels))
            zoom.fail("zoom.levels", "vsculpt has exactly 5 zoom levels (got " + v->dump() + ")");
    }
    zoom.number("base_spacing_over_d6", cfg.zoom.baseSpacingOverD6);
    if (const json* v = zoom.find("allowed_sizes")) {
        if (!v->is_array() || v->size() != kZoomLevels)
            zoom.fail("zoom.allowed_sizes", "expected 5 lists of tool levels, one per zoom level");
        for (int z = 0; z < kZoomLevels; ++z) {
            const json& row = (*v)[z];
            const std::string key = "zoom.allowed_sizes[" + std::to_string(z) + "]";
            if (!row.is_array() || row.empty())
                zoom.fail(key, "expected a non-empty list of tool levels 1..7");
            std::vector<int> sizes;
            for (const json& k : row) {
                if (!isIntegerIn(k, 1, kLevelCount))
                    zoom.fail(key, "tool levels are integers 1..7, got " + k.dump());
                if (std::find(sizes.begin(), sizes.end(), k.get<int>()) != sizes.end())
                    zoom.fail(key, "level " + k.dump() + " listed twice");
                sizes.push_back(k.get<int>());
            }
            cfg.zoom.allowedSizes[z] = sizes;
        }
    }
    zoom.rejectUnknown();

    Section poly = top.sub("polygonizer");
    if (const json* v = poly.find("grid_n")) {
        if (!isIntegerIn(*v, INT_MIN, INT_MAX))
            poly.fail("polygonizer.grid_n", "expected an integer, got " + v->dump());
        cfg.polygonizer.gridN = v->get<int>();
    }
    // Configs and projects before the Illinois root finder gave a bisection bracket; its
    // default (1/8) maps onto the new default (1/100), as do other values proportionally:
    // the old vertices lay within about a twelfth of their bracket (docs/polygonizer.md).
    double legacyBracket = 0;
    if (poly.find("bisection_tolerance") && !poly.find("root_tolerance")) {
        poly.number("bisection_tolerance", legacyBracket);
        if (!(std::isfinite(legacyBracket) && legacyBracket >= 1e-9 && legacyBracket <= 0.5))
            poly.fail("polygonizer.bisection_tolerance",
                      "must be in [1e-9, 0.5] (a fraction of the grid spacing; got " +
                          json(legacyBracket).dump() + ")");
        cfg.polygonizer.rootTolerance = legacyBracket / kLegacyBracketOverRootTolerance;
    } else if (poly.find("bisection_tolerance")) {
        poly.fail("polygonizer.bisection_tolerance",
                  "replaced by root_tolerance, which is also given: remove this one");
    }
    poly.number("root_tolerance", cfg.polygonizer.rootTolerance);
    poly.number("view_root_tolerance", cfg.polygonizer.viewRootTolerance);
    poly.rejectUnknown();

    Section inter = top.sub("interaction");
    inter.number("depth_step_over_diameter", cfg.interaction.depthStepOverDiameter);
    inter.number("rotate_rad_per_pixel", cfg.interaction.rotateRadPerPixel);
    auto bindings = [&](const char* name, const std::vector<std::string>& actions, const char* doc,
                        std::map<std::string, std::string>& out) {
        const json* b = inter.find(name);
        if (!b) return;
        const std::string where = std::string("interaction.") + name;
        if (!b->is_object()) inter.fail(where, "expected an object of action: key name");
        for (auto it = b->begin(); it != b->end(); ++it) {
            const std::string key = where + "." + it.key();
            if (std::find(actions.begin(), actions.end(), it.key()) == actions.end()) {
                const std::string near = nearestName(it.key(), actions);
                inter.fail(key, std::string("unknown action") +
                                    (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                                    " (see " + doc + ")");
            }
            if (!it->is_string() || it->get<std::string>().empty())
                inter.fail(key, "expected a key name such as \"TAB\" or \"Z\"");
            // "z" is "Z": GLFW's names are upper case, people type either (found by QA: "did
            // you mean '0'?" for "z").
            std::string keyName = it->get<std::string>();
            std::transform(keyName.begin(), keyName.end(), keyName.begin(),
                           [](unsigned char c) { return char(std::toupper(c)); });
            if (std::find(keyNames().begin(), keyNames().end(), keyName) == keyNames().end()) {
                const std::string near = nearestName(keyName, keyNames());
                inter.fail(key, "unknown key name '" + printableText(it->get<std::string>()) +
                                    "' (GLFW's names without GLFW_KEY_: A-Z, 0-9, F1-F25, "
                                    "KP_0-KP_9, TAB, SPACE, HOME, ..." +
                                    (near.empty() ? "" : "; did you mean '" + near + "'?") + ")");
            }
            out[it.key()] = keyName;
        }
        // A key bound twice here (or to an action left at its default) is refused by every
        // command, not only by the windows that read keys (found by QA: `vsculpt info` gave
        // such a file an all-clear).
        for (auto it = b->begin(); it != b->end(); ++it)
            for (const auto& [other, otherKey] : out)
                if (other != it.key() && otherKey == out[it.key()])
                    inter.fail(where + "." + it.key(),
                               "key '" + otherKey + "' is already bound to " + other +
                                   (b->contains(other)
                                        ? ""
                                        : " (by default: bind " + other + " to another key too)"));
    };
    bindings("bindings", bindableActions(), "docs/window.md", cfg.interaction.bindings);
    bindings("sketch_bindings", sketchBindableActions(), "docs/sketch-window.md",
             cfg.interaction.sketchBindings);
    inter.rejectUnknown();

    Section rend = top.sub("render");
    if (const json* v = rend.find("stereo")) {
        const std::string m = v->is_string() ? v->get<std::string>() : "";
        if (m != "mono" && m != "sbs" && m != "anaglyph")
            rend.fail("render.stereo",
                      "expected \"mono\", \"sbs\" or \"anaglyph\", got " + v->dump());
        cfg.render.stereo = m;
    }
    rend.number("ipd_mm", cfg.render.ipdMm);
    rend.number("vertical_fov_deg", cfg.render.verticalFovDeg);
    if (const json* v = rend.find("fullscreen_monitor")) {
        if (!isIntegerIn(*v, INT_MIN, INT_MAX))
            rend.fail("render.fullscreen_monitor", "expected an integer (-1: windowed)");
        cfg.render.fullscreenMonitor = v->get<int>();
    }
    rend.number("ui_depth_mm", cfg.render.uiDepthMm);
    rend.number("ui_scale", cfg.render.uiScale);
    Section lens = rend.sub("lens");
    lens.number("k1", cfg.render.lensK1);
    lens.number("k2", cfg.render.lensK2);
    lens.number("red_scale", cfg.render.lensRedScale);
    lens.number("blue_scale", cfg.render.lensBlueScale);
    lens.rejectUnknown();
    if (const json* v = rend.find("output")) {
        const std::string o = v->is_string() ? v->get<std::string>() : "";
        if (o != "window" && o != "xr")
            rend.fail("render.output", "expected \"window\" or \"xr\", got " + v->dump());
        cfg.render.output = o;
    }
    if (const json* v = rend.find("msaa_samples")) {
        if (!(isIntegerIn(*v, 0, 8) && isSampleCount(v->get<int>(), true)))
            rend.fail("render.msaa_samples",
                      "expected 0 (auto), 1, 2, 4 or 8 (1: off), got " + v->dump());
        cfg.render.msaaSamples = v->get<int>();
    }
    Section xr = rend.sub("xr");
    if (const json* v = xr.find("sculpture_in_local_m")) {
        if (!v->is_array() || v->size() != 3 || !(*v)[0].is_number() || !(*v)[1].is_number() ||
            !(*v)[2].is_number())
            xr.fail("render.xr.sculpture_in_local_m",
                    "expected [x, y, z] in metres, got " + v->dump());
        cfg.render.xr.sculptureInLocalM =
            Vec3((*v)[0].get<double>(), (*v)[1].get<double>(), (*v)[2].get<double>());
    }
    xr.number("pen_tip_mm", cfg.render.xr.penTipMm);
    xr.number("trigger_threshold", cfg.render.xr.triggerThreshold);
    xr.number("trigger_penetration_mm", cfg.render.xr.triggerPenetrationMm);
    xr.number("haptic_touching", cfg.render.xr.hapticTouching);
    xr.number("haptic_inside", cfg.render.xr.hapticInside);
    xr.number("haptic_pulse_ms", cfg.render.xr.hapticPulseMs);
    if (const json* v = xr.find("msaa_samples")) {
        if (!(isIntegerIn(*v, 1, 8) && isSampleCount(v->get<int>(), false)))
            xr.fail("render.xr.msaa_samples", "expected 1, 2, 4 or 8 (1: off), got " + v->dump());
        cfg.render.xr.msaaSamples = v->get<int>();
    }
    xr.rejectUnknown();
    rend.rejectUnknown();

    parseDevices(top.sub("devices"), cfg.devices);
    top.rejectUnknown();

    validateConfig(cfg);
    return cfg;
}

}  // namespace

SculptConfig parseConfig(std::string_view jsonText, const std::string& sourceName) {
    return parseConfigText(jsonText, sourceName, false);
}

SculptConfig parseStoredConfig(std::string_view jsonText, const std::string& sourceName) {
    return parseConfigText(jsonText, sourceName, true);
}

SculptConfig loadConfig(const std::filesystem::path& path) {
    if (path.empty()) return SculptConfig{};  // source: "built-in defaults"
    const char* env = envValue("VSCULPT_CONFIG");
    const std::string namedBy =
        env && path == std::filesystem::path(env) ? " (named by $VSCULPT_CONFIG)" : "";
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw ConfigError(path.string() + ": cannot open config file: it is a folder" + namedBy);
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        const int err = errno;  // ifstream leaves open()'s errno
        throw ConfigError(path.string() + ": cannot open config file" +
                          (err ? ": " + std::string(std::strerror(err)) : "") + namedBy);
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw ConfigError(path.string() + ": read error");
    // Refused, not taken as the defaults (a file emptied by accident would silently lose every
    // setting), but said plainly (found by QA: "invalid JSON" of a file made with `touch`).
    if (text.str().find_first_not_of(" \t\r\n") == std::string::npos)
        throw ConfigError(path.string() +
                          ": empty; a config holds at least {} (every key is "
                          "optional: {} is the built-in defaults)" +
                          namedBy);
    return parseConfig(text.str(), path.string());
}

const std::vector<std::string>& keyNames() {
    // GLFW 3.3's key tokens (glfw3.h), in its order; app/KeyNames.h maps them to key codes.
    static const std::vector<std::string> names = {"SPACE",
                                                   "APOSTROPHE",
                                                   "COMMA",
                                                   "MINUS",
                                                   "PERIOD",
                                                   "SLASH",
                                                   "0",
                                                   "1",
                                                   "2",
                                                   "3",
                                                   "4",
                                                   "5",
                                                   "6",
                                                   "7",
                                                   "8",
                                                   "9",
                                                   "SEMICOLON",
                                                   "EQUAL",
                                                   "A",
                                                   "B",
                                                   "C",
                                                   "D",
                                                   "E",
                                                   "F",
                                                   "G",
                                                   "H",
                                                   "I",
                                                   "J",
                                                   "K",
                                                   "L",
                                                   "M",
                                                   "N",
                                                   "O",
                                                   "P",
                                                   "Q",
                                                   "R",
                                                   "S",
                                                   "T",
                                                   "U",
                                                   "V",
                                                   "W",
                                                   "X",
                                                   "Y",
                                                   "Z",
                                                   "LEFT_BRACKET",
                                                   "BACKSLASH",
                                                   "RIGHT_BRACKET",
                                                   "GRAVE_ACCENT",
                                                   "WORLD_1",
                                                   "WORLD_2",
                                                   "ESCAPE",
                                                   "ENTER",
                                                   "TAB",
                                                   "BACKSPACE",
                                                   "INSERT",
                                                   "DELETE",
                                                   "RIGHT",
                                                   "LEFT",
                                                   "DOWN",
                                                   "UP",
                                                   "PAGE_UP",
                                                   "PAGE_DOWN",
                                                   "HOME",
                                                   "END",
                                                   "CAPS_LOCK",
                                                   "SCROLL_LOCK",
                                                   "NUM_LOCK",
                                                   "PRINT_SCREEN",
                                                   "PAUSE",
                                                   "F1",
                                                   "F2",
                                                   "F3",
                                                   "F4",
                                                   "F5",
                                                   "F6",
                                                   "F7",
                                                   "F8",
                                                   "F9",
                                                   "F10",
                                                   "F11",
                                                   "F12",
                                                   "F13",
                                                   "F14",
                                                   "F15",
                                                   "F16",
                                                   "F17",
                                                   "F18",
                                                   "F19",
                                                   "F20",
                                                   "F21",
                                                   "F22",
                                                   "F23",
                                                   "F24",
                                                   "F25",
                                                   "KP_0",
                                                   "KP_1",
                                                   "KP_2",
                                                   "KP_3",
                                                   "KP_4",
                                                   "KP_5",
                                                   "KP_6",
                                                   "KP_7",
                                                   "KP_8",
                                                   "KP_9",
                                                   "KP_DECIMAL",
                                                   "KP_DIVIDE",
                                                   "KP_MULTIPLY",
                                                   "KP_SUBTRACT",
                                                   "KP_ADD",
                                                   "KP_ENTER",
                                                   "KP_EQUAL",
                                                   "LEFT_SHIFT",
                                                   "LEFT_CONTROL",
                                                   "LEFT_ALT",
                                                   "LEFT_SUPER",
                                                   "RIGHT_SHIFT",
                                                   "RIGHT_CONTROL",
                                                   "RIGHT_ALT",
                                                   "RIGHT_SUPER",
                                                   "MENU"};
    return names;
}

const std::vector<std::string>& bindableActions() {
    static const std::vector<std::string> a = {
        "cycle_tool",  "step",   "zoom_in",      "zoom_out", "overview", "undo",
        "redo",        "quit",   "size_1",       "size_2",   "size_3",   "size_4",
        "size_5",      "size_6", "size_7",       "save",     "save_as",  "export",
        "new_project", "help",   "cycle_mirror", "recenter"};
    return a;
}

const std::vector<std::string>& sketchBindableActions() {
    static const std::vector<std::string> a = [] {
        std::vector<std::string> names;
        for (const auto& [action, key] : InteractionConfig{}.sketchBindings)
            names.push_back(action);
        return names;
    }();
    return a;
}

std::string configToJson(const SculptConfig& c) {
    json j;
    j["tools"] = {{"levels", kLevelCount},
                  {"d4_mm", c.d4Mm},
                  {"growth", c.growth},
                  {"lattice_spacing_over_diameter", c.spacingOverDiameter}};
    j["field"] = {{"iso", c.iso},
                  {"falloff",
                   {{"f0", c.falloff.f0},
                    {"control_u", c.falloff.controlU},
                    {"control_value", c.falloff.controlValue},
                    {"control_slope", c.falloff.controlSlope}}}};
    if (c.manualSupport)
        j["field"]["support"] = {{"r4_mm", c.manualSupport->r4Mm},
                                 {"scale", c.manualSupport->scale}};
    else
        j["field"]["support"] = "calibrate";
    j["placement"] = {{"mode", toString(c.placement)},
                      {"finer_lattice_levels", c.finerLatticeLevels},
                      {"refine_levels", c.refineLevels},
                      {"smooth_keeps_volume", c.smoothKeepsVolume}};
    j["initial_sphere"] = {
        {"radius_mm", c.sphereRadiusMm},
        {"center_mm", {c.sphereCenterMm.x, c.sphereCenterMm.y, c.sphereCenterMm.z}},
        {"core_weight", c.sphereCoreWeight},
        {"core_support_over_radius", c.sphereCoreSupportOverRadius}};
    j["zoom"] = {{"levels", kZoomLevels},
                 {"base_spacing_over_d6", c.zoom.baseSpacingOverD6},
                 {"allowed_sizes", c.zoom.allowedSizes}};
    const XrConfig& x = c.render.xr;
    j["render"] = {{"output", c.render.output},
                   {"xr",
                    {{"sculpture_in_local_m",
                      {x.sculptureInLocalM.x, x.sculptureInLocalM.y, x.sculptureInLocalM.z}},
                     {"pen_tip_mm", x.penTipMm},
                     {"trigger_threshold", x.triggerThreshold},
                     {"trigger_penetration_mm", x.triggerPenetrationMm},
                     {"haptic_touching", x.hapticTouching},
                     {"haptic_inside", x.hapticInside},
                     {"haptic_pulse_ms", x.hapticPulseMs},
                     {"msaa_samples", x.msaaSamples}}},
                   {"stereo", c.render.stereo},
                   {"ipd_mm", c.render.ipdMm},
                   {"vertical_fov_deg", c.render.verticalFovDeg},
                   {"fullscreen_monitor", c.render.fullscreenMonitor},
                   {"ui_depth_mm", c.render.uiDepthMm},
                   {"ui_scale", c.render.uiScale},
                   {"msaa_samples", c.render.msaaSamples},
                   {"lens",
                    {{"k1", c.render.lensK1},
                     {"k2", c.render.lensK2},
                     {"red_scale", c.render.lensRedScale},
                     {"blue_scale", c.render.lensBlueScale}}}};
    {
        json match = json::array();
        for (const auto& d : c.devices.match)
            match.push_back({{"name", d.name},
                             {"driver", d.driver},
                             {"access", d.access},
                             {"vendor", d.vendor},
                             {"products", d.products},
                             {"interface", d.interfaceNumber},
                             {"in_endpoint", d.inEndpoint},
                             {"out_endpoint", d.outEndpoint}});
        const Vec3& t = c.devices.worldFromTrackerTranslationMm;
        const Vec3& r = c.devices.worldFromTrackerRotationDeg;
        const Vec3& tip = c.devices.penTipMm;
        j["devices"] = {{"transfers_in_flight", c.devices.transfersInFlight},
                        {"stall_timeout_s", c.devices.stallTimeoutS},
                        {"rescan_interval_s", c.devices.rescanIntervalS},
                        {"object_from_3d_mouse",
                         {{"full_scale", c.devices.mouseFullScale},
                          {"dead_zone", c.devices.mouseDeadZone},
                          {"translate_mm_per_s", c.devices.objectTranslateMmPerS},
                          {"rotate_deg_per_s", c.devices.objectRotateDegPerS}}},
                        {"tracker",
                         {{"pen_station", c.devices.penStation},
                          {"head_station", c.devices.headStation},
                          {"object_station", c.devices.objectStation},
                          {"world_from_tracker_translation_mm", {t.x, t.y, t.z}},
                          {"world_from_tracker_rotation_deg", {r.x, r.y, r.z}},
                          {"pen_tip_mm", {tip.x, tip.y, tip.z}},
                          {"always_engaged", c.devices.penAlwaysEngaged}}}};
        if (!c.devices.match.empty()) j["devices"]["match"] = match;
    }
    j["interaction"] = {{"bindings", c.interaction.bindings},
                        {"sketch_bindings", c.interaction.sketchBindings},
                        {"depth_step_over_diameter", c.interaction.depthStepOverDiameter},
                        {"rotate_rad_per_pixel", c.interaction.rotateRadPerPixel}};
    j["polygonizer"] = {{"grid_n", c.polygonizer.gridN},
                        {"root_tolerance", c.polygonizer.rootTolerance},
                        {"view_root_tolerance", c.polygonizer.viewRootTolerance}};
    return j.dump(2);
}

void validateConfig(const SculptConfig& c) {
    auto fail = [&](const std::string& key, const std::string& why) {
        throw ConfigError(c.source + ": " + key + ": " + why);
    };
    auto num = [](double v) {
        std::ostringstream s;
        s << v;
        return s.str();
    };
    // At least 10 µm: 1e-320 passed "> 0" and gave a sphere of no triangles (found by QA).
    if (!(std::isfinite(c.d4Mm) && c.d4Mm >= 0.01 && c.d4Mm <= 1e4))
        fail("tools.d4_mm",
             "must be a diameter in mm, >= 0.01 and <= 10000 (got " + num(c.d4Mm) + ")");
    if (!(std::isfinite(c.growth) && c.growth > 1 && c.growth <= 4))
        fail("tools.growth", "must be > 1 (levels grow) and <= 4 (got " + num(c.growth) + ")");
    // A tool sphere of radius D/2 contains a lattice vertex wherever it is iff
    // D/2 >= (sqrt(3)/2) h, i.e. h/D <= 1/sqrt(3); beyond that strokes can place nothing.
    const double maxSigma = 1 / std::sqrt(3.0);
    if (!(std::isfinite(c.spacingOverDiameter) && c.spacingOverDiameter > 0.05 &&
          c.spacingOverDiameter <= maxSigma + 1e-12))
        fail("tools.lattice_spacing_over_diameter",
             "must be in (0.05, " + num(maxSigma) +
                 "] so every tool position covers a lattice vertex (got " +
                 num(c.spacingOverDiameter) + ")");
    if (const std::string why = validateFalloff(c.falloff); !why.empty())
        fail("field.falloff", why);
    if (!(c.iso > 0 && c.iso < c.falloff.f0))
        fail("field.iso", "must lie strictly between 0 and falloff.f0=" + num(c.falloff.f0) +
                              " (got " + num(c.iso) + ")");
    if (c.manualSupport) {
        const ManualSupport& m = *c.manualSupport;
        if (!(std::isfinite(m.r4Mm) && m.r4Mm > 0)) fail("field.support.r4_mm", "must be > 0");
        if (std::abs(m.scale[kReferenceLevel - 1] - 1.0) > 1e-12)
            fail("field.support.scale[3]", "L_4 must be exactly 1 (it is the reference)");
        for (int k = 0; k < kLevelCount; ++k) {
            if (!(std::isfinite(m.scale[k]) && m.scale[k] > 0))
                fail("field.support.scale[" + std::to_string(k) + "]", "must be > 0");
            if (k > 0 && !(m.scale[k] > m.scale[k - 1]))
                fail(
                    "field.support.scale[" + std::to_string(k) + "]",
                    "must be larger than L_" + std::to_string(k) + " (larger tools reach further)");
        }
    }
    if (!(std::isfinite(c.sphereRadiusMm) && c.sphereRadiusMm >= 0 && c.sphereRadiusMm <= 1e5))
        fail("initial_sphere.radius_mm", "must be >= 0 mm (0: start empty) and <= 1e5");
    if (!isUsablePoint(c.sphereCenterMm))
        fail("initial_sphere.center_mm", "must be finite and within 1e6 mm of the origin");
    if (!(std::isfinite(c.sphereCoreWeight) && c.sphereCoreWeight >= 0 && c.sphereCoreWeight <= 10))
        fail("initial_sphere.core_weight",
             "must be >= 0 (0: no core) and <= 10 (got " + num(c.sphereCoreWeight) + ")");
    if (!(std::isfinite(c.sphereCoreSupportOverRadius) && c.sphereCoreSupportOverRadius >= 1 &&
          c.sphereCoreSupportOverRadius <= 4))
        fail("initial_sphere.core_support_over_radius",
             "must be in [1, 4] (got " + num(c.sphereCoreSupportOverRadius) + ")");
    if (c.sphereRadiusMm > 0 && c.sphereCoreWeight > 0) {
        // The outer skeleton must still bring the field up to the iso-level at the radius.
        const double coreAtSurface =
            c.sphereCoreWeight * HermiteFalloff(c.falloff).value(1 / c.sphereCoreSupportOverRadius);
        if (!(coreAtSurface < 0.9 * c.iso))
            fail("initial_sphere.core_weight",
                 "the core alone gives " + num(coreAtSurface) +
                     " at the sphere's surface (support " + num(c.sphereCoreSupportOverRadius) +
                     " x the radius), more than 0.9 x field.iso; lower the weight or the support");
    }
    if (!(std::isfinite(c.zoom.baseSpacingOverD6) && c.zoom.baseSpacingOverD6 > 0 &&
          c.zoom.baseSpacingOverD6 <= 2))
        fail("zoom.base_spacing_over_d6",
             "must be in (0, 2] (got " + num(c.zoom.baseSpacingOverD6) + ")");
    if (!(std::isfinite(c.interaction.depthStepOverDiameter) &&
          c.interaction.depthStepOverDiameter > 0 && c.interaction.depthStepOverDiameter <= 10))
        fail("interaction.depth_step_over_diameter", "must be in (0, 10]");
    if (!(std::isfinite(c.interaction.rotateRadPerPixel) && c.interaction.rotateRadPerPixel > 0 &&
          c.interaction.rotateRadPerPixel <= 1))
        fail("interaction.rotate_rad_per_pixel", "must be in (0, 1]");
    if (!(std::isfinite(c.render.ipdMm) && c.render.ipdMm >= 0 && c.render.ipdMm <= 200))
        fail("render.ipd_mm", "must be in [0, 200] mm");
    if (!(std::isfinite(c.render.uiDepthMm) && c.render.uiDepthMm >= 0 &&
          c.render.uiDepthMm <= 100000))
        fail("render.ui_depth_mm", "must be in [0, 100000] mm (0: the zero-parallax plane)");
    if (!(std::isfinite(c.render.uiScale) && c.render.uiScale >= 0.5 && c.render.uiScale <= 4))
        fail("render.ui_scale", "must be in [0.5, 4]");
    if (!(c.render.verticalFovDeg >= 5 && c.render.verticalFovDeg <= 170))
        fail("render.vertical_fov_deg", "must be in [5, 170] degrees");
    if (c.render.fullscreenMonitor < -1) fail("render.fullscreen_monitor", "must be >= -1");
    {
        const XrConfig& x = c.render.xr;
        for (int i = 0; i < 3; ++i)
            if (!(std::isfinite(x.sculptureInLocalM[i]) && std::abs(x.sculptureInLocalM[i]) <= 100))
                fail("render.xr.sculpture_in_local_m", "each coordinate must be in [-100, 100] m");
        if (!(std::isfinite(x.penTipMm) && std::abs(x.penTipMm) <= 1000))
            fail("render.xr.pen_tip_mm", "must be in [-1000, 1000] mm");
        if (!(x.triggerThreshold > 0 && x.triggerThreshold <= 1))
            fail("render.xr.trigger_threshold", "must be in (0, 1]");
        if (!(x.triggerPenetrationMm >= 0 && x.triggerPenetrationMm <= 1000))
            fail("render.xr.trigger_penetration_mm", "must be in [0, 1000] mm (0: off)");
        for (const auto& [key, v] : {std::pair{"render.xr.haptic_touching", x.hapticTouching},
                                     std::pair{"render.xr.haptic_inside", x.hapticInside}})
            if (!(v >= 0 && v <= 1)) fail(key, "must be in [0, 1] (0: no pulse)");
        if (!(x.hapticPulseMs > 0 && x.hapticPulseMs <= 1000))
            fail("render.xr.haptic_pulse_ms", "must be in (0, 1000] ms");
        if (!isSampleCount(x.msaaSamples, false))
            fail("render.xr.msaa_samples", "must be 1, 2, 4 or 8 (1: off)");
    }
    if (!isSampleCount(c.render.msaaSamples, true))
        fail("render.msaa_samples", "must be 0 (auto), 1, 2, 4 or 8 (1: off)");
    for (const auto& [key, v] : {std::pair{"render.lens.k1", c.render.lensK1},
                                 std::pair{"render.lens.k2", c.render.lensK2}})
        if (!(std::isfinite(v) && std::abs(v) <= 5)) fail(key, "must be in [-5, 5]");
    for (const auto& [key, v] : {std::pair{"render.lens.red_scale", c.render.lensRedScale},
                                 std::pair{"render.lens.blue_scale", c.render.lensBlueScale}})
        if (!(std::isfinite(v) && v >= 0.5 && v <= 2)) fail(key, "must be in [0.5, 2]");
    const DevicesConfig& d = c.devices;
    if (!(std::isfinite(d.stallTimeoutS) && d.stallTimeoutS >= 0.1 && d.stallTimeoutS <= 60))
        fail("devices.stall_timeout_s",
             "must be in [0.1, 60] s (got " + num(d.stallTimeoutS) + ")");
    if (!(std::isfinite(d.rescanIntervalS) && d.rescanIntervalS >= 0.01 && d.rescanIntervalS <= 60))
        fail("devices.rescan_interval_s",
             "must be in [0.01, 60] s (got " + num(d.rescanIntervalS) + ")");
    if (!(std::isfinite(d.mouseFullScale) && d.mouseFullScale > 0))
        fail("devices.object_from_3d_mouse.full_scale",
             "must be > 0 (got " + num(d.mouseFullScale) + ")");
    if (!(std::isfinite(d.mouseDeadZone) && d.mouseDeadZone >= 0 && d.mouseDeadZone < 1))
        fail("devices.object_from_3d_mouse.dead_zone",
             "must be in [0, 1) (got " + num(d.mouseDeadZone) + ")");
    if (!(std::isfinite(d.objectTranslateMmPerS) && d.objectTranslateMmPerS >= 0))
        fail("devices.object_from_3d_mouse.translate_mm_per_s", "must be >= 0");
    if (!(std::isfinite(d.objectRotateDegPerS) && d.objectRotateDegPerS >= 0))
        fail("devices.object_from_3d_mouse.rotate_deg_per_s", "must be >= 0");
    if (c.polygonizer.gridN < 16 || c.polygonizer.gridN > 1024 || c.polygonizer.gridN % 16 != 0)
        fail("polygonizer.grid_n", "must be a multiple of 16 between 16 and 1024 (got " +
                                       std::to_string(c.polygonizer.gridN) + ")");
    auto tolerance = [&](const char* key, double value) {
        if (!(std::isfinite(value) && value >= 1e-9 && value <= 0.5))
            fail(key,
                 "must be in [1e-9, 0.5] (a fraction of the grid spacing; got " + num(value) + ")");
    };
    tolerance("polygonizer.root_tolerance", c.polygonizer.rootTolerance);
    tolerance("polygonizer.view_root_tolerance", c.polygonizer.viewRootTolerance);
}

}  // namespace vsculpt::core
