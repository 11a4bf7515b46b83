// SPDX-License-Identifier: MIT
#include "vsculpt/app/Script.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace vsculpt::app {

namespace {

std::vector<std::string> words(std::string_view line) {
    std::vector<std::string> out;
    std::istringstream in{std::string(line)};
    for (std::string w; in >> w;)
        out.push_back(w);
    return out;
}

class LineParser {
  public:
    LineParser(const std::string& source, int line) : mSource(source), mLine(line) {}
    [[noreturn]] void fail(const std::string& why) const {
        throw ScriptError(mSource + ":" + std::to_string(mLine) + ": " + why);
    }
    double number(const std::string& w, const char* what) const {
        double v = 0;
        const auto [p, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
        if (ec != std::errc() || p != w.data() + w.size() || !std::isfinite(v))
            fail(std::string("expected a number for ") + what + ", got '" + w + "'");
        return v;
    }
    int integer(const std::string& w, const char* what) const {
        int v = 0;
        const auto [p, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
        if (ec != std::errc() || p != w.data() + w.size())
            fail(std::string("expected an integer for ") + what + ", got '" + w + "'");
        return v;
    }
    core::Vec3 point(const std::vector<std::string>& w, size_t at, const char* what) const {
        const core::Vec3 p(number(w[at], what), number(w[at + 1], what), number(w[at + 2], what));
        if (!core::isUsablePoint(p)) fail(std::string(what) + " lies beyond 1e6 mm");
        return p;
    }

  private:
    const std::string& mSource;
    int mLine;
};

}  // namespace

Script parseScript(std::string_view text, const std::string& source) {
    Script script;
    script.source = source;
    std::istringstream in{std::string(text)};
    std::string raw;
    int lineNo = 0;
    // A command may continue over following lines that end the previous one with '\'.
    std::string pending;
    int pendingLine = 0;
    auto handle = [&](const std::string& full, int startLine) {
        const std::vector<std::string> w = words(full);
        if (w.empty()) return;
        LineParser p(source, startLine);
        ScriptCommand c;
        c.line = startLine;
        const std::string& cmd = w[0];
        auto arity = [&](size_t lo, size_t hi, const char* usage) {
            if (w.size() - 1 < lo || w.size() - 1 > hi)
                p.fail("'" + cmd + "' takes " + usage + " (got " + std::to_string(w.size() - 1) +
                       " argument(s))");
        };
        if (cmd == "tool") {
            arity(1, 1, "one of add, carve, select");
            c.kind = ScriptCommand::Kind::Tool;
            if (w[1] == "add")
                c.tool = ToolKind::Add;
            else if (w[1] == "carve")
                c.tool = ToolKind::Carve;
            else if (w[1] == "select")
                c.tool = ToolKind::Select;
            else
                p.fail("unknown tool '" + w[1] + "' (use add, carve or select)");
        } else if (cmd == "size") {
            arity(1, 1, "a tool level 1..7");
            c.kind = ScriptCommand::Kind::Size;
            c.value = p.integer(w[1], "the tool level");
            if (c.value < 1 || c.value > 7) p.fail("tool level " + w[1] + " outside 1..7");
        } else if (cmd == "zoom") {
            if (w.size() != 2 && w.size() != 5) arity(1, 1, "Z or Z x y z");
            c.kind = ScriptCommand::Kind::Zoom;
            c.value = p.integer(w[1], "the zoom level");
            if (c.value < 1 || c.value > 5) p.fail("zoom level " + w[1] + " outside 1..5");
            if (w.size() == 5) {
                c.hasPoint = true;
                c.point = p.point(w, 2, "the zoom centre");
            } else if (c.value > 1) {
                p.fail("zoom " + w[1] + " needs the region centre: zoom " + w[1] + " x y z");
            }
        } else if (cmd == "object") {
            if (w.size() != 4 && w.size() != 8) arity(3, 3, "x y z [qw qx qy qz]");
            c.kind = ScriptCommand::Kind::Object;
            c.pose.translation = p.point(w, 1, "the object position");
            if (w.size() == 8) {
                const glm::dquat q(p.number(w[4], "qw"), p.number(w[5], "qx"), p.number(w[6], "qy"),
                                   p.number(w[7], "qz"));
                const double len = glm::length(q);
                if (!(len > 1e-9)) p.fail("the object rotation quaternion has zero length");
                c.pose.rotation = q / len;
            }
        } else if (cmd == "space") {
            arity(1, 1, "object or world");
            c.kind = ScriptCommand::Kind::Space;
            if (w[1] == "world")
                c.world = true;
            else if (w[1] != "object")
                p.fail("unknown space '" + w[1] + "' (use object or world)");
        } else if (cmd == "stroke") {
            c.kind = ScriptCommand::Kind::Stroke;
            if (w.size() < 4 || (w.size() - 1) % 3 != 0)
                p.fail("'stroke' takes points x y z [x y z ...] (got " +
                       std::to_string(w.size() - 1) + " number(s), not a multiple of 3)");
            for (size_t i = 1; i < w.size(); i += 3)
                c.points.push_back(p.point(w, i, "a stroke point"));
        } else if (cmd == "undo" || cmd == "redo" || cmd == "save") {
            arity(0, 0, "no arguments");
            c.kind = cmd == "undo"   ? ScriptCommand::Kind::Undo
                     : cmd == "redo" ? ScriptCommand::Kind::Redo
                                     : ScriptCommand::Kind::Save;
        } else {
            p.fail("unknown command '" + cmd +
                   "' (commands: tool, size, zoom, object, space, stroke, undo, redo, save)");
        }
        script.commands.push_back(std::move(c));
    };
    while (std::getline(in, raw)) {
        ++lineNo;
        if (!raw.empty() && raw.back() == '\r') raw.pop_back();
        const size_t hash = raw.find('#');
        std::string line = hash == std::string::npos ? raw : raw.substr(0, hash);
        // Trailing whitespace does not hide a continuation backslash.
        while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back())))
            line.pop_back();
        const bool continues = !line.empty() && line.back() == '\\';
        if (continues) line.pop_back();
        if (pending.empty() && !continues) {
            handle(line, lineNo);
            continue;
        }
        if (pending.empty()) pendingLine = lineNo;
        pending += ' ' + line;
        if (!continues) {
            handle(pending, pendingLine);
            pending.clear();
        }
    }
    if (!pending.empty())
        throw ScriptError(source + ":" + std::to_string(pendingLine) +
                          ": the command continued with '\\' never ends");
    return script;
}

Script loadScript(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ScriptError(path.string() + ":0: cannot open script");
    std::ostringstream s;
    s << in.rdbuf();
    return parseScript(s.str(), path.string());
}

}  // namespace vsculpt::app
