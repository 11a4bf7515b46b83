// SPDX-License-Identifier: MIT
#include "vsculpt/core/Config.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#ifndef VSCULPT_CONFIG_DIR
#define VSCULPT_CONFIG_DIR "configs"
#endif

namespace vsculpt::core {

using nlohmann::json;

const char* toString(PlacementMode m) {
    return m == PlacementMode::Thesis ? "thesis" : "free";
}

std::filesystem::path defaultConfigPath() {
    return std::filesystem::path(VSCULPT_CONFIG_DIR) / "sculpt.json";
}

namespace {

/// Walks one JSON object, remembering which keys were read so unknown ones can be reported.
class Section {
  public:
    Section(const json& obj, std::string path, const std::string& source)
        : mObj(obj), mPath(std::move(path)), mSource(source) {
        if (!mObj.is_object()) fail(mPath.empty() ? "top level" : mPath, "expected an object");
    }

    [[noreturn]] void fail(const std::string& key, const std::string& why) const {
        throw ConfigError(mSource + ": " + key + ": " + why);
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
    void rejectUnknown() const {
        for (auto it = mObj.begin(); it != mObj.end(); ++it) {
            if (it.key().rfind("_", 0) == 0) continue;  // "_comment" style keys are allowed
            if (!mSeen.count(it.key())) fail(keyPath(it.key()), "unknown key");
        }
    }

  private:
    const json& mObj;
    std::string mPath;
    const std::string& mSource;
    std::set<std::string> mSeen;
};

std::string lineColumn(std::string_view text, size_t byte) {
    size_t line = 1, col = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    return std::to_string(line) + ":" + std::to_string(col);
}

}  // namespace

SculptConfig parseConfig(std::string_view jsonText, const std::string& sourceName) {
    json root;
    try {
        root = json::parse(jsonText, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        // e.byte is 1-based and points just past the offending character.
        const size_t at = e.byte > 0 ? e.byte - 1 : 0;
        std::string what = e.what();
        if (auto p = what.find("parse error"); p != std::string::npos) what = what.substr(p);
        throw ConfigError(sourceName + ":" + lineColumn(jsonText, at) + ": invalid JSON: " + what);
    }

    SculptConfig cfg;
    cfg.source = sourceName;
    Section top(root, "", sourceName);

    Section tools = top.sub("tools");
    if (const json* v = tools.find("levels")) {
        if (!v->is_number_integer() || v->get<int>() != kLevelCount)
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
        else
            placement.fail("placement.mode", "expected \"thesis\" or \"free\", got " + v->dump());
    }
    placement.rejectUnknown();

    Section sphere = top.sub("initial_sphere");
    sphere.number("radius_mm", cfg.sphereRadiusMm);
    sphere.vec3("center_mm", cfg.sphereCenterMm);
    sphere.rejectUnknown();

    Section zoom = top.sub("zoom");
    if (const json* v = zoom.find("levels")) {
        if (!v->is_number_integer() || v->get<int>() != kZoomLevels)
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
                if (!k.is_number_integer() || k.get<int>() < 1 || k.get<int>() > kLevelCount)
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
        if (!v->is_number_integer())
            poly.fail("polygonizer.grid_n", "expected an integer, got " + v->dump());
        cfg.polygonizer.gridN = v->get<int>();
    }
    poly.number("bisection_tolerance", cfg.polygonizer.bisectionTolerance);
    poly.rejectUnknown();

    Section inter = top.sub("interaction");
    inter.number("depth_step_over_diameter", cfg.interaction.depthStepOverDiameter);
    inter.number("rotate_rad_per_pixel", cfg.interaction.rotateRadPerPixel);
    if (const json* b = inter.find("bindings")) {
        if (!b->is_object())
            inter.fail("interaction.bindings", "expected an object of action: key name");
        const auto& actions = bindableActions();
        for (auto it = b->begin(); it != b->end(); ++it) {
            const std::string key = "interaction.bindings." + it.key();
            if (std::find(actions.begin(), actions.end(), it.key()) == actions.end())
                inter.fail(key, "unknown action (see docs/window.md)");
            if (!it->is_string() || it->get<std::string>().empty())
                inter.fail(key, "expected a key name such as \"TAB\" or \"Z\"");
            cfg.interaction.bindings[it.key()] = it->get<std::string>();
        }
    }
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
        if (!v->is_number_integer())
            rend.fail("render.fullscreen_monitor", "expected an integer (-1: windowed)");
        cfg.render.fullscreenMonitor = v->get<int>();
    }
    Section lens = rend.sub("lens");
    lens.number("k1", cfg.render.lensK1);
    lens.number("k2", cfg.render.lensK2);
    lens.number("red_scale", cfg.render.lensRedScale);
    lens.number("blue_scale", cfg.render.lensBlueScale);
    lens.rejectUnknown();
    rend.rejectUnknown();

    // The devices section is owned by the device layer (issue #6), accepted as it is here.
    top.find("devices");
    top.rejectUnknown();

    validateConfig(cfg);
    return cfg;
}

SculptConfig loadConfig(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ConfigError(path.string() + ": cannot open config file");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw ConfigError(path.string() + ": read error");
    return parseConfig(text.str(), path.string());
}

const std::vector<std::string>& bindableActions() {
    static const std::vector<std::string> a = {
        "cycle_tool", "step",   "zoom_in", "zoom_out", "overview", "undo",   "redo",  "quit",
        "size_1",     "size_2", "size_3",  "size_4",   "size_5",   "size_6", "size_7"};
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
    j["placement"] = {{"mode", toString(c.placement)}};
    j["initial_sphere"] = {
        {"radius_mm", c.sphereRadiusMm},
        {"center_mm", {c.sphereCenterMm.x, c.sphereCenterMm.y, c.sphereCenterMm.z}}};
    j["zoom"] = {{"levels", kZoomLevels},
                 {"base_spacing_over_d6", c.zoom.baseSpacingOverD6},
                 {"allowed_sizes", c.zoom.allowedSizes}};
    j["render"] = {{"stereo", c.render.stereo},
                   {"ipd_mm", c.render.ipdMm},
                   {"vertical_fov_deg", c.render.verticalFovDeg},
                   {"fullscreen_monitor", c.render.fullscreenMonitor},
                   {"lens",
                    {{"k1", c.render.lensK1},
                     {"k2", c.render.lensK2},
                     {"red_scale", c.render.lensRedScale},
                     {"blue_scale", c.render.lensBlueScale}}}};
    j["interaction"] = {{"bindings", c.interaction.bindings},
                        {"depth_step_over_diameter", c.interaction.depthStepOverDiameter},
                        {"rotate_rad_per_pixel", c.interaction.rotateRadPerPixel}};
    j["polygonizer"] = {{"grid_n", c.polygonizer.gridN},
                        {"bisection_tolerance", c.polygonizer.bisectionTolerance}};
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
    if (!(std::isfinite(c.d4Mm) && c.d4Mm > 0 && c.d4Mm <= 1e4))
        fail("tools.d4_mm", "must be a diameter in mm, > 0 and <= 10000 (got " + num(c.d4Mm) + ")");
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
    if (!(c.render.verticalFovDeg >= 5 && c.render.verticalFovDeg <= 170))
        fail("render.vertical_fov_deg", "must be in [5, 170] degrees");
    if (c.render.fullscreenMonitor < -1) fail("render.fullscreen_monitor", "must be >= -1");
    for (const auto& [key, v] : {std::pair{"render.lens.k1", c.render.lensK1},
                                 std::pair{"render.lens.k2", c.render.lensK2}})
        if (!(std::isfinite(v) && std::abs(v) <= 5)) fail(key, "must be in [-5, 5]");
    for (const auto& [key, v] : {std::pair{"render.lens.red_scale", c.render.lensRedScale},
                                 std::pair{"render.lens.blue_scale", c.render.lensBlueScale}})
        if (!(std::isfinite(v) && v >= 0.5 && v <= 2)) fail(key, "must be in [0.5, 2]");
    if (c.polygonizer.gridN < 16 || c.polygonizer.gridN > 1024 || c.polygonizer.gridN % 16 != 0)
        fail("polygonizer.grid_n", "must be a multiple of 16 between 16 and 1024 (got " +
                                       std::to_string(c.polygonizer.gridN) + ")");
    if (!(std::isfinite(c.polygonizer.bisectionTolerance) &&
          c.polygonizer.bisectionTolerance >= 1e-9 && c.polygonizer.bisectionTolerance <= 0.5))
        fail("polygonizer.bisection_tolerance",
             "must be in [1e-9, 0.5] (a fraction of the grid spacing; got " +
                 num(c.polygonizer.bisectionTolerance) + ")");
}

}  // namespace vsculpt::core
