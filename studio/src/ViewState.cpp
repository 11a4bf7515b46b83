// SPDX-License-Identifier: MIT
#include "vsculpt/studio/ViewState.h"

#include "vsculpt/core/InvalidJson.h"
#include "vsculpt/core/WriteFileAtomically.h"
#include "vsculpt/studio/Session.h"
#include "vsculpt/studio/Studio.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace vsculpt::studio {

using nlohmann::json;

namespace {

constexpr const char* kFormat = "vsculpt-view";
constexpr int kVersion = 1;

json vec3(const core::Vec3& v) {
    return json::array({v.x, v.y, v.z});
}

/// Reads the fields of one view.json, each refusal naming the file and the field.
class Fields {
  public:
    Fields(const json& j, const std::string& source) : mJ(j), mSource(source) {}

    [[noreturn]] void fail(const std::string& field, const std::string& why) const {
        throw std::invalid_argument(mSource + ": field '" + field + "': " + why);
    }
    const json& at(const char* field) const {
        const auto it = mJ.find(field);
        if (it == mJ.end()) fail(field, "missing");
        return *it;
    }
    std::string text(const char* field) const {
        const json& v = at(field);
        if (!v.is_string()) fail(field, "not a string");
        return v.get<std::string>();
    }
    int integer(const char* field, int lo, int hi) const {
        const json& v = at(field);
        if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
            fail(field, v.dump() + " is not a whole number in " + std::to_string(lo) + ".." +
                            std::to_string(hi));
        return v.get<int>();
    }
    template <size_t N>
    std::array<double, N> numbers(const char* field) const {
        const json& v = at(field);
        if (!v.is_array() || v.size() != N)
            fail(field, "not an array of " + std::to_string(N) + " numbers");
        std::array<double, N> out{};
        for (size_t i = 0; i < N; ++i) {
            if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
                fail(field, "element " + std::to_string(i) + " is not a finite number");
            out[i] = v[i].get<double>();
        }
        return out;
    }
    core::Vec3 point(const char* field) const {
        const auto a = numbers<3>(field);
        const core::Vec3 p(a[0], a[1], a[2]);
        if (!core::isUsablePoint(p)) fail(field, "not a point within 1e6 mm of the origin");
        return p;
    }

  private:
    const json& mJ;
    const std::string& mSource;
};

}  // namespace

ViewState viewStateOf(const Session& session) {
    ViewState v;
    v.tool = session.tool();
    v.mirror = session.mirror();
    v.size = session.size();
    v.zoom = session.zoom();
    v.zoomCentreMm = session.zoomCentre();
    v.worldFromObject = session.objectPose();
    return v;
}

void applyViewState(Studio& studio, const ViewState& state) {
    studio.setObjectPose(state.worldFromObject);
    studio.setZoom(state.zoom, state.zoomCentreMm);
    studio.setSize(state.size);
    studio.setTool(state.tool);
    studio.setMirror(state.mirror);
}

std::filesystem::path viewStatePath(const std::filesystem::path& dir) {
    return dir / "view.json";
}

std::string viewStateJson(const ViewState& state) {
    const glm::dquat& q = state.worldFromObject.rotation;
    json j;
    j["format"] = kFormat;
    j["version"] = kVersion;
    j["tool"] = toString(state.tool);
    j["size"] = state.size;
    j["zoom"] = state.zoom;
    j["zoom_centre_mm"] = vec3(state.zoomCentreMm);
    j["mirror"] = core::toString(state.mirror);
    j["object_rotation_wxyz"] = json::array({q.w, q.x, q.y, q.z});
    j["object_translation_mm"] = vec3(state.worldFromObject.translation);
    // nlohmann writes the shortest decimal that reads back to the same double: the pose
    // comes back bit for bit.
    return j.dump(2) + "\n";
}

ViewState parseViewState(const std::string& text, const std::string& source) {
    // nlohmann's parser takes a NUL byte for the end of the text (found by QA: a good file
    // with garbage after a NUL was read as good); a view file is text.
    if (const size_t nul = text.find('\0'); nul != std::string::npos)
        throw std::invalid_argument(source + ": a NUL byte at offset " + std::to_string(nul) +
                                    " (not a view file)");
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        throw std::invalid_argument(core::invalidJsonMessage(source, text, e));
    }
    if (!j.is_object()) throw std::invalid_argument(source + ": not a JSON object");
    const Fields f(j, source);
    if (f.text("format") != kFormat) f.fail("format", "not \"" + std::string(kFormat) + "\"");
    if (const int version = f.integer("version", 1, 1 << 30); version != kVersion)
        f.fail("version", std::to_string(version) + " is newer than this vsculpt reads (" +
                              std::to_string(kVersion) + ")");
    ViewState v;
    const std::string tool = f.text("tool");
    if (const auto t = toolKindNamed(tool))
        v.tool = *t;
    else
        f.fail("tool", "'" + tool + "' is not add, carve, smooth or select");
    const std::string mirror = f.text("mirror");
    if (const auto a = mirrorAxisNamed(mirror))
        v.mirror = *a;
    else
        f.fail("mirror", "'" + mirror + "' is not x, y, z or off");
    v.size = f.integer("size", 1, 7);
    v.zoom = f.integer("zoom", 1, 5);
    v.zoomCentreMm = f.point("zoom_centre_mm");
    const auto q = f.numbers<4>("object_rotation_wxyz");
    const glm::dquat rotation(q[0], q[1], q[2], q[3]);
    const double norm = glm::length(rotation);
    // A pose that was written is unit to rounding; anything else was edited or damaged. Kept
    // as written (not renormalised), so the pose comes back bit for bit.
    if (!(std::abs(norm - 1) <= 1e-6)) f.fail("object_rotation_wxyz", "not a unit quaternion");
    v.worldFromObject.rotation = rotation;
    v.worldFromObject.translation = f.point("object_translation_mm");
    return v;
}

void writeViewState(const std::filesystem::path& dir, const ViewState& state) {
    core::writeFileAtomically(viewStatePath(dir), viewStateJson(state), /*durable=*/false);
}

std::optional<ViewState> readViewState(const std::filesystem::path& dir) {
    const std::filesystem::path path = viewStatePath(dir);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return std::nullopt;
    if (!std::filesystem::is_regular_file(path, ec))
        throw std::invalid_argument(path.string() + ": not a regular file");
    // What viewStateJson writes is some 400 bytes (found by QA: a 6 GB file was read whole,
    // and the window took 14 s to start).
    constexpr std::uintmax_t kMaxBytes = 64 * 1024;
    if (const std::uintmax_t size = std::filesystem::file_size(path, ec); !ec && size > kMaxBytes)
        throw std::invalid_argument(path.string() + ": " + std::to_string(size) +
                                    " bytes, not a view file (those are under 1 KB)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::invalid_argument(path.string() + ": cannot be opened for reading");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw std::invalid_argument(path.string() + ": cannot be read");
    return parseViewState(text.str(), path.string());
}

}  // namespace vsculpt::studio
