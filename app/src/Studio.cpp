// SPDX-License-Identifier: MIT
#include "vsculpt/app/Studio.h"

#include "vsculpt/app/SketchSolids.h"

#include "vsculpt/render/StereoCamera.h"

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace vsculpt::app {

namespace {

const char* planeName(sketch::SketchPlane p) {
    return p == SketchPlane::Front ? "front" : p == SketchPlane::Side ? "side" : "top";
}

sketch::Role roleFromScript(const std::string& name) {
    using R = sketch::Role;
    static const std::pair<const char*, R> table[] = {{"none", R::None},
                                                      {"outline", R::Outline},
                                                      {"surface-x", R::SurfaceLineX},
                                                      {"surface-y", R::SurfaceLineY},
                                                      {"surface-z", R::SurfaceLineZ},
                                                      {"sweep-section", R::SweepSection},
                                                      {"sweep-path", R::SweepPath},
                                                      {"cut", R::Cut},
                                                      {"extrude", R::Extrude}};
    for (const auto& [n, r] : table)
        if (name == n) return r;
    throw std::invalid_argument("unknown role '" + name + "'");
}

// Writes `text` to `path` atomically: temp file, fsync, rename, fsync of the folder.
void writeAtomically(const std::filesystem::path& path, const std::string& text) {
    const std::filesystem::path tmp = path.string() + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(tmp.string() + ": cannot write: " + std::strerror(errno));
    size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const std::string why = std::strerror(errno);
            ::close(fd);
            throw std::runtime_error(tmp.string() + ": write failed: " + why);
        }
        done += size_t(n);
    }
    const bool synced = ::fsync(fd) == 0;
    ::close(fd);
    if (!synced) throw std::runtime_error(tmp.string() + ": cannot flush: " + std::strerror(errno));
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path.string() + ": cannot replace: " + ec.message());
    const int dir = ::open(path.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
}

}  // namespace

sketch::SketchParams recommendedSketchParams() {
    sketch::SketchParams p;
    p.cleanup.featureChordRatio = 0.05;
    p.cleanup.lineRunningMean = true;
    return p;
}

Studio::Studio(Session& session, const sketch::SketchParams& params)
    : mSession(session), mDocument(params) {
    mSculptSteps = mSession.history().done().size();
    // Sculpt steps made before the studio existed are undone in their own order first.
    for (size_t i = 0; i < mSculptSteps; ++i)
        mDone.push_back(Step{false, 0});
    mPlanes.assign(mDocument.pageCount(), SketchPlane::Front);
    if (!mSession.projectDir()) return;
    mFile = *mSession.projectDir() / "sketch.json";
    if (!std::filesystem::exists(*mFile)) return;
    std::ifstream in(*mFile, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const std::string where = mFile->string() + ": ";
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::exception& e) {
        throw std::invalid_argument(where + "not valid JSON (" + e.what() + ")");
    }
    if (!j.is_object() || j.value("format", "") != "vsculpt-studio")
        throw std::invalid_argument(where + "format: expected \"vsculpt-studio\"");
    if (j.value("version", 0) != 1) throw std::invalid_argument(where + "version: expected 1");
    if (!j.contains("document") || !j["document"].is_object())
        throw std::invalid_argument(where + "document: missing");
    try {
        mDocument = sketch::SketchDocument::fromJson(j["document"].dump(), params);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + "document." + e.what());
    }
    mPlanes.assign(mDocument.pageCount(), SketchPlane::Front);
    const nlohmann::json planes = j.value("planes", nlohmann::json::array());
    for (size_t i = 0; i < planes.size() && i < mPlanes.size(); ++i) {
        const std::string p = planes[i].is_string() ? planes[i].get<std::string>() : "";
        if (p != "front" && p != "side" && p != "top")
            throw std::invalid_argument(where + "planes[" + std::to_string(i) +
                                        "]: expected front, side or top");
        mPlanes[i] = p == "front"  ? SketchPlane::Front
                     : p == "side" ? SketchPlane::Side
                                   : SketchPlane::Top;
    }
    auto steps = [&](const char* key) {
        std::vector<Step> out;
        const nlohmann::json a = j.value(key, nlohmann::json::array());
        for (size_t i = 0; i < a.size(); ++i) {
            const std::string at = where + key + "[" + std::to_string(i) + "]";
            if (!a[i].is_object() || !a[i].contains("sketch") || !a[i]["sketch"].is_boolean())
                throw std::invalid_argument(at + ".sketch: expected true or false");
            Step s;
            s.sketch = a[i]["sketch"].get<bool>();
            s.page = a[i].value("page", size_t(0));
            s.surfaceLines = a[i].value("surface_lines", size_t(0));
            if (s.page >= mDocument.pageCount())
                throw std::invalid_argument(at + ".page: no such page");
            out.push_back(s);
        }
        return out;
    };
    auto lines = [&](const char* key) {
        std::vector<std::vector<core::Vec3>> out;
        const nlohmann::json a = j.value(key, nlohmann::json::array());
        for (size_t i = 0; i < a.size(); ++i) {
            std::vector<core::Vec3> line;
            for (size_t k = 0; k < a[i].size(); ++k) {
                const nlohmann::json& p = a[i][k];
                if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
                    !p[2].is_number())
                    throw std::invalid_argument(where + key + "[" + std::to_string(i) + "][" +
                                                std::to_string(k) + "]: expected [x, y, z]");
                line.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
            }
            out.push_back(std::move(line));
        }
        return out;
    };
    mSurfaceLines = lines("surface_lines");
    mUndoneSurfaceLines = lines("redo_surface_lines");
    mDone = steps("timeline");
    mUndone = steps("redo");
    size_t surfaceDone = 0, surfaceUndone = 0;
    for (const Step& s : mDone)
        surfaceDone += s.surfaceLines;
    for (const Step& s : mUndone)
        surfaceUndone += s.surfaceLines;
    if (surfaceDone != mSurfaceLines.size() || surfaceUndone != mUndoneSurfaceLines.size())
        throw std::invalid_argument(where + "surface_lines: do not match the timeline's steps");
    // The journal may hold sculpt steps the file has not seen (a crash between the two
    // writes), or fewer: reconcile by the sculpt step count, keeping the order known.
    size_t sculpt = 0;
    for (const Step& s : mDone)
        sculpt += s.sculpt();
    const size_t actual = mSession.history().done().size();
    while (sculpt > actual) {
        for (auto it = mDone.rbegin(); it != mDone.rend(); ++it)
            if (it->sculpt()) {
                mDone.erase(std::next(it).base());
                break;
            }
        --sculpt;
        mUndone.clear();
    }
    for (; sculpt < actual; ++sculpt) {
        mDone.push_back(Step{false, 0});
        mUndone.clear();
    }
    mSculptSteps = actual;
}

SketchPlane Studio::plane(size_t pageIndex) const {
    return pageIndex < mPlanes.size() ? mPlanes[pageIndex] : SketchPlane::Front;
}

void Studio::setPlane(size_t pageIndex, SketchPlane plane) {
    if (pageIndex >= mDocument.pageCount()) throw std::out_of_range("no such sketch page");
    mPlanes.resize(mDocument.pageCount(), SketchPlane::Front);
    mPlanes[pageIndex] = plane;
    save();
}

void Studio::push(const Step& step) {
    mDone.push_back(step);
    mUndone.clear();
    mUndoneSurfaceLines.clear();
}

size_t Studio::drawOnModel(const std::vector<glm::dvec2>& strokePx,
                           const render::ProjectionCamera& camera) {
    mSession.endStroke();
    syncSculptSteps();
    const core::Mesh mesh = mSession.view().mesh();
    if (mesh.triangleCount() == 0 || strokePx.empty()) return 0;
    render::StrokeProjectionOptions o;
    // Points about a third of the finest lattice spacing on show apart: smooth at any zoom.
    o.spacingMm = std::max(0.05, mSession.view().region().spacingMm / 3);
    o.maxDepthJumpMm = std::max(o.spacingMm, 10 * mSession.view().region().spacingMm);
    const auto pieces = render::projectStroke(mesh, camera, strokePx, o);
    size_t added = 0;
    for (const auto& piece : pieces) {
        if (piece.size() < 2) continue;
        std::vector<core::Vec3> line;
        for (const render::SurfacePoint& p : piece)
            line.push_back(p.position);
        mSurfaceLines.push_back(std::move(line));
        ++added;
    }
    if (added == 0) return 0;
    push(Step{false, 0, added});
    save();
    return added;
}

render::ProjectionCamera Studio::frontCamera(glm::ivec2 viewportPx) const {
    if (viewportPx.x <= 0 || viewportPx.y <= 0)
        throw std::invalid_argument("model view size must be positive");
    const core::Aabb box = core::meshBounds(mSession.view().mesh());
    if (box.empty()) throw std::invalid_argument("nothing to draw on: the sculpture is empty");
    const core::RigidTransform& pose = mSession.objectPose();
    glm::dmat4 worldFromObject = glm::mat4_cast(pose.rotation);
    worldFromObject[3] = glm::dvec4(pose.translation, 1.0);
    // As the window frames it: the box after the object's pose, seen from the front.
    const glm::dvec3 c = glm::dvec3(worldFromObject * glm::dvec4(0.5 * (box.min + box.max), 1));
    const glm::dvec3 half = 0.5 * (box.max - box.min);
    render::StereoDisplay d;
    const glm::dmat4 head =
        render::frameFromFront(c - half, c + half, double(viewportPx.x) / viewportPx.y, d);
    d.ipdMm = 0;
    return render::ProjectionCamera::fromEye(render::stereoEyes(head, d)[0], worldFromObject,
                                             viewportPx);
}

void Studio::noteSketchStep() {
    push(Step{true, mDocument.currentIndex()});
    save();
}

void Studio::syncSculptSteps() {
    const size_t n = mSession.history().done().size();
    if (n == mSculptSteps) return;
    for (; mSculptSteps < n; ++mSculptSteps)
        push(Step{false, 0});
    // Fewer: undone behind the studio's back; drop that many sculpt steps from the end.
    while (mSculptSteps > n) {
        for (auto it = mDone.rbegin(); it != mDone.rend(); ++it)
            if (it->sculpt()) {
                mDone.erase(std::next(it).base());
                break;
            }
        --mSculptSteps;
    }
    save();
}

bool Studio::undo() {
    mSession.endStroke();
    syncSculptSteps();
    if (mDone.empty()) return false;
    const Step s = mDone.back();
    if (s.surfaceLines > 0) {
        for (size_t i = 0; i < s.surfaceLines; ++i) {
            mUndoneSurfaceLines.push_back(std::move(mSurfaceLines.back()));
            mSurfaceLines.pop_back();
        }
    } else if (s.sketch) {
        sketch::SketchPage& p = mDocument.page(s.page);
        if (p.penIsDown()) p.cancelStroke();
        mDocument.selectPage(s.page);  // the undone stroke is on show
        if (!p.undo()) throw std::logic_error("sketch timeline and page log disagree");
    } else {
        if (!mSession.undo()) throw std::logic_error("sculpt timeline and history disagree");
        --mSculptSteps;
    }
    mDone.pop_back();
    mUndone.push_back(s);
    if (mLastSolid && mLastSolid->timelineIndex >= mDone.size()) mLastSolid.reset();
    save();
    return s.sculpt();
}

bool Studio::redo() {
    mSession.endStroke();
    syncSculptSteps();
    if (mUndone.empty()) return false;
    const Step s = mUndone.back();
    if (s.surfaceLines > 0) {
        for (size_t i = 0; i < s.surfaceLines; ++i) {
            mSurfaceLines.push_back(std::move(mUndoneSurfaceLines.back()));
            mUndoneSurfaceLines.pop_back();
        }
    } else if (s.sketch) {
        mDocument.selectPage(s.page);
        if (!mDocument.page(s.page).redo())
            throw std::logic_error("sketch timeline and page log disagree");
    } else {
        if (!mSession.redo()) throw std::logic_error("sculpt timeline and history disagree");
        ++mSculptSteps;
    }
    mUndone.pop_back();
    mDone.push_back(s);
    save();
    return s.sculpt();
}

core::Vec3 Studio::toObject(size_t pageIndex, const glm::dvec2& c) const {
    return sketch::canvasToObject(plane(pageIndex), c);
}

std::vector<std::vector<core::Vec3>> Studio::curvesInObjectSpace() const {
    std::vector<std::vector<core::Vec3>> out;
    for (size_t i = 0; i < mDocument.pageCount(); ++i) {
        const sketch::SketchPage& p = mDocument.page(i);
        auto add = [&](const sketch::Polyline2& pts, bool closed) {
            if (pts.size() < 2) return;
            std::vector<core::Vec3> c;
            for (const glm::dvec2& q : pts)
                c.push_back(toObject(i, q));
            if (closed && pts.front() != pts.back()) c.push_back(c.front());
            out.push_back(std::move(c));
        };
        for (const sketch::CleanCurve& c : p.cleanCurves())
            add(c.samples, c.closed);
        for (int id : p.liveStrokeIds())
            add(p.strokePoints(id), false);
    }
    out.insert(out.end(), mSurfaceLines.begin(), mSurfaceLines.end());
    return out;
}

int Studio::buildSolid(sketch::SolidConstruction construction, int level) {
    using C = sketch::SolidConstruction;
    mSession.endStroke();
    syncSculptSteps();
    const sketch::SketchSolidInput input = sketchSolidInput(
        construction, mDocument, mDocument.currentIndex(), mPlanes,
        mLastBuilt ? std::optional<sketch::PolyMesh>(mLastBuilt->polyMesh) : std::nullopt);
    sketch::SketchSolid built = sketch::buildSketchSolid(input);
    // Regenerating (the same construction after editing its lines), cutting or extruding the
    // last solid while it is still the last sculpt step replaces it instead of piling a
    // second solid onto it.
    bool replace = false;
    if (mLastSolid && mLastSolid->timelineIndex < mDone.size() &&
        mDone[mLastSolid->timelineIndex].sculpt() &&
        (construction == C::Cut || construction == C::Extrude ||
         construction == mLastSolid->construction)) {
        replace = true;
        for (size_t i = mLastSolid->timelineIndex + 1; i < mDone.size(); ++i)
            if (mDone[i].sculpt()) replace = false;
    }
    const size_t before = mSession.history().done().size();
    const int used = mSession.addSolid(toMesh(built.triangles), level, replace);
    if (mSession.history().done().size() > before) {
        ++mSculptSteps;
        push(Step{false, 0});
        const C kept = (construction == C::Cut || construction == C::Extrude) && mLastSolid
                           ? mLastSolid->construction
                           : construction;
        mLastSolid = BuiltSolid{kept, mDone.size() - 1};
        mLastBuilt = std::move(built);
        save();
    }
    return used;
}

bool Studio::apply(const ScriptCommand& c) {
    using K = ScriptCommand::Kind;
    switch (c.kind) {
        case K::Undo:
            return undo();
        case K::Redo:
            return redo();
        case K::Sketch:
            if (c.sketch.verb == SketchCommand::Verb::Solid) {
                buildSolid(constructionFromName(c.sketch.name), c.sketch.level);
                return true;
            }
            applySketch(c);
            return false;
        default: {
            const bool changed = mSession.apply(c);
            syncSculptSteps();
            if (c.kind == K::Save) save();
            return changed;
        }
    }
}

void Studio::applySketch(const ScriptCommand& c) {
    using V = SketchCommand::Verb;
    const SketchCommand& s = c.sketch;
    const auto& n = s.numbers;
    switch (s.verb) {
        case V::Page: {
            std::optional<size_t> found;
            for (size_t i = 0; i < mDocument.pageCount(); ++i)
                if (mDocument.page(i).name() == s.name) found = i;
            if (found) {
                mDocument.selectPage(*found);
                if (!s.group.empty()) mDocument.setPageGroup(*found, s.group);
            } else {
                mDocument.addPage(s.name, s.group.empty() ? "Sketches" : s.group);
                mPlanes.resize(mDocument.pageCount(), SketchPlane::Front);
            }
            // A page named after a view ("side", "top", "front ...") is drawn on that plane.
            const std::string lower = s.name.substr(0, 5);
            if (lower.rfind("side", 0) == 0)
                setPlane(mDocument.currentIndex(), SketchPlane::Side);
            else if (lower.rfind("top", 0) == 0)
                setPlane(mDocument.currentIndex(), SketchPlane::Top);
            save();
            return;
        }
        case V::Mode:
            page().setMode(s.flag ? sketch::SketchMode::Cleanup : sketch::SketchMode::Draft);
            return;
        case V::Kind:
            page().setKind(s.flag ? sketch::StrokeKind::Line : sketch::StrokeKind::Curve);
            return;
        case V::Pen: {
            // Script positions are canvas mm, so a script draws the same whatever the view (the
            // window centres its canvas); the pen goes through the view as a tablet's would.
            // Times: as given, or 10 ms apart, each stroke 0.2 s after the previous one (within
            // the clean-up pause, so scripted overdrawing forms one group until `tick`).
            std::vector<sketch::PenSample> samples;
            double t = mClock + 0.2;
            for (const PenPoint& q : s.pen) {
                sketch::PenSample ps;
                ps.view = page().view().viewFromCanvas(glm::dvec2(q.x, q.y));
                ps.pressure = q.pressure;
                ps.time = q.time.value_or(t);
                t = ps.time + 0.01;
                samples.push_back(ps);
            }
            sketchStep([&](sketch::SketchPage& p) {
                p.penDown(samples.front());
                try {
                    for (size_t i = 1; i < samples.size(); ++i)
                        p.penMove(samples[i]);
                } catch (...) {
                    p.cancelStroke();
                    throw;
                }
                p.penUp();
            });
            mClock = samples.back().time;
            return;
        }
        case V::EndGroup:
            sketchStep([](sketch::SketchPage& p) { p.endGroup(); });
            return;
        case V::Tick:
            mClock = std::max(mClock, n[0]);
            sketchStep([&](sketch::SketchPage& p) { p.advanceTime(n[0]); });
            return;
        case V::CanvasZoom:
            page().zoomAbout(glm::dvec2(n[1], n[2]), n[0]);
            return;
        case V::CanvasPan:
            page().pan(glm::dvec2(n[0], n[1]));
            return;
        case V::CanvasReset:
            page().resetView();
            return;
        case V::Select:
            if (s.ids.empty())
                page().clearSelection();
            else
                page().select(s.ids);
            return;
        case V::SelectLasso: {
            sketch::Polyline2 poly;
            for (size_t i = 0; i + 1 < n.size(); i += 2)
                poly.push_back(glm::dvec2(n[i], n[i + 1]));
            page().selectLasso(poly);
            return;
        }
        case V::SelectNear:
            page().selectNearest(glm::dvec2(n[0], n[1]), n[2]);
            return;
        case V::Move:
            sketchStep([&](sketch::SketchPage& p) { p.moveSelection(glm::dvec2(n[0], n[1])); });
            return;
        case V::Scale:
            sketchStep([&](sketch::SketchPage& p) { p.scaleSelection(n[0]); });
            return;
        case V::Delete:
            sketchStep([](sketch::SketchPage& p) { p.deleteSelection(); });
            return;
        case V::Role: {
            const sketch::Role role = roleFromScript(s.name);
            sketchStep([&](sketch::SketchPage& p) {
                if (s.target == SketchCommand::Target::Stroke) {
                    p.setStrokeRole(s.ids[0], role);
                } else if (s.target == SketchCommand::Target::Curve) {
                    p.setCurveRole(s.ids[0], role);
                } else {
                    // The last stroke drawn; in clean-up mode the curve it became part of.
                    const std::vector<int> live = p.liveStrokeIds();
                    if (live.empty()) throw std::invalid_argument("role last: no stroke drawn");
                    const int last = live.back();
                    for (const sketch::CleanCurve& cc : p.cleanCurves())
                        for (int sid : cc.strokes)
                            if (sid == last) {
                                p.setCurveRole(cc.id, role);
                                return;
                            }
                    p.setStrokeRole(last, role);
                }
            });
            return;
        }
        case V::Reuse:
            sketchStep([&](sketch::SketchPage& p) { p.reuse(s.ids[0]); });
            return;
        case V::Solid:
            buildSolid(constructionFromName(s.name), s.level);
            return;
        case V::ModelLine: {
            std::vector<glm::dvec2> px;
            for (const PenPoint& q : s.pen)
                px.emplace_back(q.x, q.y);
            drawOnModel(px, frontCamera(glm::ivec2(int(n[0]), int(n[1]))));
            return;
        }
    }
}

void Studio::save() const {
    if (!mFile) return;
    nlohmann::json j;
    j["format"] = "vsculpt-studio";
    j["version"] = 1;
    nlohmann::json planes = nlohmann::json::array();
    for (size_t i = 0; i < mDocument.pageCount(); ++i)
        planes.push_back(planeName(plane(i)));
    j["planes"] = planes;
    auto steps = [](const std::vector<Step>& v) {
        nlohmann::json a = nlohmann::json::array();
        for (const Step& s : v)
            a.push_back(
                {{"sketch", s.sketch}, {"page", s.page}, {"surface_lines", s.surfaceLines}});
        return a;
    };
    j["timeline"] = steps(mDone);
    j["redo"] = steps(mUndone);
    auto lines = [](const std::vector<std::vector<core::Vec3>>& v) {
        nlohmann::json a = nlohmann::json::array();
        for (const auto& line : v) {
            nlohmann::json l = nlohmann::json::array();
            for (const core::Vec3& p : line)
                l.push_back({p.x, p.y, p.z});
            a.push_back(l);
        }
        return a;
    };
    j["surface_lines"] = lines(mSurfaceLines);
    j["redo_surface_lines"] = lines(mUndoneSurfaceLines);
    j["document"] = nlohmann::json::parse(mDocument.toJson());
    writeAtomically(*mFile, j.dump(1) + "\n");
}

}  // namespace vsculpt::app
