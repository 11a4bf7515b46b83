// SPDX-License-Identifier: MIT
/// @file Project.h
/// @brief Crash-safe projects: a snapshot plus an append-only journal of edits.
///
/// A project is a folder holding `snapshot.vsnap` (the sculpture, its config and its undo
/// history at some point) and `journal.vjl` (every edit since, one framed and checksummed
/// record each, flushed to disk before the edit is acknowledged). Opening replays the journal
/// tail over the snapshot. A crash loses at most the record being written: a truncated or
/// corrupt tail is reported and dropped, everything before it is recovered. Snapshots are
/// written atomically (temporary file, fsync, rename, fsync of the folder). Format details:
/// docs/projects.md.
#pragma once

#include "vsculpt/core/History.h"
#include "vsculpt/core/SkeletonStore.h"

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
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

enum class JournalOp : uint8_t { Stroke = 1, Undo = 2, Redo = 3, Solid = 4 };

struct JournalRecord {
    uint64_t sequence = 0;  ///< 1, 2, 3, ... over the project's life
    JournalOp op = JournalOp::Stroke;
    ToolOp tool = ToolOp::Add;            ///< strokes only
    int level = 0;                        ///< strokes only
    std::vector<Vec3> samples;            ///< strokes only: object-space tool centres, mm
    int solidLevel = 0;                   ///< solids only: the lattice level
    std::vector<SkeletonChange> changes;  ///< solids only: the vertices' after-states
};

struct JournalContents {
    std::vector<JournalRecord> records;  ///< every complete, intact record, in order
    uint64_t validBytes = 0;             ///< length of the intact prefix
    std::string warning;                 ///< why the tail was dropped (empty if it was not)
};

/// Reads a journal; a missing file is an empty journal. Never throws for damage after the
/// header: it stops at the first bad record. Throws ProjectError if the header is wrong.
JournalContents readJournal(const std::filesystem::path& path);

/// Appends records, each flushed to disk (fdatasync) before append() returns.
class JournalWriter {
  public:
    /// Opens (creating if needed) and cuts the file to `validBytes` (dropping a damaged tail).
    JournalWriter(const std::filesystem::path& path, uint64_t validBytes);
    ~JournalWriter();
    JournalWriter(const JournalWriter&) = delete;
    JournalWriter& operator=(const JournalWriter&) = delete;

    void append(const JournalRecord& record);
    /// Empties the journal (after a snapshot has absorbed it).
    void reset();

  private:
    std::filesystem::path mPath;
    int mFd = -1;
};

struct SnapshotContents {
    std::string configJson;
    uint64_t lastSequence = 0;  ///< journal records up to this one are in the snapshot
    std::vector<SkeletonEntry> skeletons;
    std::vector<StrokeRecord> done, undone;
};

/// Writes the snapshot atomically: `path`.tmp, fsync, rename over `path`, fsync the folder.
void writeSnapshot(const std::filesystem::path& path, const std::string& configJson,
                   uint64_t lastSequence, const Sculpture& sculpture, const History& history);
/// Throws ProjectError naming the file and the offset of the damage.
SnapshotContents readSnapshot(const std::filesystem::path& path);

inline std::filesystem::path snapshotPath(const std::filesystem::path& dir) {
    return dir / "snapshot.vsnap";
}
inline std::filesystem::path journalPath(const std::filesystem::path& dir) {
    return dir / "journal.vjl";
}

}  // namespace vsculpt::core
