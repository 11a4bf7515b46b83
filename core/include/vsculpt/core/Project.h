// SPDX-License-Identifier: MIT
/// @file Project.h
/// @brief Crash-safe projects: a snapshot plus an append-only journal of edits, each with a
/// backup generation.
///
/// A project is a folder holding `snapshot.vsnap` (the sculpture, its config and its undo
/// history at some point) and `journal.vjl` (every edit since, one framed and checksummed
/// record each, flushed to disk before the edit is acknowledged). Opening replays the journal
/// tail over the snapshot. A crash loses at most the record being written: a truncated or
/// corrupt tail is reported and dropped, everything before it is recovered. Saving keeps the
/// previous snapshot and journal as `snapshot.vsnap.bak` and `journal.vjl.bak`, so a snapshot
/// damaged later is recovered from the backup and both journals. Snapshots are written
/// atomically and durably (WriteFileAtomically.h). Every value read is checked against the
/// bounds below, so a damaged or hand-edited file is refused by name instead of reaching the
/// lattices. One writer per project: ProjectLock.h. Format details: docs/projects.md.
#pragma once

#include "vsculpt/core/History.h"
#include "vsculpt/core/SkeletonStore.h"

#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace vsculpt::core {

class Sculpture;

/// A project file that cannot be used; the message names the file, the byte offset and why.
class ProjectError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// The most vertex changes one solid's journal record holds (records are limited to 64 MiB).
inline constexpr size_t kMaxJournalSolidChanges = 3'000'000;
/// The most tool samples one stroke may hold in a journal or snapshot (48 MB of samples, so a
/// stroke always fits a journal record; an hour of samples at 500 Hz).
inline constexpr size_t kMaxStrokeSamples = 2'000'000;
/// Tool samples must satisfy |x|, |y|, |z| < this (mm), as StrokeBuilder requires
/// (isUsablePoint), so a record that passes the check always replays.
inline constexpr double kMaxProjectCoordinateMm = 1.0e6;
/// Skeleton weights must be finite and within +-this. Placement gives weights of order 1
/// (exactly -1, 0, 1 in thesis mode); the bound is loose on purpose, so no sculpted value is
/// ever refused, and only garbage (1e30, a flipped exponent bit) is.
inline constexpr float kMaxSkeletonWeight = 1.0e6f;
/// Sequence numbers (of journal records, and the snapshot's last one) stay below this: an edit
/// a second for 10^11 years, so only a damaged number reaches it, and the next record's number
/// can never wrap to 0 (found by fuzzing: a snapshot claiming 2^64 - 1 made every edit fail).
inline constexpr uint64_t kMaxSequence = uint64_t(1) << 62;

enum class JournalOp : uint8_t { Stroke = 1, Undo = 2, Redo = 3, Solid = 4 };

/// One edit. Values are checked on reading and before writing: levels 1..7, samples within
/// kMaxProjectCoordinateMm and at most kMaxStrokeSamples, lattice coordinates within
/// +-kMaxLatticeCoord, weights finite and within kMaxSkeletonWeight.
struct JournalRecord {
    uint64_t sequence = 0;  ///< 1, 2, 3, ... over the project's life
    JournalOp op = JournalOp::Stroke;
    ToolOp tool = ToolOp::Add;             ///< strokes only
    MirrorAxis mirror = MirrorAxis::None;  ///< strokes only
    int level = 0;                         ///< strokes only
    std::vector<Vec3> samples;             ///< strokes only: object-space tool centres, mm
    int solidLevel = 0;                    ///< solids only: the lattice level
    std::vector<SkeletonChange> changes;   ///< solids only: the vertices' after-states
};

struct JournalContents {
    std::vector<JournalRecord> records;  ///< every complete, intact record, in order
    uint64_t validBytes = 0;             ///< length of the intact prefix
    std::string warning;                 ///< why the tail was dropped (empty if it was not)
};

/// Reads a journal; a missing file is an empty journal. Never writes. Never throws for damage
/// after the header: it stops at the first record that is truncated, fails its checksum,
/// cannot be decoded, is out of sequence or holds a value out of range, keeps every record
/// before it, and says why in `warning`, naming the file, the record (1-based) and, for a
/// value, its sequence number, the field and the reason, e.g. "journal.vjl: record 12
/// (sequence 57): sample 3 x is NaN; it and the rest were dropped". Throws ProjectError if the
/// header is not a version 01 journal's.
JournalContents readJournal(const std::filesystem::path& path);

/// A project file's bytes, read whole. Only a regular file is read: a pipe planted at its name
/// would block, /dev/zero never end (opened non-blocking, then checked). Throws ProjectError
/// naming `path` and the reason.
std::string readProjectFile(const std::filesystem::path& path);

/// Appends records. append() writes its record before it returns, so a crash of this process
/// keeps it (the kernel has it); a flusher thread makes it durable (fdatasync) right after,
/// off the caller's thread: the frame that ends a stroke never waits for the disk, whose flush
/// takes milliseconds on a laptop (a frame at 90 Hz has 11). A power loss can take the
/// records of the flush in progress; waitDurable() waits for every record appended so far.
class JournalWriter {
  public:
    /// How a file is flushed to disk: ::fdatasync unless given (tests hold it, or fail it).
    /// Returns 0, or -1 with errno set.
    using SyncFn = std::function<int(int fd)>;

    /// Opens (creating if needed) and cuts the file to `validBytes` (dropping a damaged tail;
    /// below the header's 8 bytes: a new, empty journal). Before anything is cut, the whole
    /// file is copied, durably, to the first free name of `path`.damaged, .damaged-2, ...
    /// (keptDamaged()): the records after a damaged one cannot be replayed, but they are the
    /// sculptor's work and a repair may need them. Never follows a symlink at `path`.
    /// Throws ProjectError naming the path and the OS reason, having cut nothing.
    JournalWriter(const std::filesystem::path& path, uint64_t validBytes, SyncFn sync = {});
    /// Where the constructor kept the file it cut; empty when it cut nothing.
    const std::filesystem::path& keptDamaged() const { return mKeptDamaged; }
    /// Waits for the last flush (records appended are made durable first).
    ~JournalWriter();
    JournalWriter(const JournalWriter&) = delete;
    JournalWriter& operator=(const JournalWriter&) = delete;

    /// Throws ProjectError, writing nothing, for a record readJournal would refuse (a value
    /// out of range, a sequence number not following the last appended one) or an I/O error,
    /// and for every record after a flush failed (the disk may not hold the earlier ones).
    void append(const JournalRecord& record);
    /// Returns once every record appended before the call is on disk; throws ProjectError
    /// naming the reason when a flush failed.
    void waitDurable();
    /// Starts a new, empty journal at the same path, durably, and appends there from now on.
    /// The file is replaced (a new file renamed into place), not truncated, so another name
    /// for the old one (saveProject's journal.vjl.bak) keeps its records. Records appended
    /// while it runs (from another thread: a background save restarts the journal on its own
    /// thread) follow in the new file: append() never waits for reset()'s flushes, which run
    /// without the lock (the new file is written as `path`.restart, flushed, then renamed).
    /// After a failure the old file goes on: append() writes there as before.
    void reset();
    /// The same, but the new journal starts with this one's records from byte `keepFrom` on
    /// (a bytes() taken between appends): the edits appended while a snapshot of the earlier
    /// ones was written in the background (writeProjectSnapshot). Throws std::logic_error for
    /// an offset outside the records, ProjectError as reset().
    void reset(uint64_t keepFrom);
    /// The journal's length so far: where the next record goes.
    uint64_t bytes() const;
    const std::filesystem::path& path() const { return mPath; }

  private:
    void flushLoop();

    std::filesystem::path mPath;
    std::filesystem::path mKeptDamaged;
    SyncFn mSync;
    // Guards everything below against the flusher thread, which holds it only to take a
    // duplicate of mFd and to count.
    mutable std::mutex mMutex;
    std::condition_variable mWake, mFlushed;
    int mFd = -1;
    uint64_t mLastSequence = 0;  ///< of the last record appended by this writer; 0: none yet
    uint64_t mAppended = 0, mDurable = 0;  ///< records appended, and of those made durable
    std::string mFlushError;               ///< why a flush failed; then every append throws
    bool mStop = false;
    uint64_t mGeneration = 0;  ///< files reset() put in place: a flush of an older one is moot
    std::thread mFlusher;
};

struct SnapshotContents {
    std::string configJson;
    uint64_t lastSequence = 0;  ///< journal records up to this one are in the snapshot
    std::vector<SkeletonEntry> skeletons;
    std::vector<StrokeRecord> done, undone;
};

/// Writes the snapshot atomically and durably (writeFileAtomically). Throws ProjectError,
/// leaving the old file as it was, for an I/O error or a value readSnapshot would refuse
/// (naming the skeleton or history step).
void writeSnapshot(const std::filesystem::path& path, const std::string& configJson,
                   uint64_t lastSequence, const Sculpture& sculpture, const History& history);
/// Never writes. Throws ProjectError naming the file and the damage: the byte offset, or the
/// entry, the field and the byte for a value out of range, e.g. "snapshot.vsnap: skeleton 12:
/// weight is NaN (byte 4711)" or "snapshot.vsnap: redo step 2: change 5: lattice z 8388607 is
/// beyond +-4194303 (byte 90210)".
SnapshotContents readSnapshot(const std::filesystem::path& path);

inline std::filesystem::path snapshotPath(const std::filesystem::path& dir) {
    return dir / "snapshot.vsnap";
}
inline std::filesystem::path journalPath(const std::filesystem::path& dir) {
    return dir / "journal.vjl";
}
inline std::filesystem::path snapshotBackupPath(const std::filesystem::path& dir) {
    return dir / "snapshot.vsnap.bak";
}
inline std::filesystem::path journalBackupPath(const std::filesystem::path& dir) {
    return dir / "journal.vjl.bak";
}

/// What a project folder holds, as readProject() found it.
struct RecoveredProject {
    /// The snapshot to start from (its config, skeletons, history and lastSequence); nullopt
    /// for a project never saved (start from the caller's config and an empty sculpture).
    std::optional<SnapshotContents> snapshot;
    /// The edits after the snapshot, in order, sequence numbers without gaps (replay them with
    /// applyJournalRecord).
    std::vector<JournalRecord> records;
    /// Where a JournalWriter on journal.vjl continues: just after the last record used (or
    /// already in the snapshot). Records after it are unusable and were reported.
    uint64_t journalValidBytes = 0;
    /// Each names the file, the record or offset, and why something was dropped or the backup
    /// used. Empty for a clean project.
    std::vector<std::string> warnings;
    /// The snapshot is the backup (snapshot.vsnap was missing or damaged): records come from
    /// journal.vjl.bak and journal.vjl.
    bool fromBackup = false;
    /// The sequence number of the last edit recovered (the next one is this + 1).
    uint64_t lastSequence() const {
        return !records.empty() ? records.back().sequence : snapshot ? snapshot->lastSequence : 0;
    }
};

/// Reads a project folder and writes nothing (safe on read-only projects and while another
/// process writes: a record being appended reads as a truncated tail). Uses snapshot.vsnap
/// and journal.vjl; when the snapshot is damaged or missing while its backup exists, the
/// backup with journal.vjl.bak then journal.vjl (records up to the snapshot's lastSequence
/// skipped, then each must follow the previous: the first gap ends the recovery, reported).
/// A missing folder, or one with neither snapshot, is a project never saved. Throws
/// ProjectError only when nothing usable exists: `dir` is not a folder, the snapshot and its
/// backup are both unusable (naming both reasons), or journal.vjl is not a journal (refused
/// rather than overwritten: move it away).
RecoveredProject readProject(const std::filesystem::path& dir);

/// Saves a project: the current snapshot becomes snapshot.vsnap.bak and the current journal
/// journal.vjl.bak (new names for the same files; durable before anything else changes), the
/// new snapshot replaces snapshot.vsnap atomically and durably, and `journal` starts a new,
/// empty journal.vjl (JournalWriter::reset). A crash at any point leaves a folder readProject
/// recovers completely. When snapshot.vsnap cannot be read (a project recovered from its
/// backup) it is not rotated, so the good backup is never replaced by a damaged file: the new
/// snapshot is written as both snapshot and backup, with an empty journal.vjl.bak.
/// `lastSequence`: the last edit the sculpture and history contain. Throws ProjectError (the
/// old snapshot kept) for an I/O error or a value out of range; std::invalid_argument when
/// `journal` does not write `dir`'s journal.vjl.
void saveProject(const std::filesystem::path& dir, const std::string& configJson,
                 uint64_t lastSequence, const Sculpture& sculpture, const History& history,
                 JournalWriter& journal);
/// The part of saveProject that may run beside further edits (a background save, on a copy
/// of the sculpture and history): rotates the backups and writes the snapshot, and leaves
/// journal.vjl as it is, records still being appended to it. At every moment the folder reads
/// back (readProject) as every edit journaled: a reader skips the journal's records the
/// snapshot holds. Finish with JournalWriter::reset(keepFrom), keepFrom being the journal's
/// bytes() when `lastSequence` was its last record, so the new journal holds the edits made
/// meanwhile. Throws ProjectError as saveProject.
void writeProjectSnapshot(const std::filesystem::path& dir, const std::string& configJson,
                          uint64_t lastSequence, const Sculpture& sculpture,
                          const History& history);

/// Puts a snapshot's skeletons into `sculpture` (built from the snapshot's config, empty of
/// lattice skeletons) and its undo/redo stacks into `history`.
void restoreSnapshot(const SnapshotContents& snapshot, Sculpture& sculpture, History& history);

/// Replays one journal record as the session did when it was journaled: a stroke or solid is
/// applied and pushed on the history, an undo or redo is done. Returns the object-space box
/// whose field changed (empty when nothing did). Throws std::invalid_argument for values the
/// placement refuses (never for a record readJournal or readProject returned).
Aabb applyJournalRecord(Sculpture& sculpture, History& history, const JournalRecord& record);

}  // namespace vsculpt::core
