// SPDX-License-Identifier: MIT
#include "vsculpt/app/Session.h"

#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/PlaceStroke.h"

#include <chrono>
#include <cmath>

namespace vsculpt::app {

using namespace vsculpt::core;

Session::Session(const SculptConfig& cfg) : Session(cfg, true) {
    rebuildView();
}

Session::Session(const SculptConfig& cfg, bool)
    : mConfig(cfg), mSculpture(std::make_unique<Sculpture>(cfg)) {
    mSize = mConfig.zoom.allowedSizes[0].front();
}

Session::~Session() = default;

std::unique_ptr<Session> Session::openProject(const std::filesystem::path& dir,
                                              const SculptConfig& cfgForNew) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw ProjectError(dir.string() + ": cannot create project folder: " + ec.message());
    const auto snap = snapshotPath(dir);
    std::unique_ptr<Session> s;
    uint64_t lastSeq = 0;
    if (std::filesystem::exists(snap)) {
        SnapshotContents c = readSnapshot(snap);
        SculptConfig cfg;
        try {
            cfg = parseConfig(c.configJson, snap.string() + " (stored config)");
        } catch (const ConfigError& e) {
            throw ProjectError(e.what());
        }
        s.reset(new Session(cfg, true));
        for (const SkeletonEntry& e : c.skeletons)
            s->mSculpture->store().set(e.level, e.coord, e.weight);
        s->mHistory.restore(std::move(c.done), std::move(c.undone));
        lastSeq = c.lastSequence;
    } else {
        s.reset(new Session(cfgForNew, true));
        // A new project starts with a snapshot, so the config travels with it.
        writeSnapshot(snap, configToJson(s->mConfig), 0, *s->mSculpture, s->mHistory);
    }
    s->mProjectDir = dir;
    s->mSequence = lastSeq;
    const JournalContents j = readJournal(journalPath(dir));
    for (const JournalRecord& r : j.records) {
        if (r.sequence <= lastSeq) continue;  // already in the snapshot
        s->applyJournalRecord(r);
        s->mSequence = r.sequence;
        ++s->mRecovered;
    }
    s->mRecoveryWarning = j.warning;
    s->mJournal = std::make_unique<JournalWriter>(journalPath(dir), j.validBytes);
    s->rebuildView();
    return s;
}

void Session::applyJournalRecord(const JournalRecord& r) {
    switch (r.op) {
        case JournalOp::Stroke: {
            StrokeRecord rec;
            rec.op = r.tool;
            rec.level = r.level;
            rec.samples = r.samples;
            applyStroke(*mSculpture, r.tool, r.level, r.samples, &rec.changes);
            mHistory.push(std::move(rec));
            break;
        }
        case JournalOp::Solid: {
            SolidPlacement placed = replaySolid(*mSculpture, r.solidLevel, r.changes);
            StrokeRecord rec;
            rec.solid = true;
            rec.level = placed.level;
            rec.changes = std::move(placed.changes);
            mHistory.push(std::move(rec));
            break;
        }
        case JournalOp::Undo:
            mHistory.undo(*mSculpture);
            break;
        case JournalOp::Redo:
            mHistory.redo(*mSculpture);
            break;
    }
}

void Session::rebuildView() {
    const GridRegion region = zoomRegion(mConfig, mSculpture->levels(), mZoom, mZoomCenter);
    mView =
        std::make_unique<Polygonizer>(*mSculpture, region, mConfig.polygonizer.bisectionTolerance);
    mView->rebuildAll();
}

bool Session::apply(const ScriptCommand& c) {
    using K = ScriptCommand::Kind;
    switch (c.kind) {
        case K::Tool:
            setTool(c.tool);
            return false;
        case K::Size:
            setSize(c.value);
            return false;
        case K::Zoom:
            setZoom(c.value, c.point);
            return false;
        case K::Object:
            setObjectPose(c.pose);
            return false;
        case K::Space:
            mWorldSpace = c.world;
            return false;
        case K::Stroke:
            stroke(c.points, mWorldSpace);
            return true;
        case K::Undo:
            return undo();
        case K::Redo:
            return redo();
        case K::Save:
            save();
            return false;
        case K::Sketch:
            break;
    }
    // Sketch commands need the sketch document: Studio::apply runs them.
    throw SessionError(
        "a sketch command needs the sketch mode (vsculpt play and vsculpt "
        "sketch run them)");
}

void Session::setSize(int level) {
    if (!toolAllowedAtZoom(mConfig, mZoom, level)) {
        std::string allowed;
        for (int k : mConfig.zoom.allowedSizes[mZoom - 1])
            allowed += " " + std::to_string(k);
        throw SessionError("size " + std::to_string(level) + " is not offered at zoom " +
                           std::to_string(mZoom) + " (offered:" + allowed + ")");
    }
    endStroke();
    mSize = level;
}

void Session::setZoom(int zoom, const Vec3& center) {
    if (zoom < 1 || zoom > kZoomLevels) throw SessionError("zoom level outside 1..5");
    endStroke();
    mZoom = zoom;
    mZoomCenter = zoom == 1 ? mConfig.sphereCenterMm : center;
    if (!toolAllowedAtZoom(mConfig, mZoom, mSize)) {
        int best = mConfig.zoom.allowedSizes[mZoom - 1].front();
        for (int k : mConfig.zoom.allowedSizes[mZoom - 1])
            if (std::abs(k - mSize) < std::abs(best - mSize)) best = k;
        mSize = best;
    }
    rebuildView();
}

void Session::setObjectPose(const RigidTransform& worldFromObject) {
    mWorldFromObject = worldFromObject;
}

void Session::journal(const JournalRecord& r) {
    if (mJournal) mJournal->append(r);
}

void Session::beginStroke() {
    if (mStroke) throw SessionError("a stroke is already in progress");
    if (mTool == ToolKind::Select)
        throw SessionError("stroke needs the add or carve tool (the select tool is active)");
    const ToolOp op = mTool == ToolKind::Add ? ToolOp::Add : ToolOp::Carve;
    mStroke = std::make_unique<StrokeBuilder>(*mSculpture, op, mSize);
    mStrokeRecord = StrokeRecord{};
    mStrokeRecord.op = op;
    mStrokeRecord.level = mSize;
}

void Session::strokeSample(const Vec3& p, bool world) {
    if (!mStroke) throw SessionError("no stroke in progress");
    const Vec3 objectPos = world ? mWorldFromObject.inverse().apply(p) : p;
    try {
        const auto t0 = std::chrono::steady_clock::now();
        const EditResult r = mStroke->addSample(objectPos);
        mView->update(r.changedPoints, r.supportMm);
        mSampleMs.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
        mStrokeRecord.samples.push_back(objectPos);
    } catch (...) {
        // A refused sample cancels the whole stroke: no half-applied, unjournaled edit.
        mView->update(revertChanges(*mSculpture, mStroke->changes()));
        mStroke.reset();
        throw;
    }
}

void Session::endStroke() {
    if (!mStroke) return;
    mStrokeRecord.changes = mStroke->takeChanges();
    mStroke.reset();
    // The edit is durable before it counts as done.
    JournalRecord j;
    j.sequence = ++mSequence;
    j.op = JournalOp::Stroke;
    j.tool = mStrokeRecord.op;
    j.level = mStrokeRecord.level;
    j.samples = mStrokeRecord.samples;
    journal(j);
    mHistory.push(std::move(mStrokeRecord));
    mStrokeRecord = StrokeRecord{};
}

void Session::stroke(const std::vector<Vec3>& points, bool world) {
    beginStroke();
    for (const Vec3& p : points)
        strokeSample(p, world);
    endStroke();
}

int Session::addSolid(const Mesh& solid, int level, bool replaceLast) {
    endStroke();
    // Replacing: first take the previous solid's clay away (its changes backwards), then
    // place the new one on what is left; both go into the one step.
    std::vector<SkeletonChange> takeAway;
    Aabb takenBox;
    if (replaceLast) {
        if (!mHistory.canUndo() || !mHistory.done().back().solid)
            throw SessionError("no solid to replace: the last step is not a solid");
        const std::vector<SkeletonChange>& last = mHistory.done().back().changes;
        for (auto it = last.rbegin(); it != last.rend(); ++it)
            takeAway.push_back(SkeletonChange{it->level, it->coord, it->after, it->before});
        takenBox = reapplyChanges(*mSculpture, takeAway);
    }
    SolidPlacement placed;
    try {
        placed = placeSolid(*mSculpture, solid, level);
    } catch (...) {
        revertChanges(*mSculpture, takeAway);
        throw;
    }
    if (!takeAway.empty())
        placed.changes.insert(placed.changes.begin(), takeAway.begin(), takeAway.end());
    if (placed.changes.size() > kMaxJournalSolidChanges) {
        revertChanges(*mSculpture, placed.changes);
        throw SessionError("solid changes " + std::to_string(placed.changes.size()) +
                           " lattice vertices at level " + std::to_string(placed.level) +
                           ", more than one edit can hold; choose a larger level");
    }
    if (placed.changes.empty()) return placed.level;  // already clay everywhere: no step
    if (!takenBox.empty()) mView->update(takenBox);
    mView->update(placed.edit.changedPoints, placed.edit.supportMm);
    JournalRecord j;
    j.sequence = ++mSequence;
    j.op = JournalOp::Solid;
    j.solidLevel = placed.level;
    j.changes = placed.changes;
    try {
        journal(j);
    } catch (...) {
        // Not durable, so not done: no edit the project would lose on reopening.
        mView->update(revertChanges(*mSculpture, placed.changes));
        --mSequence;
        throw;
    }
    const int used = placed.level;
    StrokeRecord rec;
    rec.solid = true;
    rec.level = used;
    rec.changes = std::move(placed.changes);
    mHistory.push(std::move(rec));
    return used;
}

bool Session::undo() {
    endStroke();
    if (!mHistory.canUndo()) return false;
    const Aabb box = mHistory.undo(*mSculpture);
    mView->update(box);
    JournalRecord j;
    j.sequence = ++mSequence;
    j.op = JournalOp::Undo;
    journal(j);
    return true;
}

bool Session::redo() {
    endStroke();
    if (!mHistory.canRedo()) return false;
    const Aabb box = mHistory.redo(*mSculpture);
    mView->update(box);
    JournalRecord j;
    j.sequence = ++mSequence;
    j.op = JournalOp::Redo;
    journal(j);
    return true;
}

void Session::save() {
    endStroke();
    if (!mProjectDir) return;
    writeSnapshot(snapshotPath(*mProjectDir), configToJson(mConfig), mSequence, *mSculpture,
                  mHistory);
    mJournal->reset();
}

std::string Session::verifyMesh() const {
    return mView->verifyAgainstFullRebuild();
}

Mesh Session::wholeMesh(double spacing) const {
    if (spacing <= 0) spacing = zoomSpacing(mConfig, mSculpture->levels(), 1);
    const Aabb bounds = mSculpture->supportBounds();
    if (bounds.empty()) return {};
    GridRegion r;
    r.spacingMm = spacing;
    int64_t extent = 0;
    for (int a = 0; a < 3; ++a) {
        r.originCell[a] = int64_t(std::floor(bounds.min[a] / spacing)) - 1;
        extent =
            std::max(extent, int64_t(std::ceil(bounds.max[a] / spacing)) + 1 - r.originCell[a]);
    }
    const int64_t n = (extent + 15) / 16 * 16;
    if (n > 1024)
        throw SessionError("the sculpture spans " + std::to_string(extent) + " cells at " +
                           std::to_string(spacing) +
                           " mm; at most 1024 per axis: choose a coarser export spacing");
    r.n = int(n);
    Polygonizer poly(*mSculpture, r, mConfig.polygonizer.bisectionTolerance);
    poly.rebuildAll();
    return poly.mesh();
}

}  // namespace vsculpt::app
