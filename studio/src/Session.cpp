// SPDX-License-Identifier: MIT
#include "vsculpt/studio/Session.h"

#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/PlaceStroke.h"
#include "vsculpt/core/WorkerPool.h"

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <thread>

namespace vsculpt::studio {

using namespace vsculpt::core;

Session::Session(const SculptConfig& cfg) : Session(cfg, true) {
    rebuildView();
}

Session::Session(const SculptConfig& cfg, bool)
    : mConfig(cfg), mSculpture(std::make_unique<Sculpture>(cfg)) {
    mSize = mConfig.zoom.allowedSizes[0].front();
    // Every write goes to the mesher: the asynchronous one replays them on its replica, the
    // synchronous view keeps its grid sums with them (Polygonizer::noteWrites).
    mSculpture->store().logWritesTo(&mWrites);
}

/// A snapshot being written by saveInBackground: the thread owns copies of what it writes.
struct Session::BackgroundSave {
    uint64_t sequence = 0;      // the last edit the snapshot holds
    uint64_t journalBytes = 0;  // the journal's length then: later records start here
    std::string error;          // why writing failed (empty: written)
    std::string journalError;   // why the journal did not restart after it (empty: it did)
    std::atomic<bool> done{false};
    std::thread thread;
};

/// An ended stroke whose volume estimate runs on a thread of its own (setAsyncStrokeFinish):
/// the builder waits here, untouched by the session, until the thread is done.
struct Session::PendingFinish {
    std::unique_ptr<StrokeBuilder> stroke;
    std::exception_ptr error;  // what the estimate threw
    std::atomic<bool> done{false};
    std::thread thread;
};

Session::~Session() {
    // A stroke ended but not yet completed is work: it is journaled before the session goes.
    try {
        pollStrokeFinish(true);
    } catch (const std::exception& e) {
        spdlog::warn("{}", e.what());
    }
    // A snapshot being written is finished, so the journal does not keep what it holds.
    try {
        pollSave(true);
    } catch (const std::exception& e) {
        spdlog::warn("{}", e.what());
    }
    mMesher.reset();
    mSculpture->store().logWritesTo(nullptr);
}

void takeMachineSettings(SculptConfig& projectConfig, const SculptConfig& machine) {
    projectConfig.interaction = machine.interaction;
    projectConfig.render = machine.render;
    projectConfig.devices = machine.devices;
}

std::string projectConfigJson(const SculptConfig& cfg) {
    nlohmann::json j = nlohmann::json::parse(configToJson(cfg));
    for (const char* machineOnly : {"interaction", "render", "devices"})
        j.erase(machineOnly);
    return j.dump(1);
}

std::unique_ptr<Session> Session::openProject(const std::filesystem::path& dir,
                                              const SculptConfig& cfg, ProjectMode mode) {
    const bool readOnly = mode == ProjectMode::ReadOnly;
    std::error_code ec;
    if (readOnly) {
        if (!std::filesystem::is_directory(dir, ec))
            throw ProjectError(dir.string() + ": no project folder here");
        // Before the lock: a reader leaves no lock file in a folder that is not a project
        // (a project has a snapshot or, after a crash in a save, its backup).
        if (!std::filesystem::exists(snapshotPath(dir), ec) &&
            !std::filesystem::exists(snapshotBackupPath(dir), ec))
            throw ProjectError(dir.string() + ": not a vsculpt project (no " +
                               snapshotPath(dir).filename().string() + ")");
    } else {
        if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
            throw ProjectError(dir.string() +
                               ": is a file, not a project folder (a project is a folder)");
        std::filesystem::create_directories(dir, ec);
        if (ec)
            throw ProjectError(dir.string() + ": cannot create project folder: " + ec.message());
    }
    // Locked before anything is read, so no other process writes between reading and
    // appending.
    std::unique_ptr<ProjectLock> lock;
    std::string lockNote;
    if (!readOnly) {
        lock = std::make_unique<ProjectLock>(dir, ProjectLock::Mode::Write);
    } else {
        // A reader waits for no one: beside a window that has the project open it reads the
        // journal as far as it is written (a torn last record is dropped, never cut off).
        try {
            lock = std::make_unique<ProjectLock>(dir, ProjectLock::Mode::ReadOnly);
        } catch (const ProjectError& e) {
            // A reader need not close it: drop the writer's advice (found by QA: "close it
            // first; reading it as it is now" said both).
            std::string why = e.what();
            const std::string advice = "; close it first";
            if (why.size() > advice.size() &&
                why.compare(why.size() - advice.size(), advice.size(), advice) == 0)
                why.resize(why.size() - advice.size());
            lockNote = why + "; reading it as it is now (later edits are not in it)";
        }
    }
    RecoveredProject found = readProject(dir);
    std::unique_ptr<Session> s;
    uint64_t lastSeq = 0;
    if (found.snapshot) {
        SnapshotContents& c = *found.snapshot;
        SculptConfig stored;
        try {
            stored =
                parseStoredConfig(c.configJson, snapshotPath(dir).string() + " (stored config)");
        } catch (const ConfigError& e) {
            throw ProjectError(e.what());
        }
        takeMachineSettings(stored, cfg);
        s.reset(new Session(stored, true));
        restoreSnapshot(c, *s->mSculpture, s->mHistory);
        lastSeq = c.lastSequence;
    } else if (readOnly) {
        throw ProjectError(dir.string() + ": not a vsculpt project (no " +
                           snapshotPath(dir).filename().string() + ")");
    } else {
        s.reset(new Session(cfg, true));
        // A new project starts with a snapshot, so the config travels with it.
        // and its backup is the same: a damaged first snapshot never loses the project.
        writeSnapshot(snapshotPath(dir), projectConfigJson(s->mConfig), 0, *s->mSculpture,
                      s->mHistory);
        writeSnapshot(snapshotBackupPath(dir), projectConfigJson(s->mConfig), 0, *s->mSculpture,
                      s->mHistory);
    }
    s->mProjectDir = dir;
    s->mReadOnly = readOnly;
    s->mSequence = lastSeq;
    s->mSnapshotSequence = lastSeq;
    // A crash's journal replays at about 2 ms an edit: said before a wait of seconds (found
    // by QA: 7 s of silence for 3 849 edits).
    if (found.records.size() >= 500)
        spdlog::info("{}: replaying the {} edit(s) journaled since the last save...", dir.string(),
                     found.records.size());
    for (const JournalRecord& r : found.records) {
        if (r.sequence <= s->mSequence) continue;  // already in the snapshot
        core::applyJournalRecord(*s->mSculpture, s->mHistory, r);
        s->mSequence = r.sequence;
        ++s->mRecovered;
    }
    for (const std::string& w : found.warnings)
        s->addRecoveryWarning(w);
    if (!lockNote.empty()) s->addRecoveryWarning(lockNote);
    if (!readOnly) {
        s->mJournal = std::make_unique<JournalWriter>(journalPath(dir), found.journalValidBytes);
        if (const std::filesystem::path& kept = s->mJournal->keptDamaged(); !kept.empty())
            s->addRecoveryWarning(journalPath(dir).string() +
                                  " as it was (with what could not be replayed) is kept in " +
                                  kept.string());
    }
    s->mLock = std::move(lock);
    s->rebuildView();
    return s;
}

void Session::rebuildView() {
    mRegion = zoomRegion(mConfig, mSculpture->levels(), mZoom, mZoomCenter);
    if (mMesher) {
        // The writes so far belong to the old region's last edit; then the region changes.
        if (!mWrites.empty()) mMesher->post(std::exchange(mWrites, {}), Aabb{});
        mMesher->setRegion(mRegion);
        return;
    }
    mWrites.clear();  // the new view starts from the sculpture as it is
    ++mViewChanges;
    mViewRegionStale = true;
    mDirtyBlocks.clear();
    if (!mDeferred) catchUpView();
}

void Session::setDeferredMeshing(bool on) {
    if (on == mDeferred) return;
    if (!on) catchUpView();
    mDeferred = on;
}

void Session::catchUpView() const {
    if (mMesher) return;
    if (mViewRegionStale) {
        mView = std::make_unique<Polygonizer>(*mSculpture, mRegion,
                                              mConfig.polygonizer.viewRootTolerance);
        mView->rebuildAll();
    } else if (!mDirtyBlocks.empty()) {
        // Its kept grid sums missed the writes: the polygonizer notices and evaluates afresh.
        mView->rebuildBlocks(mDirtyBlocks);
    }
    mViewRegionStale = false;
    mDirtyBlocks.clear();
}

void Session::markDirty(std::vector<std::array<int, 3>> blocks) {
    mWrites.clear();
    ++mViewChanges;
    if (!mViewRegionStale) Polygonizer::mergeBlocks(mDirtyBlocks, std::move(blocks));
}

void Session::meshChanged(std::span<const Vec3> points, double radius,
                          std::optional<AsyncMesher::Focus> focus) {
    if (mMesher) {
        mMesher->post(std::exchange(mWrites, {}), std::vector<Vec3>(points.begin(), points.end()),
                      radius, focus);
        return;
    }
    if (mDeferred) {
        markDirty(mViewRegionStale ? Polygonizer::BlockList{} : mView->blocksNear(points, radius));
        return;
    }
    mView->noteWrites(std::exchange(mWrites, {}));
    mView->update(points, radius);
    ++mViewChanges;
}

void Session::meshChanged(const Aabb& box) {
    if (mMesher) {
        mMesher->post(std::exchange(mWrites, {}), box);
        return;
    }
    if (mDeferred) {
        markDirty(mViewRegionStale ? Polygonizer::BlockList{} : mView->blocksTouching(box));
        return;
    }
    mView->noteWrites(std::exchange(mWrites, {}));
    mView->update(box);
    ++mViewChanges;
}

void Session::setAsyncMeshing(bool on) {
    if (on == asyncMeshing()) return;
    if (on) {
        mMesher = std::make_unique<AsyncMesher>(*mSculpture, mRegion,
                                                mConfig.polygonizer.viewRootTolerance);
        mWrites.clear();
        mView.reset();
        mSyncPublished.reset();
    } else {
        mMesher.reset();
        mWrites.clear();
        rebuildView();
    }
}

const Polygonizer& Session::view() const {
    if (mMesher) throw std::logic_error("Session::view() with async meshing on: draw published()");
    catchUpView();
    return *mView;
}

std::shared_ptr<const MeshChunks> Session::published() const {
    if (mMesher) return mMesher->published();
    catchUpView();
    if (!mSyncPublished || mSyncPublishedAt != mViewChanges) {
        auto set = std::const_pointer_cast<MeshChunks>(publishChunks(*mView, mSyncPublished.get()));
        set->edits = mViewChanges;
        set->complete = true;
        mSyncPublished = std::move(set);
        mSyncPublishedAt = mViewChanges;
    }
    return mSyncPublished;
}

void Session::waitForMesh() const {
    if (mMesher) mMesher->waitIdle();
}

std::vector<double> Session::takePublishDelaysMs() {
    return mMesher ? mMesher->takePublishDelaysMs() : std::vector<double>{};
}

bool Session::apply(const ScriptCommand& c) {
    using K = ScriptCommand::Kind;
    switch (c.kind) {
        case K::Tool:
            setTool(c.tool);
            return false;
        case K::Mirror:
            setMirror(c.mirror);
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
        case K::Probe:
            spdlog::info("line {}: probe {}", c.line,
                         readField(c.point, mWorldSpace, true).describe());
            return false;
        case K::Expect:
            // The surface is searched for only to say where it is when the check fails.
            if (readField(c.point, mWorldSpace, false).inside() != c.expectInside)
                throw ExpectationError(
                    std::string("expect ") + (c.expectInside ? "inside" : "outside") +
                    " failed: " + readField(c.point, mWorldSpace, true).describe());
            return false;
        case K::Sketch:
            break;
        case K::Import:
            // Its notes (a repair) go to the studio's notice sink: Studio::apply runs it.
            throw SessionError("import runs through the studio (Studio::apply)");
    }
    // Sketch commands need the sketch document: Studio::apply runs them.
    throw SessionError(
        "a sketch command needs the sketch mode (vsculpt play and vsculpt "
        "sketch run them)");
}

namespace {
// "(0.00, 0.71, -0.71)", without "-0.00".
std::string direction(const Vec3& d) {
    char text[64];
    auto tidy = [](double v) { return std::abs(v) < 0.005 ? 0.0 : v; };
    std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f)", tidy(d.x), tidy(d.y), tidy(d.z));
    return text;
}
}  // namespace

std::string FieldReading::describe() const {
    char text[160];
    const Vec3& p = objectPos;
    std::snprintf(text, sizeof text, "(%g, %g, %g): %s the clay (f - c = %+.4g)", p.x, p.y, p.z,
                  inside() ? "inside" : "outside", value);
    std::string said = text;
    if (surfaceMm) {
        std::snprintf(text, sizeof text, "; the surface %.3g mm away towards ", *surfaceMm);
        said += text + direction(surfaceDirection);
    } else {
        std::snprintf(text, sizeof text, "; no surface within %g mm", kSurfaceSearchMm);
        said += text;
    }
    // The field grows into the clay: the outward normal is against the gradient.
    if (const double g = glm::length(gradient); g > 0)
        said += "; outward normal " + direction(-gradient / g);
    return said;
}

FieldReading Session::readField(const Vec3& point, bool world, bool findSurface) {
    pollStrokeFinish(true);
    FieldReading r;
    r.objectPos = world ? mWorldFromObject.inverse().apply(point) : point;
    FieldProbe probe(*mSculpture);
    const FieldSample f = probe.sample(r.objectPos);
    r.value = f.value;
    r.gradient = f.gradient;
    if (!findSurface) return r;
    // Rays: the gradient's line both ways (the nearest surface near it) and the 26 directions to
    // a cube's neighbours (where the gradient's line runs along a limb or out of a pit).
    std::vector<Vec3> rays;
    if (const double g = glm::length(f.gradient); g > 0) {
        rays.push_back(f.gradient / g);
        rays.push_back(-f.gradient / g);
    }
    for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x)
                if (x || y || z) rays.push_back(glm::normalize(Vec3(x, y, z)));
    constexpr double kStep = 0.25;
    const bool inside = r.inside();
    for (const Vec3& dir : rays) {
        const double reach = std::min(FieldReading::kSurfaceSearchMm, r.surfaceMm.value_or(1e300));
        for (double t = kStep; t <= reach; t += kStep) {
            if ((probe.value(r.objectPos + dir * t) > 0) == inside) continue;
            double lo = t - kStep, hi = t;
            while (hi - lo > 1e-4) {
                const double mid = 0.5 * (lo + hi);
                ((probe.value(r.objectPos + dir * mid) > 0) == inside ? lo : hi) = mid;
            }
            const double found = 0.5 * (lo + hi);
            if (!r.surfaceMm || found < *r.surfaceMm) {
                r.surfaceMm = found;
                r.surfaceDirection = dir;
            }
            break;
        }
    }
    return r;
}

double Session::preStrokeValueAt(const Vec3& objectPos) const {
    if (mStroke) return mStroke->preStrokeValueAt(objectPos);
    FieldProbe probe(*mSculpture);
    return probe.value(objectPos);
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
    if (zoom != 1 && !core::isUsablePoint(center)) {
        char where[160];
        std::snprintf(where, sizeof where, "(%g, %g, %g)", center.x, center.y, center.z);
        throw SessionError(std::string("cannot zoom in at ") + where +
                           ": not a point within 1e6 mm of the origin");
    }
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
    if (mReadOnly) throw SessionError("the project is open read-only: edits are not kept");
    if (mJournal) mJournal->append(r);
}

void Session::beginStroke() {
    if (mStroke) throw SessionError("a stroke is already in progress");
    pollStrokeFinish(true);  // the stroke before this one is complete first
    if (mTool == ToolKind::Select)
        throw SessionError(
            "stroke needs the add, carve or smooth tool (the select tool is active)");
    const ToolOp op = mTool == ToolKind::Add     ? ToolOp::Add
                      : mTool == ToolKind::Carve ? ToolOp::Carve
                                                 : ToolOp::Smooth;
    try {
        mStroke = std::make_unique<StrokeBuilder>(*mSculpture, op, mSize, mMirror);
        mStroke->holdBackChangesBelow(kInteractiveHoldBelow);
    } catch (const std::invalid_argument& e) {
        throw SessionError(e.what());  // smooth in thesis mode: the user's choice to change
    }
    mStrokeRecord = StrokeRecord{};
    mStrokeRecord.op = op;
    mStrokeRecord.mirror = mMirror;
    mStrokeRecord.level = mSize;
}

void Session::strokeSample(const Vec3& p, bool world) {
    if (!mStroke) throw SessionError("no stroke in progress");
    const Vec3 objectPos = world ? mWorldFromObject.inverse().apply(p) : p;
    try {
        const auto t0 = std::chrono::steady_clock::now();
        const EditResult r = mStroke->addSample(objectPos);
        // The surface within the tool's ball first, the placement's adjustments beside it
        // after (docs/async-mesher.md).
        strokeEdited(
            r, t0,
            AsyncMesher::Focus{objectPos, 0.5 * mSculpture->levels().level(mSize).diameterMm});
        mStrokeRecord.samples.push_back(objectPos);
    } catch (const std::logic_error& e) {
        // A refused sample cancels the whole stroke: no half-applied, unjournaled edit.
        cancelStroke();
        // The lattices refuse a point they cannot hold with invalid_argument/out_of_range:
        // the user's input. Any other logic_error is a broken invariant and stays one.
        if (dynamic_cast<const std::invalid_argument*>(&e) ||
            dynamic_cast<const std::out_of_range*>(&e))
            throw SessionError(std::string("tool sample refused: ") + e.what());
        throw;
    } catch (...) {
        cancelStroke();
        throw;
    }
}

void Session::strokeEdited(const EditResult& r, std::chrono::steady_clock::time_point t0,
                           std::optional<AsyncMesher::Focus> focus) {
    meshChanged(r.changedPoints, r.supportMm, focus);
    mSampleMs.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
}

void Session::cancelStroke() {
    meshChanged(revertChanges(*mSculpture, mStroke->changes()));
    mStroke.reset();
    mStrokeRecord = StrokeRecord{};
}

void Session::setAsyncStrokeFinish(bool on) {
    if (!on) pollStrokeFinish(true);
    mAsyncFinish = on;
}

bool Session::pollStrokeFinish(bool wait) {
    if (!mFinishing) return false;
    if (!wait && !mFinishing->done.load(std::memory_order_acquire)) return false;
    mFinishing->thread.join();
    const std::unique_ptr<PendingFinish> pending = std::move(mFinishing);
    mStroke = std::move(pending->stroke);
    if (pending->error) {
        cancelStroke();
        std::rethrow_exception(pending->error);
    }
    completeStroke();
    return true;
}

void Session::endStroke() {
    pollStrokeFinish(true);
    if (!mStroke) return;
    if (mAsyncFinish) {
        std::function<void()> estimate;
        try {
            estimate = mStroke->beginFinish();
        } catch (...) {
            cancelStroke();
            throw;
        }
        if (estimate) {
            // Nothing writes the sculpture until the stroke is completed: every call that
            // would waits for it first (pollStrokeFinish(true)).
            auto pending = std::make_unique<PendingFinish>();
            pending->stroke = std::move(mStroke);
            PendingFinish* p = pending.get();
            pending->thread = std::thread([p, estimate = std::move(estimate)] {
                // Background work, as the mesher's helpers: a waking frame thread comes first.
                lowerThisThreadsPriority(AsyncMesher::kHelperNice);
                try {
                    estimate();
                } catch (...) {
                    p->error = std::current_exception();
                }
                p->done.store(true, std::memory_order_release);
            });
            mFinishing = std::move(pending);
            return;
        }
    }
    completeStroke();
}

void Session::completeStroke() {
    try {
        // The small adjustments the samples held back: the stroke is complete only now.
        const auto t0 = std::chrono::steady_clock::now();
        const EditResult r = mStroke->finish();
        if (!r.changedPoints.empty()) strokeEdited(r, t0);
    } catch (...) {
        cancelStroke();
        throw;
    }
    mStrokeRecord.changes = mStroke->takeChanges();
    mStroke.reset();
    if (mStrokeRecord.samples.empty()) return;  // nothing placed: no step
    // The edit is durable before it counts as done.
    JournalRecord j;
    j.sequence = mSequence + 1;
    j.op = JournalOp::Stroke;
    j.tool = mStrokeRecord.op;
    j.mirror = mStrokeRecord.mirror;
    j.level = mStrokeRecord.level;
    j.samples = mStrokeRecord.samples;
    try {
        journal(j);
    } catch (...) {
        // Not durable, so not done: roll the stroke back as addSolid does, so the sculpture
        // never shows what a reopened project would not have.
        meshChanged(revertChanges(*mSculpture, mStrokeRecord.changes));
        mStrokeRecord = StrokeRecord{};
        throw;
    }
    ++mSequence;
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
    return commitSolid(std::move(placed), takenBox);
}

int Session::addPlacedSolid(int level, std::span<const SkeletonChange> placedChanges) {
    endStroke();
    return commitSolid(replaySolid(*mSculpture, level, placedChanges), Aabb{});
}

int Session::commitSolid(SolidPlacement placed, const Aabb& takenBox) {
    if (placed.changes.size() > kMaxJournalSolidChanges) {
        revertChanges(*mSculpture, placed.changes);
        throw SessionError("solid changes " + std::to_string(placed.changes.size()) +
                           " lattice vertices at level " + std::to_string(placed.level) +
                           ", more than one edit can hold; " +
                           (placed.level < core::kLevelCount
                                ? std::string("choose a larger level")
                                : std::string("make it smaller (level 7 is the largest)")));
    }
    if (placed.changes.empty()) return placed.level;  // already clay everywhere: no step
    if (!takenBox.empty()) meshChanged(takenBox);
    meshChanged(placed.edit.changedPoints, placed.edit.supportMm);
    JournalRecord j;
    j.sequence = ++mSequence;
    j.op = JournalOp::Solid;
    j.solidLevel = placed.level;
    j.changes = placed.changes;
    try {
        journal(j);
    } catch (...) {
        // Not durable, so not done: no edit the project would lose on reopening.
        meshChanged(revertChanges(*mSculpture, placed.changes));
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
    JournalRecord j;
    j.sequence = mSequence + 1;
    j.op = JournalOp::Undo;
    journal(j);  // before the undo: a failed write leaves the step in place
    ++mSequence;
    meshChanged(mHistory.undo(*mSculpture));
    return true;
}

bool Session::redo() {
    endStroke();
    if (!mHistory.canRedo()) return false;
    JournalRecord j;
    j.sequence = mSequence + 1;
    j.op = JournalOp::Redo;
    journal(j);
    ++mSequence;
    meshChanged(mHistory.redo(*mSculpture));
    return true;
}

void Session::save() {
    endStroke();
    if (!mProjectDir) return;
    if (mReadOnly) throw SessionError("the project is open read-only: nothing to save");
    // A background save's outcome is superseded by this one (a failure here is thrown).
    pollSave(true);
    saveProject(*mProjectDir, projectConfigJson(mConfig), mSequence, *mSculpture, mHistory,
                *mJournal);
    mSnapshotSequence = mSequence;
}

void Session::saveCopyTo(const std::filesystem::path& dir) {
    endStroke();
    std::error_code ec;
    if (std::filesystem::exists(snapshotPath(dir), ec) ||
        std::filesystem::exists(journalPath(dir), ec))
        throw SessionError(dir.string() + ": already holds a project");
    std::filesystem::create_directories(dir);
    writeProjectSnapshot(dir, projectConfigJson(mConfig), mSequence, *mSculpture, mHistory);
}

namespace {
// Below the mesher's helpers (AsyncMesher::kHelperNice, +5), as exports: the frame and the
// mesh on show come first; the snapshot's encoding is the CPU work here.
constexpr int kBackgroundSaveNice = 10;
}  // namespace

bool Session::saveInBackground() {
    endStroke();
    if (!mProjectDir) return false;
    if (mReadOnly) throw SessionError("the project is open read-only: nothing to save");
    if (mSaving && !pollSave())
        throw SessionError("still saving " + mProjectDir->string() + " (asked for earlier)");
    auto job = std::make_unique<BackgroundSave>();
    job->sequence = mSequence;
    job->journalBytes = mJournal->bytes();
    BackgroundSave* j = job.get();
    // Copies for the thread (at 1e5 skeletons 0.2-0.4 ms for the sculpture, 0.2 ms for the
    // history, whose records are shared: docs/benchmarks.md); the live ones go on changing.
    j->thread = std::thread([j, dir = *mProjectDir, configJson = projectConfigJson(mConfig),
                             sculpture = std::unique_ptr<const Sculpture>(mSculpture->clone()),
                             history = mHistory, journal = mJournal.get()] {
        try {
            lowerThisThreadsPriority(kBackgroundSaveNice);
            writeProjectSnapshot(dir, configJson, j->sequence, *sculpture, history);
        } catch (const std::exception& e) {
            j->error = e.what();
        }
        if (j->error.empty()) {
            // The journal restarts here too, not on the frame that polls: the new file (the
            // records appended since the snapshot began) is written durably, flushes that take
            // milliseconds on a laptop's disk; appends go on meanwhile (JournalWriter::reset).
            try {
                journal->reset(j->journalBytes);
            } catch (const std::exception& e) {
                j->journalError = e.what();
            }
        }
        j->done.store(true, std::memory_order_release);
    });
    mSaving = std::move(job);
    return true;
}

std::optional<std::string> Session::pollSave(bool wait, bool* failed) {
    if (!mSaving || (!wait && !mSaving->done.load(std::memory_order_acquire))) return std::nullopt;
    bool bad = true;
    std::string outcome = finishSave(bad);
    // Logged here, whoever takes it (a window's poll, a save or a close waiting for it): a
    // failure is a warning, the journal keeping every edit.
    if (bad)
        spdlog::warn("{}", outcome);
    else
        spdlog::info("{}", outcome);
    if (failed) *failed = bad;
    return outcome;
}

std::string Session::finishSave(bool& failed) {
    mSaving->thread.join();
    const std::unique_ptr<BackgroundSave> job = std::move(mSaving);
    const std::string dir = mProjectDir->string();
    failed = true;
    if (!job->error.empty())
        return "saving " + dir + " failed: " + job->error + "; the journal keeps every edit";
    if (!job->journalError.empty())
        // The snapshot is in place and the old journal holds every edit, and goes on taking
        // them: nothing is lost, the next save restarts it.
        return "saved " + dir + ", but the journal did not restart: " + job->journalError;
    mSnapshotSequence = job->sequence;
    failed = false;
    return "saved " + dir;
}

std::string Session::verifyMesh() const {
    if (mMesher) return mMesher->verifyAgainstFullRebuild();
    catchUpView();
    return mView->verifyAgainstFullRebuild();
}

Mesh Session::wholeMesh(double spacing) const {
    return wholeMeshOf(*mSculpture, spacing);
}

Mesh wholeMeshOf(const Sculpture& sculpture, double spacing, WorkerPool* workers) {
    constexpr int kWholeMeshMaxCells = Session::kWholeMeshMaxCells;
    if (spacing == 0) spacing = zoomSpacing(sculpture.config(), sculpture.levels(), 1);
    if (!std::isfinite(spacing) || spacing <= 0)
        throw SessionError("grid spacing must be a positive number of mm");
    const Aabb bounds = sculpture.supportBounds();
    if (bounds.empty()) return {};
    // The extent in cells is computed in doubles first: a tiny spacing gives a cell count
    // no integer holds, and it is refused before any conversion.
    double cells = 0;
    for (int a = 0; a < 3; ++a)
        cells = std::max(
            cells, std::ceil(bounds.max[a] / spacing) - std::floor(bounds.min[a] / spacing) + 2);
    if (!(cells <= kWholeMeshMaxCells)) {
        char text[160];
        std::snprintf(text, sizeof text,
                      "the sculpture spans %.3g cells at %.3g mm; at most %d per axis: "
                      "choose a coarser spacing",
                      cells, spacing, kWholeMeshMaxCells);
        throw SessionError(text);
    }
    GridRegion r;
    r.spacingMm = spacing;
    int64_t extent = 0;
    for (int a = 0; a < 3; ++a) {
        r.originCell[a] = int64_t(std::floor(bounds.min[a] / spacing)) - 1;
        extent =
            std::max(extent, int64_t(std::ceil(bounds.max[a] / spacing)) + 1 - r.originCell[a]);
    }
    const int64_t n = (extent + 15) / 16 * 16;
    if (n > kWholeMeshMaxCells)
        throw SessionError("the sculpture spans " + std::to_string(extent) + " cells at " +
                           std::to_string(spacing) + " mm; at most " +
                           std::to_string(kWholeMeshMaxCells) +
                           " per axis: choose a coarser spacing");
    r.n = int(n);
    Polygonizer poly(sculpture, r, sculpture.config().polygonizer.rootTolerance);
    poly.useWorkers(workers);
    poly.rebuildAll();
    return poly.mesh();
}

}  // namespace vsculpt::studio
