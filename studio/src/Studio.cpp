// SPDX-License-Identifier: MIT
#include "vsculpt/studio/Studio.h"

#include "vsculpt/studio/SketchSolids.h"

#include "vsculpt/studio/ImportInBackground.h"
#include "vsculpt/studio/SketchFileWriter.h"

#include "vsculpt/core/InvalidJson.h"
#include "vsculpt/core/JsonNesting.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/WriteFileAtomically.h"

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <set>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace vsculpt::studio {

namespace {}  // namespace

studio::SketchParams recommendedSketchParams() {
    studio::SketchParams p;
    p.cleanup.featureChordRatio = 0.05;
    p.cleanup.lineRunningMean = true;
    return p;
}

Studio::Studio(const core::SculptConfig& cfg, const studio::SketchParams& params)
    : Studio(std::make_unique<Session>(cfg), params) {}

Studio::Studio(std::unique_ptr<Session> session, const studio::SketchParams& params)
    : mSession(std::move(session)), mDocument(params) {
    if (!mSession) throw std::logic_error("Studio needs a session");
    mSculptSteps = mSession->history().done().size();
    // Sculpt steps made before the studio existed are undone in their own order first, and
    // what was undone before (a recovered journal ending in undos) can still be redone.
    for (size_t i = 0; i < mSculptSteps; ++i)
        mDone.push_back(Step{false, 0});
    for (size_t i = 0; i < mSession->history().undone().size(); ++i)
        mUndone.push_back(Step{false, 0});
    mPlanes.assign(mDocument.pageCount(), SketchPlane::Front);
    if (!mSession->projectDir()) return;
    mFile = *mSession->projectDir() / "sketch.json";
    if (!mSession->readOnly()) mSketchWriter = std::make_unique<SketchFileWriter>(*mFile);
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(*mFile, ec))) return;
    const std::vector<Step> sculptDone = mDone, sculptUndone = mUndone;
    try {
        loadSketchFile();
    } catch (const std::invalid_argument& e) {
        openWithoutSketchFile(e.what(), sculptDone, sculptUndone);
    }
}

void Studio::openWithoutSketchFile(const std::string& why, std::vector<Step> sculptDone,
                                   std::vector<Step> sculptUndone) {
    // The sculpture, its snapshot and journal are intact: a damaged sketch file costs the
    // sketch pages, never the project. Kept byte for byte under another name first, so the
    // next sketch write (a new, empty file) cannot replace it.
    std::string kept;
    if (mSession->readOnly()) {
        kept = "read-only, so the file is left as it is";
    } else {
        try {
            kept = "the file is kept as " + core::setAsideAsDamaged(*mFile, true).string();
        } catch (const core::FileWriteError& e) {
            throw std::invalid_argument(why + " (and it could not be set aside: " + e.what() + ")");
        }
    }
    mDocument = studio::SketchDocument(mDocument.params());
    mPlanes.assign(mDocument.pageCount(), SketchPlane::Front);
    mSurfaceLines.clear();
    mUndoneSurfaceLines.clear();
    mBuilt.clear();  // built in another timeline
    mDone = std::move(sculptDone);
    mUndone = std::move(sculptUndone);
    mWrittenDone.clear();
    mWrittenUndone.clear();
    mSculptSteps = mSession->history().done().size();
    mSession->addRecoveryWarning(why + "; the project opens with empty sketch pages (" + kept +
                                 ")");
}

Studio::~Studio() = default;

std::unique_ptr<Studio> Studio::openProject(const std::filesystem::path& dir,
                                            const core::SculptConfig& cfg, ProjectMode mode,
                                            const studio::SketchParams& params) {
    return std::make_unique<Studio>(Session::openProject(dir, cfg, mode), params);
}

Studio::ReconciledTimeline Studio::reconciledTimeline(std::vector<Step> done,
                                                      std::vector<Step> undone, size_t sculptDone,
                                                      size_t sculptUndone) {
    // The journal may hold sculpt steps the file has not seen (a crash between the two
    // writes, or steps after which the file was not rewritten), or fewer: reconcile by the
    // sculpt step counts, keeping the order known. Redo steps are kept when the session can
    // still redo them.
    auto reconcile = [](std::vector<Step>& steps, size_t actual) {
        size_t sculpt = 0;
        for (const Step& s : steps)
            sculpt += s.sculpt();
        bool changed = false;
        while (sculpt > actual) {
            for (auto it = steps.rbegin(); it != steps.rend(); ++it)
                if (it->sculpt()) {
                    steps.erase(std::next(it).base());
                    break;
                }
            --sculpt;
            changed = true;
        }
        for (; sculpt < actual; ++sculpt, changed = true)
            steps.push_back(Step{false, 0});
        return changed;
    };
    ReconciledTimeline out;
    const bool doneChanged = reconcile(done, sculptDone);
    if (doneChanged) {
        // The done steps changed: what the file called redo no longer follows them.
        undone.clear();
        out.undoneSurfaceLinesKept = false;
    }
    size_t sculptRedo = 0;
    for (const Step& s : undone)
        sculptRedo += s.sculpt();
    // With the done steps as the file has them, a session that can redo more sculpt steps
    // than the file's redo list holds has redo steps a later sketch step took off the
    // timeline (a new step clears what could be redone; the session's own list is cleared
    // only by its next stroke): they are not offered again.
    if ((doneChanged || sculptUndone <= sculptRedo) && reconcile(undone, sculptUndone)) {
        // Sculpt redo steps the file did not know of come first to be redone.
        std::vector<Step> sculptOnly;
        for (const Step& s : undone)
            if (s.sculpt()) sculptOnly.push_back(s);
        if (sculptOnly.size() != undone.size()) {
            undone = sculptOnly;
            out.undoneSurfaceLinesKept = false;
        }
    }
    out.done = std::move(done);
    out.undone = std::move(undone);
    return out;
}

void Studio::loadSketchFile() {
    const studio::SketchParams params = mDocument.params();
    std::string text;
    try {
        text = core::readProjectFile(*mFile);
    } catch (const core::ProjectError& e) {
        throw std::invalid_argument(e.what());  // damaged as far as opening is concerned
    }
    const std::string where = mFile->string() + ": ";
    if (const auto deep = core::jsonNestingBeyond(text))
        throw std::invalid_argument(mFile->string() + ":" + *deep);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw std::invalid_argument(core::invalidJsonMessage(mFile->string(), text, e));
    }
    if (!j.is_object() || !j.contains("format") || j["format"] != "vsculpt-studio")
        throw std::invalid_argument(where + "format: expected \"vsculpt-studio\"");
    if (!j.contains("version") || j["version"] != 1)
        throw std::invalid_argument(where + "version: expected 1");
    // Optional lists: absent is empty, anything but a list is refused by name.
    auto list = [&](const char* key) {
        if (!j.contains(key)) return nlohmann::json::array();
        if (!j[key].is_array()) throw std::invalid_argument(where + key + ": expected a list");
        return j[key];
    };
    if (!j.contains("document") || !j["document"].is_object())
        throw std::invalid_argument(where + "document: missing");
    try {
        mDocument = studio::SketchDocument::fromJson(j["document"].dump(), params);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + "document." + e.what());
    }
    mPlanes.assign(mDocument.pageCount(), SketchPlane::Front);
    const nlohmann::json planes = list("planes");
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
        const nlohmann::json a = list(key);
        for (size_t i = 0; i < a.size(); ++i) {
            const std::string at = where + key + "[" + std::to_string(i) + "]";
            if (!a[i].is_object() || !a[i].contains("sketch") || !a[i]["sketch"].is_boolean())
                throw std::invalid_argument(at + ".sketch: expected true or false");
            auto count = [&](const char* field) {
                if (!a[i].contains(field)) return size_t(0);
                if (!a[i][field].is_number_unsigned())
                    throw std::invalid_argument(at + "." + field + ": expected a count");
                return a[i][field].get<size_t>();
            };
            Step s;
            s.sketch = a[i]["sketch"].get<bool>();
            s.page = count("page");
            s.surfaceLines = count("surface_lines");
            if (s.page >= mDocument.pageCount())
                throw std::invalid_argument(at + ".page: no such page");
            out.push_back(s);
        }
        return out;
    };
    auto lines = [&](const char* key) {
        std::vector<std::vector<core::Vec3>> out;
        const nlohmann::json a = list(key);
        for (size_t i = 0; i < a.size(); ++i) {
            if (!a[i].is_array())
                throw std::invalid_argument(where + key + "[" + std::to_string(i) +
                                            "]: expected a list of points");
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
    mBuilt.clear();  // built in another timeline
    mDone = steps("timeline");
    mUndone = steps("redo");
    // The timeline must be what undo and redo can walk: its steps' lines add up to the lines
    // kept (counted without overflow: 2^63 twice once passed as 0), and no page has more
    // sketch steps than actions its log can undo or redo (a page may keep redo actions the
    // timeline dropped when a later step was taken elsewhere).
    auto agree = [&](const std::vector<Step>& steps, size_t lineCount, const char* key,
                     const char* linesKey, size_t (studio::SketchPage::*actions)() const,
                     const char* verb) {
        size_t lines = 0;
        std::vector<size_t> perPage(mDocument.pageCount(), 0);
        for (const Step& s : steps) {
            if (s.surfaceLines > lineCount - lines)
                throw std::invalid_argument(where + linesKey + ": fewer lines than the " + key +
                                            "'s steps hold");
            lines += s.surfaceLines;
            if (s.sketch) ++perPage[s.page];
        }
        if (lines != lineCount)
            throw std::invalid_argument(where + linesKey + ": more lines than the " + key +
                                        "'s steps hold");
        for (size_t p = 0; p < perPage.size(); ++p)
            if (perPage[p] > (mDocument.page(p).*actions)())
                throw std::invalid_argument(
                    where + key + ": " + std::to_string(perPage[p]) + " sketch step(s) on page " +
                    std::to_string(p) + ", whose log holds " +
                    std::to_string((mDocument.page(p).*actions)()) + " action(s) to " + verb);
    };
    agree(mDone, mSurfaceLines.size(), "timeline", "surface_lines", &studio::SketchPage::undoCount,
          "undo");
    agree(mUndone, mUndoneSurfaceLines.size(), "redo", "redo_surface_lines",
          &studio::SketchPage::redoCount, "redo");
    mWrittenDone = mDone;
    mWrittenUndone = mUndone;
    const ReconciledTimeline t = reconciledTimeline(
        mDone, mUndone, mSession->history().done().size(), mSession->history().undone().size());
    mBuilt.clear();  // built in another timeline
    mDone = t.done;
    mUndone = t.undone;
    if (!t.undoneSurfaceLinesKept) mUndoneSurfaceLines.clear();
    mSculptSteps = mSession->history().done().size();
}

SketchPlane Studio::plane(size_t pageIndex) const {
    return pageIndex < mPlanes.size() ? mPlanes[pageIndex] : SketchPlane::Front;
}

void Studio::setPlane(size_t pageIndex, SketchPlane plane) {
    if (pageIndex >= mDocument.pageCount()) throw std::out_of_range("no such sketch page");
    mPlanes.resize(mDocument.pageCount(), SketchPlane::Front);
    mPlanes[pageIndex] = plane;
    writeSketchFile();
}

void Studio::push(const Step& step) {
    // What could have been redone is gone, and the solids built in it.
    while (!mBuilt.empty() && mBuilt.back().timelineIndex >= mDone.size())
        mBuilt.pop_back();
    mDone.push_back(step);
    mUndone.clear();
    mUndoneSurfaceLines.clear();
}

size_t Studio::addSurfaceLines(std::vector<std::vector<core::Vec3>> lines) {
    endStroke();
    size_t added = 0;
    for (auto& line : lines) {
        if (line.size() < 2) continue;
        for (const core::Vec3& p : line)
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw std::invalid_argument("surface line point is not finite");
        mSurfaceLines.push_back(std::move(line));
        ++added;
    }
    if (added == 0) return 0;
    push(Step{false, 0, added});
    writeSketchFile();
    return added;
}

// Tool state and sculpting: every call that can end a stroke goes through sculpt(), which
// puts the completed step on the timeline.
void Studio::setTool(ToolKind tool) {
    sculpt([&](Session& s) { s.setTool(tool); });
}
void Studio::setMirror(core::MirrorAxis axis) {
    sculpt([&](Session& s) { s.setMirror(axis); });
}
void Studio::setSize(int level) {
    sculpt([&](Session& s) { s.setSize(level); });
}
void Studio::setZoom(int zoom, const core::Vec3& center) {
    sculpt([&](Session& s) { s.setZoom(zoom, center); });
}
void Studio::setObjectPose(const core::RigidTransform& worldFromObject) {
    mSession->setObjectPose(worldFromObject);
}
void Studio::beginStroke() {
    // Through sculpt(): the stroke before it may be completed first (a step).
    sculpt([](Session& s) { s.beginStroke(); });
}
bool Studio::pollStrokeFinish(bool wait) {
    return sculpt([&](Session& s) { return s.pollStrokeFinish(wait); });
}
void Studio::strokeSample(const core::Vec3& point, bool world) {
    mSession->strokeSample(point, world);
}
void Studio::endStroke() {
    sculpt([](Session& s) { s.endStroke(); });
}
void Studio::stroke(const std::vector<core::Vec3>& points, bool world) {
    sculpt([&](Session& s) { s.stroke(points, world); });
}
int Studio::addSolid(const core::Mesh& solid, int level) {
    return sculpt([&](Session& s) { return s.addSolid(solid, level); });
}

int Studio::importMesh(const std::filesystem::path& file, const core::ImportOptions& options,
                       int level, core::ImportReport* report) {
    endStroke();
    core::ImportReport local;
    core::ImportReport& r = report ? *report : local;
    const core::Mesh solid = core::importMesh(file, options, &r);
    if (level == 0) level = core::importLevelFor(mSession->sculpture().levels(), solid);
    int used = 0;
    try {
        used = addSolid(solid, level);
    } catch (const SessionError& e) {
        throw SessionError(file.string() + ": " + e.what());
    } catch (const std::invalid_argument& e) {
        // A mesh in the wrong units is the usual cause of one too small or too large.
        throw std::invalid_argument(file.string() + ": " + e.what() +
                                    " (check its units: import ... units mm|cm|m|in, or fit MM)");
    }
    tellNotes(r);
    return used;
}

void Studio::tellNotes(const core::ImportReport& report) const {
    for (const std::string& note : report.notes)
        tell(note);
}

void Studio::tell(const std::string& note) const {
    if (mNotice)
        mNotice(note);
    else
        spdlog::warn("{}", note);  // the program's logger (app/Log.h)
}

void Studio::importMeshInBackground(const std::filesystem::path& file,
                                    const core::ImportOptions& options, int level) {
    if (mImport)
        throw SessionError("still importing " + mImport->file().string() +
                           ": import again once it is in");
    core::checkImportFile(file, options);  // a mistyped path is refused at once
    endStroke();
    mImport =
        std::make_unique<ImportInBackground>(file, options, level, mSession->sculpture().clone());
}

std::optional<std::string> Studio::importStatus() const {
    if (!mImport) return std::nullopt;
    char line[64];
    std::snprintf(line, sizeof line, " (%.0f s)...", mImport->secondsSinceStart());
    return "importing " + mImport->file().string() +
           (mImport->phase() == ImportInBackground::Phase::Reading ? ": reading" : ": placing") +
           line;
}

std::optional<std::string> Studio::pollImport(bool wait, bool* failed) {
    if (failed) *failed = false;
    std::erase_if(mEndingImports, [](const auto& i) { return i->ended(); });
    while (mImport && (wait || mImport->done())) {
        // The samples of a stroke in progress are on the sculpture already: the stroke ends
        // before the import is committed, so the copy is compared with all of it.
        if (wait) endStroke();
        if (mSession->inStroke()) return std::nullopt;
        const std::filesystem::path file = mImport->file();
        std::string said;
        bool bad = false, again = false;
        {
            ImportInBackground::Result r = mImport->take();
            // Sculpted meanwhile: the copy's decisions may not hold here. Place again.
            again =
                r.error.empty() && r.placedOnWrites != mSession->sculpture().store().writeCount();
            if (!r.error.empty()) {
                bad = true;
                said = "import failed: " + r.error;
            } else if (!again) {
                try {
                    const int used =
                        sculpt([&](Session& s) { return s.addPlacedSolid(r.level, r.changes); });
                    tellNotes(r.report);
                    char took[64];
                    std::snprintf(took, sizeof took, " in %.1f s", r.seconds);
                    said = "imported " + file.string() + " as clay (level " + std::to_string(used) +
                           ", " + std::to_string(r.report.triangles) + " triangles" + took +
                           "); U undoes it";
                } catch (const std::exception& e) {
                    bad = true;
                    said = "import of " + file.string() + " failed: " + e.what();
                }
            }
        }
        // Only now, with the result freed here, does its thread go on (placing again, or
        // freeing the mesh: milliseconds for a large one) beside the frame: doing both at
        // once, the frame would wait for the allocator's lock of that thread's heap.
        if (again) {
            mImport->placeAgain(mSession->sculpture().clone());
            continue;
        }
        mImport->finish();
        mEndingImports.push_back(std::move(mImport));
        if (failed) *failed = bad;
        return said;
    }
    return std::nullopt;
}

bool Studio::cancelImport() {
    if (!mImport) return false;
    // Its thread ends with the phase under way, seconds for a large scan: the frame does not
    // wait for that (pollImport lets it go once ended, the destructor waits).
    mImport->finish();
    mEndingImports.push_back(std::move(mImport));
    return true;
}

void Studio::save() {
    endStroke();
    mSession->save();
    writeSketchFile();
    waitForSketchFile();  // a save says whether everything is on disk
}

bool Studio::saveInBackground() {
    endStroke();
    if (!mSession->saveInBackground()) return false;
    writeSketchFile();
    return true;
}

std::optional<std::string> Studio::pollSave(bool wait, bool* failed) {
    bool bad = false;
    std::optional<std::string> outcome = mSession->pollSave(wait, &bad);
    if (outcome && mSketchWriter) {
        // The sketch file posted with the save (saveInBackground) is part of it.
        if (wait) mSketchWriter->wait();
        if (const std::string error = mSketchWriter->takeError(); !error.empty()) {
            *outcome += "; the sketch was not saved: " + error;
            bad = true;
        }
    }
    if (failed) *failed = bad;
    return outcome;
}

void Studio::noteSketchStep() {
    push(Step{true, mDocument.currentIndex()});
    writeSketchFile();
}

void Studio::noteSculptSteps() {
    const size_t n = mSession->history().done().size();
    if (n == mSculptSteps) return;
    if (n < mSculptSteps)
        throw std::logic_error("the session undid a step behind the studio's timeline");
    for (; mSculptSteps < n; ++mSculptSteps) {
        push(Step{false, 0});
        // Said, or the brush looks broken (found by QA: sizes 3-4 over a size-5 ridge, size 1
        // over size-2 dabs left the clay bit for bit as it was). Smooth relaxes the weights of
        // sizes up to its own (docs/placement.md).
        const core::StrokeRecord& r = mSession->history().done()[mSculptSteps];
        if (r.op == core::ToolOp::Smooth && !r.solid && r.changes.empty())
            tell("smooth size " + std::to_string(r.level) +
                 " changed nothing here: the clay under it is already smooth at that size, or "
                 "was made with larger sizes (smooth relaxes clay of sizes up to its own)");
    }
    writeSketchFileUnlessJournalTellsIt();
}

void Studio::writeSketchFileUnlessJournalTellsIt() const {
    // Sculpt steps, undos and redos are in the journal; loadSketchFile() reconciles the file's
    // timeline with the journal's step counts (reconciledTimeline). Where that gives the live
    // timeline back the file is left as it is. Rewriting the whole file (the timeline is in
    // it) at every stroke cost the frame a time that grew with the session, 1 ms a stroke
    // after 1 000 strokes and 4 ms after 4 000, and two fsyncs (docs/projects.md).
    if (!mFile || mSession->readOnly()) return;
    const ReconciledTimeline t =
        reconciledTimeline(mWrittenDone, mWrittenUndone, mSession->history().done().size(),
                           mSession->history().undone().size());
    if (t.done != mDone || t.undone != mUndone) writeSketchFile();
}

bool Studio::undo() {
    endStroke();
    if (mDone.empty()) return false;
    const Step s = mDone.back();
    if (s.surfaceLines > 0) {
        for (size_t i = 0; i < s.surfaceLines; ++i) {
            mUndoneSurfaceLines.push_back(std::move(mSurfaceLines.back()));
            mSurfaceLines.pop_back();
        }
    } else if (s.sketch) {
        studio::SketchPage& p = mDocument.page(s.page);
        if (p.penIsDown()) p.cancelStroke();
        mDocument.selectPage(s.page);  // the undone stroke is on show
        if (!p.undo()) throw std::logic_error("sketch timeline and page log disagree");
    } else {
        if (!mSession->undo()) throw std::logic_error("sculpt timeline and history disagree");
        --mSculptSteps;
    }
    mDone.pop_back();
    mUndone.push_back(s);
    if (s.sculpt())
        writeSketchFileUnlessJournalTellsIt();
    else
        writeSketchFile();
    return s.sculpt();
}

bool Studio::redo() {
    endStroke();
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
        if (!mSession->redo()) throw std::logic_error("sculpt timeline and history disagree");
        ++mSculptSteps;
    }
    mUndone.pop_back();
    mDone.push_back(s);
    if (s.sculpt())
        writeSketchFileUnlessJournalTellsIt();
    else
        writeSketchFile();
    return s.sculpt();
}

core::Vec3 Studio::toObject(size_t pageIndex, const glm::dvec2& c) const {
    return sketch::canvasToObject(plane(pageIndex), c);
}

std::vector<std::vector<core::Vec3>> Studio::curvesInObjectSpace() const {
    std::vector<std::vector<core::Vec3>> out;
    for (size_t i = 0; i < mDocument.pageCount(); ++i) {
        const studio::SketchPage& p = mDocument.page(i);
        auto add = [&](const sketch::Polyline2& pts, bool closed) {
            if (pts.size() < 2) return;
            std::vector<core::Vec3> c;
            for (const glm::dvec2& q : pts)
                c.push_back(toObject(i, q));
            if (closed && pts.front() != pts.back()) c.push_back(c.front());
            out.push_back(std::move(c));
        };
        // The clean curves, and the strokes no clean curve was made of (found by QA: a clean-up
        // group's raw strokes were exported beside its curve).
        const studio::PageContent content = p.content();
        std::set<int> consumed;
        for (const auto& c : content.curves) {
            consumed.insert(c.strokes.begin(), c.strokes.end());
            add(c.samples, c.closed);
        }
        for (const auto& s : content.strokes)
            if (!consumed.count(s.id)) add(s.points, false);
    }
    out.insert(out.end(), mSurfaceLines.begin(), mSurfaceLines.end());
    return out;
}

namespace {

// The sketch library's messages name the function that refused ("buildSketchSolid: Teddy:
// outline encloses zero area"): for the designer, only the reason (found by QA).
std::string withoutFunctionNames(const std::string& message) {
    auto isFunctionName = [](const std::string& word) {
        if (word == "Teddy" || word.empty()) return true;
        bool lower = false, inner = false;
        for (size_t i = 0; i < word.size(); ++i) {
            const char c = word[i];
            if (!std::isalpha(static_cast<unsigned char>(c))) return false;
            if (std::islower(static_cast<unsigned char>(c))) lower = true;
            if (i > 0 && lower && std::isupper(static_cast<unsigned char>(c))) inner = true;
        }
        return inner;  // camelCase or PascalCase: an identifier, not a word
    };
    std::vector<std::string> parts;
    std::string rest = message;
    for (size_t at; (at = rest.find(": ")) != std::string::npos; rest = rest.substr(at + 2))
        if (const std::string head = rest.substr(0, at); !isFunctionName(head))
            parts.push_back(head);
    parts.push_back(rest);
    std::string out;
    for (size_t i = 0; i < parts.size(); ++i) {
        // "outline: outline self-intersects": the role said twice.
        if (i + 1 < parts.size() && parts[i + 1].rfind(parts[i] + " ", 0) == 0) continue;
        out += (out.empty() ? "" : ": ") + parts[i];
    }
    return out;
}

// "inflate: " + why, unless why already starts with the construction's name.
std::string refusal(sketch::SolidConstruction construction, const std::string& message) {
    const std::string name = sketch::constructionName(construction);
    const std::string why = withoutFunctionNames(message);
    return why.rfind(name + " ", 0) == 0 ? why : name + ": " + why;
}

}  // namespace

int Studio::buildSolid(sketch::SolidConstruction construction, int level) {
    using C = sketch::SolidConstruction;
    endStroke();
    std::vector<PolylineRef> sources;
    const sketch::SketchSolidInput input = sketchSolidInput(
        construction, mDocument, mDocument.currentIndex(), mPlanes,
        lastSolid() ? std::optional<sketch::PolyMesh>(lastSolid()->polyMesh) : std::nullopt,
        &sources);
    sketch::SketchSolid built;
    try {
        built = sketch::buildSketchSolid(input);
    } catch (const std::logic_error& e) {
        if (!dynamic_cast<const std::invalid_argument*>(&e)) throw;  // a broken invariant
        throw std::invalid_argument(refusal(construction, e.what()));
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(refusal(construction, e.what()));
    }
    // Regenerating (the same construction from the same lines, edited), cutting or extruding
    // the last solid while it is still the last sculpt step replaces it instead of piling a
    // second solid onto it. The same construction from other lines (a head's outline after a
    // body's) is another solid.
    const bool changesLast = construction == C::Cut || construction == C::Extrude;
    bool replace = false;
    const BuiltSolid* last = currentSolid();
    if (last && mDone[last->timelineIndex].sculpt() &&
        (changesLast || (construction == last->construction && sources == last->sources))) {
        replace = true;
        for (size_t i = last->timelineIndex + 1; i < mDone.size(); ++i)
            if (mDone[i].sculpt()) replace = false;
    }
    // A cut that cannot replace the solid it cuts (sculpted on since, or no solid built this
    // session) would add its kept part inside the clay there: a step that changes nothing
    // (found by QA). Refused, saying why.
    if (construction == C::Cut && !replace)
        throw std::invalid_argument(
            "cut: it changes the last solid built while that is still the last sculpt step; the "
            "clay has been sculpted since (or no solid was built in this session): undo back to "
            "the solid, or carve with the tool");
    const size_t before = mSession->history().done().size();
    const int used =
        sculpt([&](Session& s) { return s.addSolid(toMesh(built.triangles), level, replace); });
    if (mSession->history().done().size() > before) {
        // A cut or an extrusion changes the last solid: built again from its own lines, that
        // solid is still the one regenerated.
        BuiltSolid b = changesLast && last ? BuiltSolid{last->construction, last->sources, 0, {}}
                                           : BuiltSolid{construction, std::move(sources), 0, {}};
        b.timelineIndex = mDone.size() - 1;
        b.solid = std::make_shared<const sketch::SketchSolid>(std::move(built));
        mBuilt.push_back(std::move(b));
    }
    return used;
}

bool Studio::apply(const ScriptCommand& c) {
    using K = ScriptCommand::Kind;
    switch (c.kind) {
        case K::Undo:
        case K::Redo: {
            // A script's undo or redo with nothing left is said, once (found by QA: 5 000
            // undos past the start went by in silence).
            // Once for a run of them: a step undone or redone in between says it again.
            const bool isUndo = c.kind == K::Undo;
            bool& said = isUndo ? mSaidNothingToUndo : mSaidNothingToRedo;
            if (isUndo ? !mDone.empty() : !mUndone.empty()) {
                said = false;
                return isUndo ? undo() : redo();  // whether the sculpture changed
            }
            if (!said)
                tell("line " + std::to_string(c.line) + ": " + (isUndo ? "undo" : "redo") +
                     ": nothing left to " + (isUndo ? "undo" : "redo") +
                     " (ignored, as are more in a row)");
            said = true;
            return false;
        }
        case K::Sketch:
            if (c.sketch.verb == SketchCommand::Verb::Solid) {
                buildSolid(constructionFromName(c.sketch.name), c.sketch.level);
                return true;
            }
            applySketch(c);
            return false;
        case K::Save:
            // Said, not skipped in silence (found by QA): the test engineer expects a file.
            if (!mSession->projectDir())
                tell("line " + std::to_string(c.line) +
                     ": save: this session has no project (--project DIR): nothing saved");
            save();
            return false;
        case K::Import: {
            // Clay where there already is clay adds nothing, and no step.
            const size_t before = mDone.size();
            importMesh(c.file, c.importOptions, c.value);
            return mDone.size() > before;
        }
        default:
            return sculpt([&](Session& s) { return s.apply(c); });
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
            writeSketchFile();
            return;
        }
        case V::Mode:
            page().setMode(s.flag ? studio::SketchMode::Cleanup : studio::SketchMode::Draft);
            return;
        case V::Kind:
            page().setKind(s.flag ? sketch::StrokeKind::Line : sketch::StrokeKind::Curve);
            return;
        case V::Pen: {
            // Script positions are canvas mm, so a script draws the same whatever the view (the
            // window centres its canvas). The pen goes through an identity view, bit for bit:
            // through the window's view and back the samples moved by 1e-14 mm, and a solid
            // inflated from them came out different from `play`'s (found by QA).
            // Times: as given, or 10 ms apart, each stroke 0.2 s after the previous one (within
            // the clean-up pause, so scripted overdrawing forms one group until `tick`).
            std::vector<studio::PenSample> samples;
            double t = mClock + 0.2;
            for (const PenPoint& q : s.pen) {
                studio::PenSample ps;
                ps.view = glm::dvec2(q.x, q.y);
                ps.pressure = q.pressure;
                ps.time = q.time.value_or(t);
                t = ps.time + 0.01;
                samples.push_back(ps);
            }
            sketchStep([&](studio::SketchPage& p) {
                const studio::CanvasView shown = p.view();
                p.resetView();
                try {
                    p.penDown(samples.front());
                    for (size_t i = 1; i < samples.size(); ++i)
                        p.penMove(samples[i]);
                } catch (...) {
                    p.cancelStroke();
                    p.setView(shown);
                    throw;
                }
                p.penUp();
                p.setView(shown);
            });
            mClock = samples.back().time;
            return;
        }
        case V::EndGroup:
            sketchStep([](studio::SketchPage& p) { p.endGroup(); });
            return;
        case V::Tick:
            mClock = std::max(mClock, n[0]);
            sketchStep([&](studio::SketchPage& p) { p.advanceTime(n[0]); });
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
            sketchStep([&](studio::SketchPage& p) { p.moveSelection(glm::dvec2(n[0], n[1])); });
            return;
        case V::Scale:
            sketchStep([&](studio::SketchPage& p) { p.scaleSelection(n[0]); });
            return;
        case V::Delete:
            sketchStep([](studio::SketchPage& p) { p.deleteSelection(); });
            return;
        case V::Role: {
            const studio::Role role = roleFromScriptWord(s.name);
            sketchStep([&](studio::SketchPage& p) {
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
            sketchStep([&](studio::SketchPage& p) { p.reuse(s.ids[0]); });
            return;
        case V::Solid:
            buildSolid(constructionFromName(s.name), s.level);
            return;
        case V::ModelLine: {
            std::vector<glm::dvec2> px;
            for (const PenPoint& q : s.pen)
                px.emplace_back(q.x, q.y);
            if (!mProjector)
                throw std::invalid_argument(
                    "model-line needs a view of the model to draw on (vsculpt play, render "
                    "and the windows have one)");
            addSurfaceLines(mProjector(*mSession, px, glm::ivec2(int(n[0]), int(n[1]))));
            return;
        }
    }
}

namespace {

/// What sketch.json holds, copied for the writer's thread.
struct SketchFileState {
    SketchDocument document;
    std::vector<std::string> planes;
    std::vector<Studio::Step> done, undone;
    std::vector<std::vector<core::Vec3>> surfaceLines, undoneSurfaceLines;
};

std::string sketchFileText(const SketchFileState& s) {
    nlohmann::json j;
    j["format"] = "vsculpt-studio";
    j["version"] = 1;
    j["planes"] = s.planes;
    auto steps = [](const std::vector<Studio::Step>& v) {
        nlohmann::json a = nlohmann::json::array();
        for (const Studio::Step& step : v)
            a.push_back({{"sketch", step.sketch},
                         {"page", step.page},
                         {"surface_lines", step.surfaceLines}});
        return a;
    };
    j["timeline"] = steps(s.done);
    j["redo"] = steps(s.undone);
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
    j["surface_lines"] = lines(s.surfaceLines);
    j["redo_surface_lines"] = lines(s.undoneSurfaceLines);
    // The document's own text goes in as it is (one line): parsing it back into this object
    // only to print it again took most of the file's time.
    std::string text = j.dump(1);
    const size_t close = text.rfind('}');
    text.replace(close, 1, ",\n \"document\": " + s.document.toJson() + "\n}\n");
    return text;
}

}  // namespace

std::vector<std::string> Studio::planeNames() const {
    std::vector<std::string> planes;
    for (size_t i = 0; i < mDocument.pageCount(); ++i)
        planes.emplace_back(sketch::sketchPlaneName(plane(i)));
    return planes;
}

void Studio::writeSketchFile() const {
    if (!mFile || mSession->readOnly()) return;
    if (const std::string failed = mSketchWriter->takeError(); !failed.empty() && mNotice)
        mNotice("the sketch was not saved: " + failed);
    auto state = std::make_shared<const SketchFileState>(SketchFileState{
        mDocument, planeNames(), mDone, mUndone, mSurfaceLines, mUndoneSurfaceLines});
    mSketchWriter->post([state] { return sketchFileText(*state); });
    mWrittenDone = mDone;
    mWrittenUndone = mUndone;
}

void Studio::saveCopyTo(const std::filesystem::path& dir) {
    endStroke();
    mSession->saveCopyTo(dir);
    const SketchFileState state{mDocument, planeNames(),  mDone,
                                mUndone,   mSurfaceLines, mUndoneSurfaceLines};
    core::writeFileAtomically(dir / "sketch.json", sketchFileText(state), true);
}

void Studio::waitForSketchFile() const {
    if (!mSketchWriter) return;
    mSketchWriter->wait();
    if (const std::string failed = mSketchWriter->takeError(); !failed.empty())
        throw core::FileWriteError(failed, EIO);
}

}  // namespace vsculpt::studio
