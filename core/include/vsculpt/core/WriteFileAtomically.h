// SPDX-License-Identifier: MIT
/// @file WriteFileAtomically.h
/// @brief Replacing a file's contents in one step: readers see the old file or the new one,
/// never a mix, and a failed write leaves the old file as it was.
///
/// Used for project snapshots (durable) and exports (not durable). POSIX only.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace vsculpt::core {

/// A file that could not be written or replaced. what() names the target path (never the
/// temporary file's) and the operating system's reason; code() is the errno value.
class FileWriteError : public std::runtime_error {
  public:
    FileWriteError(const std::string& message, int code)
        : std::runtime_error(message), mCode(code) {}
    int code() const noexcept { return mCode; }

  private:
    int mCode;
};

/// Writes `bytes` to a new temporary file in `path`'s folder and renames it over `path`.
///
/// The temporary file is `.<name>.<pid>.<n>.tmp`, created with O_EXCL | O_NOFOLLOW: it is
/// always a new file, never an existing one and never the target of a symlink planted at that
/// name (a taken name is skipped for the next). Mode 0644 less the umask; the old file's mode
/// and owner are not carried over.
///
/// A symlink AT `path` is replaced by the new regular file; the file it pointed to is left
/// untouched (rename works on folder entries). Other hard links to the old file keep the old
/// contents.
///
/// With `durable`, the data is fsynced before the rename and the folder after it, so the new
/// contents survive a power loss once the call returns; without it they survive a crash of
/// this process, not necessarily of the machine.
///
/// Throws FileWriteError. The temporary file is removed on every failure and `path` keeps its
/// old contents, except when only the final folder fsync fails: the new contents are then in
/// place but perhaps not on disk, and the message says so.
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes, bool durable);

/// Removes the temporary files of the writeFileAtomically calls in progress in this process
/// (replaceWithHardLink's exist for an instant only). Async-signal-safe: for a SIGINT or SIGTERM
/// handler that then ends the process, so an export interrupted with Ctrl-C leaves no hidden
/// temporary file behind (one of hundreds of MB for a fine export). A process killed outright
/// (SIGKILL, a crash) leaves its temporary file; the next write to the same name in that folder
/// removes it once its process is gone and it has not changed for 10 s.
void removeTemporaryFilesInProgress() noexcept;

/// Gives the file `existing` the additional name `target` (a hard link), replacing whatever
/// `target` named, in one step: `target` is never missing in between, and `existing` is not
/// touched. The two names then share one file: writing through either changes both, while
/// replacing either (writeFileAtomically, rename) separates them. With `durable`, `target`'s
/// folder is fsynced afterwards. The link is made under a temporary name as in
/// writeFileAtomically, then renamed. Throws FileWriteError naming `target`; code() EPERM,
/// EOPNOTSUPP or EXDEV when the file system cannot link (then copy instead).
void replaceWithHardLink(const std::filesystem::path& existing, const std::filesystem::path& target,
                         bool durable);

/// Checks, creating nothing, that writeFileAtomically(path, ...) can work: `path`'s folder
/// exists and is a folder this process may create files in, and `path` is not a folder,
/// device, pipe or socket (those are never replaced: writeFileAtomically refuses them too).
/// For output files named at the start of a long session (an export after a playback), so a
/// mistyped or read-only folder fails at once rather than after the work. Throws
/// FileWriteError naming `path` and the reason. A check, not a promise: the folder can change
/// or the disk fill before the write.
void ensureWritable(const std::filesystem::path& path);

/// The name a damaged file is kept under: `path`.damaged for n = 1, `path`.damaged-n after.
std::filesystem::path damagedName(const std::filesystem::path& path, int n);

/// Renames the damaged file `path` to the first damagedName(path, n) that names nothing, never
/// replacing a file kept earlier, and returns that name. The bytes stay exactly as they were
/// (a rename, not a copy), so what could not be read is there to rescue by hand, and `path`
/// is free for a good file. With `durable`, the folder is fsynced afterwards. Throws
/// FileWriteError naming `path`.
std::filesystem::path setAsideAsDamaged(const std::filesystem::path& path, bool durable);

namespace detail {
/// For tests: the temporary name tried with number `n` for a target named `fileName`...
std::string temporaryName(const std::string& fileName, uint64_t n);
/// ...and the number the next attempt uses (counting up from there; random at start-up), so a
/// test can plant files and symlinks exactly where the next attempts will go.
void setNextTemporaryNumber(uint64_t n);
/// For tests: called (when set) once writeFileAtomically has created and tracked its temporary
/// file, with that file's path, before any byte is written: a test can interrupt a write there.
void setAfterTemporaryCreated(void (*hook)(const char* temporaryPath));
}  // namespace detail

}  // namespace vsculpt::core
