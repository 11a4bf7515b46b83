// SPDX-License-Identifier: MIT
#include "vsculpt/core/PatchConfigText.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace vsculpt::core {

namespace {

using json = nlohmann::json;

/// Where an object's members and values lie in the text (byte offsets).
struct ObjectSpan {
    struct Member {
        std::string key;
        size_t keyBegin = 0, valueBegin = 0, valueEnd = 0;
        int object = -1;  // index of the value's ObjectSpan when it is an object
    };
    std::vector<Member> members;
    size_t open = 0, close = 0;  // the braces
};

/// A scanner of JSON with // and /* */ comments that records where object members are. The
/// text has been validated by nlohmann::json first, so it only needs to find boundaries.
class Scanner {
  public:
    explicit Scanner(std::string_view t) : mText(t) {}
    std::vector<ObjectSpan> objects;

    size_t value(size_t p) {  // returns the offset just past the value starting at p
        p = skip(p);
        const char c = mText[p];
        if (c == '{') return object(p);
        if (c == '[') {
            p = skip(p + 1);
            if (mText[p] == ']') return p + 1;
            for (;;) {
                p = skip(value(p));
                if (mText[p] == ']') return p + 1;
                ++p;  // ','
            }
        }
        if (c == '"') return string(p);
        while (p < mText.size() &&
               std::string_view(",]} \t\r\n/").find(mText[p]) == std::string_view::npos)
            ++p;  // number or literal
        return p;
    }
    size_t skip(size_t p) const {
        while (p < mText.size()) {
            const char c = mText[p];
            if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
                ++p;
            } else if (c == '/' && p + 1 < mText.size() && mText[p + 1] == '/') {
                while (p < mText.size() && mText[p] != '\n')
                    ++p;
            } else if (c == '/' && p + 1 < mText.size() && mText[p + 1] == '*') {
                const size_t e = mText.find("*/", p + 2);
                p = e == std::string_view::npos ? mText.size() : e + 2;
            } else {
                break;
            }
        }
        return p;
    }

  private:
    size_t string(size_t p) const {
        for (++p; p < mText.size() && mText[p] != '"'; ++p)
            if (mText[p] == '\\') ++p;
        return p + 1;
    }
    size_t object(size_t p) {
        const int index = int(objects.size());
        objects.emplace_back();
        objects[size_t(index)].open = p;
        p = skip(p + 1);
        while (mText[p] != '}') {
            ObjectSpan::Member m;
            m.keyBegin = p;
            const size_t keyEnd = string(p);
            m.key = json::parse(mText.substr(p, keyEnd - p)).get<std::string>();
            p = skip(keyEnd) + 1;  // ':'
            m.valueBegin = skip(p);
            if (mText[m.valueBegin] == '{') m.object = int(objects.size());
            m.valueEnd = value(m.valueBegin);
            objects[size_t(index)].members.push_back(std::move(m));
            p = skip(m.valueEnd);
            if (mText[p] == ',') p = skip(p + 1);
        }
        objects[size_t(index)].close = p;
        return p + 1;
    }
    std::string_view mText;
};

struct Edit {
    size_t at, length;
    std::string text;
};

/// The indentation of the line holding offset p (its leading spaces and tabs).
std::string indentAt(std::string_view t, size_t p) {
    size_t start = t.rfind('\n', p == 0 ? 0 : p - 1);
    start = start == std::string_view::npos ? 0 : start + 1;
    size_t e = start;
    while (e < t.size() && (t[e] == ' ' || t[e] == '\t'))
        ++e;
    return std::string(t.substr(start, e - start));
}

/// A value as the file would hold it at `indent`: objects, and arrays holding them, over
/// several lines; the rest on one.
std::string valueText(const json& v, const std::string& indent) {
    const bool nested = v.is_array() && std::any_of(v.begin(), v.end(), [](const json& e) {
                            return e.is_structured();
                        });
    if (v.empty() || (!v.is_object() && !nested)) return v.dump();
    std::string s = v.dump(2), out;
    for (char c : s) {
        out += c;
        if (c == '\n') out += indent;
    }
    return out;
}

/// The members of `want` that differ from `fallback`, sections recursively: what a section the
/// file lacks must hold to load as wanted.
json changesFrom(const json& want, const json& fallback) {
    if (!want.is_object() || !fallback.is_object()) return want;
    json out = json::object();
    for (const auto& [key, v] : want.items()) {
        if (!fallback.contains(key)) {
            out[key] = v;
        } else if (v != fallback[key]) {
            out[key] = v.is_object() ? changesFrom(v, fallback[key]) : v;
        }
    }
    return out;
}

void patchObject(std::string_view text, const std::vector<ObjectSpan>& objects, int index,
                 const json& target, const json& defaults, std::vector<Edit>& edits) {
    const ObjectSpan& o = objects[size_t(index)];
    const std::string outer = indentAt(text, o.open);
    const std::string inner =
        o.members.empty() ? outer + "  " : indentAt(text, o.members.front().keyBegin);
    std::string added;
    for (const auto& [key, want] : target.items()) {
        const auto m = std::find_if(o.members.begin(), o.members.end(),
                                    [&](const ObjectSpan::Member& x) { return x.key == key; });
        const json fallback =
            defaults.is_object() && defaults.contains(key) ? defaults[key] : json();
        if (m == o.members.end()) {
            if (want == fallback) continue;  // left out, it loads as wanted
            added += (added.empty() && o.members.empty() ? "\n" : ",\n") + inner +
                     json(key).dump() + ": " + valueText(changesFrom(want, fallback), inner);
            continue;
        }
        if (m->object >= 0 && want.is_object()) {
            patchObject(text, objects, m->object, want, fallback, edits);
            continue;
        }
        const json have = json::parse(text.substr(m->valueBegin, m->valueEnd - m->valueBegin),
                                      nullptr, true, /*ignore_comments=*/true);
        if (have != want)
            edits.push_back({m->valueBegin, m->valueEnd - m->valueBegin,
                             valueText(want, indentAt(text, m->keyBegin))});
    }
    if (added.empty()) return;
    if (o.members.empty())
        edits.push_back({o.open + 1, o.close - o.open - 1, added + "\n" + outer});
    else
        edits.push_back({o.members.back().valueEnd, 0, added});
}

}  // namespace

std::string patchConfigText(std::string_view fileText, const SculptConfig& cfg,
                            const std::string& sourceName) {
    // Validates (with the line of the first error) and gives the values the file holds now.
    parseConfig(fileText, sourceName);
    const json root = json::parse(fileText, nullptr, true, /*ignore_comments=*/true);
    if (!root.is_object()) throw ConfigError(sourceName + ": the config is not a JSON object");
    Scanner scan(fileText);
    // nlohmann::json skips a UTF-8 byte order mark; so does the scanner.
    scan.value(fileText.starts_with("\xEF\xBB\xBF") ? 3 : 0);
    if (scan.objects.empty())
        throw ConfigError(sourceName + ": the config is not a JSON object");
    const json target = json::parse(configToJson(cfg));
    const json defaults = json::parse(configToJson(SculptConfig{}));
    std::vector<Edit> edits;
    patchObject(fileText, scan.objects, 0, target, defaults, edits);
    std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.at > b.at; });
    std::string out(fileText);
    for (const Edit& e : edits)
        out.replace(e.at, e.length, e.text);
    return out;
}

}  // namespace vsculpt::core
