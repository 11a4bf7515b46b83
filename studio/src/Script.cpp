// SPDX-License-Identifier: MIT
#include "vsculpt/studio/Script.h"

#include "vsculpt/core/PrintableText.h"
#include "vsculpt/core/Project.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace vsculpt::studio {

namespace {

class LineParser {
  public:
    /// `parts`: a command continued over lines ('\\'), each physical line with its number, so
    /// a bad word is named on its own line (found by QA: line 4 for a word on line 6).
    LineParser(const std::string& source, int line,
               const std::vector<std::pair<int, std::string>>* parts = nullptr)
        : mSource(source), mLine(line), mParts(parts) {}
    [[noreturn]] void fail(const std::string& why) const { failOn(mLine, why); }
    /// The same, on the first physical line holding `word` as a word of its own.
    [[noreturn]] void failAt(const std::string& word, const std::string& why) const {
        failOn(lineOf(word), why);
    }
    double number(const std::string& w, const char* what,
                  const std::string* whole = nullptr) const {
        double v = 0;
        const auto [p, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
        if (ec != std::errc() || p != w.data() + w.size() || !std::isfinite(v))
            failAt(whole ? *whole : w,
                   std::string("expected a number for ") + what + ", got '" + w + "'");
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

    // "X,Y[,P[,T]]" with `lo`..`hi` fields.
    std::vector<double> tuple(const std::string& w, size_t lo, size_t hi, const char* what) const {
        std::vector<double> v;
        size_t start = 0;
        while (true) {
            const size_t comma = w.find(',', start);
            v.push_back(number(w.substr(start, comma - start), what, &w));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        if (v.size() < lo || v.size() > hi)
            failAt(w, std::string("expected ") + what + " as " +
                          (hi == 2 ? "X,Y" : "X,Y[,PRESSURE[,TIME]]") + ", got '" + w + "'");
        for (double x : v)
            if (std::abs(x) > 1e6) failAt(w, std::string(what) + " '" + w + "' lies beyond 1e6");
        return v;
    }

  private:
    [[noreturn]] void failOn(int line, const std::string& why) const {
        // What the line said is quoted in `why`: never raw bytes on the user's terminal.
        throw ScriptError(mSource + ":" + std::to_string(line) + ": " +
                          core::printableText(why, 240));
    }
    int lineOf(const std::string& word) const {
        if (!mParts) return mLine;
        for (const auto& [line, text] : *mParts) {
            std::istringstream in(text);
            for (std::string w; in >> w;)
                if (w == word) return line;
        }
        return mLine;
    }

    const std::string& mSource;
    int mLine;
    const std::vector<std::pair<int, std::string>>* mParts;
};

// The line's words, split at spaces and tabs; "a quoted word" may hold spaces (a page named
// "Sketch 1", as the window names them: found by QA). A quote left open is refused.
std::vector<std::string> words(std::string_view line, const LineParser& p) {
    std::vector<std::string> out;
    size_t i = 0;
    auto space = [&](size_t k) { return line[k] == ' ' || line[k] == '\t' || line[k] == '\r'; };
    while (i < line.size()) {
        if (space(i)) {
            ++i;
            continue;
        }
        if (line[i] == '"') {
            const size_t close = line.find('"', i + 1);
            if (close == std::string_view::npos) p.fail("a quoted word has no closing '\"'");
            out.emplace_back(line.substr(i + 1, close - i - 1));
            i = close + 1;
            if (i < line.size() && !space(i)) p.fail("expected a space after a quoted word");
            continue;
        }
        const size_t start = i;
        while (i < line.size() && !space(i))
            ++i;
        out.emplace_back(line.substr(start, i - start));
    }
    return out;
}

const char* const kRoles[] = {"none",          "outline",    "surface-x", "surface-y", "surface-z",
                              "sweep-section", "sweep-path", "cut",       "extrude"};

// Sketch commands (docs/playback.md). Returns false for a word that is not one.
bool parseSketch(const std::vector<std::string>& w, const LineParser& p, ScriptCommand& c) {
    using V = SketchCommand::Verb;
    SketchCommand& s = c.sketch;
    const std::string& cmd = w[0];
    const size_t n = w.size() - 1;
    auto arity = [&](size_t lo, size_t hi, const char* usage) {
        if (n < lo || n > hi)
            p.fail("'" + cmd + "' takes " + usage + " (got " + std::to_string(n) + " argument(s))");
    };
    auto numbersFrom = [&](size_t at, const char* what) {
        for (size_t i = at; i < w.size(); ++i)
            s.numbers.push_back(p.number(w[i], what));
    };
    if (cmd == "page") {
        arity(1, 2, "NAME [GROUP]");
        s.verb = V::Page;
        s.name = w[1];
        if (n == 2) s.group = w[2];
    } else if (cmd == "mode") {
        arity(1, 1, "draft or cleanup");
        s.verb = V::Mode;
        if (w[1] != "draft" && w[1] != "cleanup")
            p.fail("unknown sketch mode '" + w[1] + "' (use draft or cleanup)");
        s.flag = w[1] == "cleanup";
    } else if (cmd == "kind") {
        arity(1, 1, "line or curve");
        s.verb = V::Kind;
        if (w[1] != "line" && w[1] != "curve")
            p.fail("unknown stroke kind '" + w[1] + "' (use line or curve)");
        s.flag = w[1] == "line";
    } else if (cmd == "pen") {
        if (n < 1) arity(1, 1u << 30, "samples X,Y[,PRESSURE[,TIME]] ...");
        s.verb = V::Pen;
        for (size_t i = 1; i < w.size(); ++i) {
            const std::vector<double> v = p.tuple(w[i], 2, 4, "a pen sample");
            PenPoint q{v[0], v[1], std::nullopt, std::nullopt};
            if (v.size() > 2) {
                if (v[2] < 0 || v[2] > 1) p.fail("pen pressure '" + w[i] + "' outside 0..1");
                q.pressure = v[2];
            }
            if (v.size() > 3) q.time = v[3];
            if (!s.pen.empty() && q.pressure.has_value() != s.pen[0].pressure.has_value())
                p.fail("pen sample '" + w[i] +
                       "': give a pressure for every sample of a stroke or for none");
            if (!s.pen.empty() && q.time.has_value() != s.pen[0].time.has_value())
                p.fail("pen sample '" + w[i] +
                       "': give a time for every sample of a stroke or for none");
            if (q.time && !s.pen.empty() && *q.time < *s.pen.back().time)
                p.fail("pen sample '" + w[i] + "': time goes backwards");
            s.pen.push_back(q);
        }
    } else if (cmd == "endgroup") {
        arity(0, 0, "no arguments");
        s.verb = V::EndGroup;
    } else if (cmd == "tick") {
        arity(1, 1, "a time T in seconds");
        s.verb = V::Tick;
        numbersFrom(1, "the time");
    } else if (cmd == "canvas") {
        if (n < 1) p.fail("'canvas' takes zoom F X Y, pan DX DY or reset");
        if (w[1] == "zoom") {
            arity(4, 4, "zoom F X Y");
            s.verb = V::CanvasZoom;
            numbersFrom(2, "canvas zoom");
            if (!(s.numbers[0] > 0)) p.fail("canvas zoom factor must be positive");
        } else if (w[1] == "pan") {
            arity(3, 3, "pan DX DY");
            s.verb = V::CanvasPan;
            numbersFrom(2, "canvas pan");
        } else if (w[1] == "reset") {
            arity(1, 1, "reset");
            s.verb = V::CanvasReset;
        } else {
            p.fail("unknown canvas operation '" + w[1] + "' (use zoom, pan or reset)");
        }
    } else if (cmd == "select") {
        if (n < 1) p.fail("'select' takes IDs, none, lasso X,Y X,Y X,Y ... or near X Y TOL");
        if (w[1] == "lasso") {
            if (n < 4) p.fail("'select lasso' takes at least three points X,Y");
            s.verb = V::SelectLasso;
            for (size_t i = 2; i < w.size(); ++i)
                for (double v : p.tuple(w[i], 2, 2, "a lasso point"))
                    s.numbers.push_back(v);
        } else if (w[1] == "near") {
            arity(4, 4, "near X Y TOL");
            s.verb = V::SelectNear;
            numbersFrom(2, "select near");
            if (!(s.numbers[2] > 0)) p.fail("select near: tolerance must be positive");
        } else {
            s.verb = V::Select;
            if (!(n == 1 && w[1] == "none"))
                for (size_t i = 1; i < w.size(); ++i)
                    s.ids.push_back(p.integer(w[i], "a stroke id"));
        }
    } else if (cmd == "move") {
        arity(2, 2, "DX DY");
        s.verb = V::Move;
        numbersFrom(1, "the move");
    } else if (cmd == "scale") {
        arity(1, 1, "a factor F");
        s.verb = V::Scale;
        numbersFrom(1, "the scale factor");
        if (!(s.numbers[0] > 0)) p.fail("scale factor must be positive");
    } else if (cmd == "delete") {
        arity(0, 0, "no arguments");
        s.verb = V::Delete;
    } else if (cmd == "role") {
        arity(2, 3, "ROLE stroke ID, ROLE curve ID or ROLE last");
        s.verb = V::Role;
        bool known = false;
        for (const char* r : kRoles)
            known |= w[1] == r;
        if (!known)
            p.fail("unknown role '" + w[1] +
                   "' (use outline, surface-x, surface-y, surface-z, sweep-section, sweep-path, "
                   "cut, extrude or none)");
        s.name = w[1];
        if (w[2] == "last") {
            arity(2, 2, "ROLE last");
            s.target = SketchCommand::Target::Last;
        } else if (w[2] == "stroke" || w[2] == "curve") {
            arity(3, 3, "ROLE stroke ID or ROLE curve ID");
            s.target =
                w[2] == "stroke" ? SketchCommand::Target::Stroke : SketchCommand::Target::Curve;
            s.ids.push_back(p.integer(w[3], "the id"));
        } else {
            p.fail("role target '" + w[2] + "' (use stroke ID, curve ID or last)");
        }
    } else if (cmd == "reuse") {
        arity(1, 1, "a stroke id");
        s.verb = V::Reuse;
        s.ids.push_back(p.integer(w[1], "the stroke id"));
    } else if (cmd == "model-line") {
        if (n < 3) p.fail("'model-line' takes W H X,Y [X,Y ...] (view size, then pixels)");
        s.verb = V::ModelLine;
        for (size_t i = 1; i <= 2; ++i) {
            const int v = p.integer(w[i], "the model view size");
            if (v < 16 || v > 16384) p.fail("model view size " + w[i] + " outside 16..16384");
            s.numbers.push_back(v);
        }
        for (size_t i = 3; i < w.size(); ++i) {
            const std::vector<double> v = p.tuple(w[i], 2, 2, "a model-line pixel");
            s.pen.push_back(PenPoint{v[0], v[1], std::nullopt, std::nullopt});
        }
    } else if (cmd == "solid") {
        if (n != 1 && n != 3) arity(1, 1, "inflate|three-section|sweep|cut|extrude [level K]");
        s.verb = V::Solid;
        s.name = w[1];
        if (s.name != "inflate" && s.name != "three-section" && s.name != "sweep" &&
            s.name != "cut" && s.name != "extrude")
            p.fail("unknown solid construction '" + s.name +
                   "' (use inflate, three-section, sweep, cut or extrude)");
        if (n == 3) {
            if (w[2] != "level") p.fail("expected 'level K' after the construction");
            s.level = p.integer(w[3], "the level");
            if (s.level < 1 || s.level > 7) p.fail("solid level " + w[3] + " outside 1..7");
        }
    } else {
        return false;
    }
    return true;
}

// import PATH|"PATH" [level K] [units U] [up y|z] [fit MM] [at X Y Z] [repair on|off] [gap MM]
// (docs/playback.md). The path is taken from the raw text so a quoted one may hold spaces.
void parseImport(const std::string& full, const LineParser& p, const std::string& source,
                 ScriptCommand& c) {
    const char* usage =
        "'import' takes PATH [level K] [units mm|cm|m|in|MM] [up y|z] [fit MM] [at X Y Z] "
        "[repair on|off] [gap MM]";
    std::string rest = full.substr(full.find("import") + 6);
    const size_t start = rest.find_first_not_of(" \t");
    if (start == std::string::npos) p.fail(std::string(usage) + " (got no path)");
    rest = rest.substr(start);
    std::string path;
    if (rest[0] == '"') {
        const size_t close = rest.find('"', 1);
        if (close == std::string::npos) p.fail("import: the quoted path has no closing '\"'");
        path = rest.substr(1, close - 1);
        rest = rest.substr(close + 1);
        if (!rest.empty() && !std::isspace(static_cast<unsigned char>(rest[0])))
            p.fail("import: expected a space after the quoted path");
    } else {
        const size_t end = rest.find_first_of(" \t");
        path = rest.substr(0, end);
        rest = end == std::string::npos ? "" : rest.substr(end);
    }
    if (path.empty()) p.fail("import: the path is empty");
    c.kind = ScriptCommand::Kind::Import;
    c.file = path;
    // Relative to the script's folder, so a script and its meshes move together.
    if (c.file.is_relative()) c.file = std::filesystem::path(source).parent_path() / c.file;
    const std::vector<std::string> w = words(rest, p);
    core::ImportOptions& o = c.importOptions;
    std::vector<std::string> given;
    auto once = [&](const std::string& key) {
        if (std::find(given.begin(), given.end(), key) != given.end())
            p.fail("import: '" + key + "' given twice");
        given.push_back(key);
    };
    auto value = [&](size_t i, const char* what) -> const std::string& {
        if (i >= w.size()) p.fail("import: '" + w[i - 1] + "' needs " + what);
        return w[i];
    };
    for (size_t i = 0; i < w.size(); ++i) {
        const std::string& key = w[i];
        if (key == "level") {
            once(key);
            c.value = p.integer(value(++i, "a level 1..7"), "the import level");
            if (c.value < 1 || c.value > 7) p.fail("import level " + w[i] + " outside 1..7");
        } else if (key == "units") {
            once(key);
            try {
                o.mmPerUnit = core::parseImportUnit(value(++i, "mm, cm, m, in or mm per unit"));
            } catch (const std::invalid_argument& e) {
                p.fail(std::string("import: ") + e.what());
            }
        } else if (key == "up") {
            once(key);
            const std::string& v = value(++i, "y or z");
            if (v != "y" && v != "z") p.fail("import: unknown up axis '" + v + "' (use y or z)");
            o.up = v == "y" ? core::UpAxis::Y : core::UpAxis::Z;
        } else if (key == "fit") {
            once(key);
            o.fitMm = p.number(value(++i, "a size in mm"), "the fit size");
            if (!(*o.fitMm > 0) || *o.fitMm > 1e6)
                p.fail("import: fit " + w[i] + " must be a size in mm above 0 and at most 1e6");
        } else if (key == "at") {
            once(key);
            if (i + 3 >= w.size()) p.fail("import: 'at' needs a point X Y Z");
            o.centreAt = p.point(w, i + 1, "the import centre");
            i += 3;
        } else if (key == "gap") {
            once(key);
            o.repairGapMm = p.number(value(++i, "a size in mm"), "the repair gap");
            if (!(o.repairGapMm > 0) || o.repairGapMm > 1e4)
                p.fail("import: gap " + w[i] + " must be a size in mm above 0 and at most 1e4");
        } else if (key == "repair") {
            once(key);
            const std::string& v = value(++i, "on or off");
            if (v != "on" && v != "off") p.fail("import: repair '" + v + "' (use on or off)");
            o.repair = v == "on";
        } else {
            p.fail("import: unknown option '" + key +
                   "' (use level, units, up, fit, at, repair or gap; quote a path with spaces)");
        }
    }
}

}  // namespace

const char* toString(ToolKind tool) {
    switch (tool) {
        case ToolKind::Add:
            return "add";
        case ToolKind::Carve:
            return "carve";
        case ToolKind::Smooth:
            return "smooth";
        case ToolKind::Select:
            break;
    }
    return "select";
}

std::optional<ToolKind> toolKindNamed(std::string_view name) {
    for (ToolKind t : {ToolKind::Add, ToolKind::Carve, ToolKind::Smooth, ToolKind::Select})
        if (name == toString(t)) return t;
    return std::nullopt;
}

std::optional<core::MirrorAxis> mirrorAxisNamed(std::string_view name) {
    for (core::MirrorAxis a :
         {core::MirrorAxis::None, core::MirrorAxis::X, core::MirrorAxis::Y, core::MirrorAxis::Z})
        if (name == core::toString(a)) return a;
    return std::nullopt;
}

Script parseScript(std::string_view text, const std::string& source) {
    Script script;
    script.source = source;
    // Editors on Windows start UTF-8 files with a byte order mark: not part of the first command.
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
    if (const auto at = core::firstBinaryByte(text)) {
        const size_t line = 1 + size_t(std::count(text.begin(), text.begin() + long(*at), '\n'));
        throw ScriptError(source + ":" + std::to_string(line) +
                          ": not a playback script: binary data (byte " + std::to_string(*at) +
                          " is " + core::printableText(text.substr(*at, 1)) +
                          "; docs/playback.md)");
    }
    // Line ends: LF, CRLF, and a lone CR (classic Mac OS, some exporters): as one line, a
    // file of lone CRs was a single line, all of it a comment when it began with one (found by
    // QA: the whole snowman dropped, exit 0).
    std::string lines(text);
    if (lines.find('\r') != std::string::npos) {
        std::string unified;
        unified.reserve(lines.size());
        for (size_t i = 0; i < lines.size(); ++i) {
            if (lines[i] != '\r') {
                unified += lines[i];
            } else if (i + 1 == lines.size() || lines[i + 1] != '\n') {
                unified += '\n';
            }
        }
        lines = std::move(unified);
    }
    std::istringstream in{std::move(lines)};
    std::string raw;
    int lineNo = 0;
    // A command may continue over following lines that end the previous one with '\'.
    std::string pending;
    int pendingLine = 0;
    std::vector<std::pair<int, std::string>> parts;  // the pending command's physical lines
    auto handle = [&](const std::string& full, int startLine,
                      const std::vector<std::pair<int, std::string>>* lines = nullptr) {
        LineParser p(source, startLine, lines);
        const std::vector<std::string> w = words(full, p);
        if (w.empty()) return;
        ScriptCommand c;
        c.line = startLine;
        const std::string& cmd = w[0];
        auto arity = [&](size_t lo, size_t hi, const char* usage) {
            if (w.size() - 1 < lo || w.size() - 1 > hi)
                p.fail("'" + cmd + "' takes " + usage + " (got " + std::to_string(w.size() - 1) +
                       " argument(s))");
        };
        if (cmd == "tool") {
            arity(1, 1, "one of add, carve, smooth, select");
            c.kind = ScriptCommand::Kind::Tool;
            if (const auto t = toolKindNamed(w[1]))
                c.tool = *t;
            else
                p.fail("unknown tool '" + w[1] + "' (use add, carve, smooth or select)");
        } else if (cmd == "mirror") {
            arity(1, 1, "one of x, y, z, off");
            c.kind = ScriptCommand::Kind::Mirror;
            if (const auto a = mirrorAxisNamed(w[1]))
                c.mirror = *a;
            else
                p.fail("unknown mirror plane '" + w[1] + "' (use x, y, z or off)");
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
            // Refused when the script is read, not after the stroke was sculpted (found by
            // QA: a project's journal refused it then, and the rest of the run was lost).
            if (const size_t n = (w.size() - 1) / 3; n > core::kMaxStrokeSamples)
                p.fail("a stroke of " + std::to_string(n) + " points; a stroke may hold at most " +
                       std::to_string(core::kMaxStrokeSamples) + " (split it into strokes)");
            for (size_t i = 1; i < w.size(); i += 3)
                c.points.push_back(p.point(w, i, "a stroke point"));
        } else if (cmd == "probe") {
            arity(3, 3, "a point x y z");
            c.kind = ScriptCommand::Kind::Probe;
            c.point = p.point(w, 1, "the probe point");
        } else if (cmd == "expect") {
            if (w.size() != 5) arity(4, 4, "inside or outside, then a point x y z");
            c.kind = ScriptCommand::Kind::Expect;
            if (w[1] == "inside")
                c.expectInside = true;
            else if (w[1] == "outside")
                c.expectInside = false;
            else
                p.fail("unknown expectation '" + w[1] + "' (use inside or outside)");
            c.point = p.point(w, 2, "the expected point");
        } else if (cmd == "import") {
            parseImport(full, p, source, c);
        } else if (parseSketch(w, p, c)) {
            c.kind = ScriptCommand::Kind::Sketch;
        } else if (cmd == "undo" || cmd == "redo" || cmd == "save") {
            arity(0, 0, "no arguments");
            c.kind = cmd == "undo"   ? ScriptCommand::Kind::Undo
                     : cmd == "redo" ? ScriptCommand::Kind::Redo
                                     : ScriptCommand::Kind::Save;
        } else {
            p.fail(
                "unknown command '" + cmd +
                "' (commands: tool, size, zoom, object, space, stroke, mirror, import, undo, redo, "
                "save, probe, expect; "
                "sketch: page, mode, kind, pen, endgroup, tick, canvas, select, move, scale, "
                "delete, role, reuse, solid, model-line)");
        }
        script.commands.push_back(std::move(c));
    };
    while (std::getline(in, raw)) {
        ++lineNo;
        const size_t hash = raw.find('#');
        // A comment line inside a continued command is skipped, so a long stroke can carry
        // notes between its points (it ended the command, which then ran cut short).
        if (!pending.empty() && raw.find_first_not_of(" \t") == hash && hash != std::string::npos)
            continue;
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
        parts.emplace_back(lineNo, line);
        if (!continues) {
            handle(pending, pendingLine, &parts);
            pending.clear();
            parts.clear();
        }
    }
    if (!pending.empty())
        throw ScriptError(source + ":" + std::to_string(pendingLine) +
                          ": the command continued with '\\' never ends");
    return script;
}

Script loadScript(const std::filesystem::path& path) {
    // An ifstream opens a folder and reads nothing from it: a script of no commands.
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw ScriptError(path.string() + ": cannot open script: it is a folder");
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        // The whole file: no ":0" line number, and the OS's reason.
        const int why = errno;
        throw ScriptError(path.string() + ": cannot open script: " + std::strerror(why));
    }
    std::ostringstream s;
    s << in.rdbuf();
    Script script = parseScript(s.str(), path.string());
    // A mesh file missing or unreadable is found now, not after every line before it has run
    // (found by QA: 408 lines, then the error).
    for (const ScriptCommand& c : script.commands) {
        if (c.kind != ScriptCommand::Kind::Import) continue;
        if (std::filesystem::is_directory(c.file, ec))
            throw ScriptError(path.string() + ":" + std::to_string(c.line) + ": import " +
                              c.file.string() + ": it is a folder");
        if (!std::ifstream(c.file, std::ios::binary)) {
            const int why = errno;
            throw ScriptError(path.string() + ":" + std::to_string(c.line) + ": import " +
                              c.file.string() + ": cannot read: " + std::strerror(why));
        }
    }
    return script;
}

}  // namespace vsculpt::studio
