// SPDX-License-Identifier: MIT
/// @file ProjectLock.h
/// @brief One writer per project: an advisory flock() on `<dir>/lock`, held for as long as a
/// ProjectLock lives.
///
/// Two vsculpt processes appending to one journal, or one saving while the other appends,
/// would interleave records and lose edits; the lock turns that into a clear error at opening.
/// flock() locks belong to the open file, so two ProjectLocks in one process conflict just as
/// two processes do, and the kernel releases a lock when its holder dies (kill -9 included):
/// there is never a stale lock to clean up. Not reliable on network file systems that do not
/// support flock().
#pragma once

#include "vsculpt/core/Project.h"

#include <filesystem>

namespace vsculpt::core {

inline std::filesystem::path lockPath(const std::filesystem::path& dir) {
    return dir / "lock";
}

class ProjectLock {
  public:
    enum class Mode {
        /// Exclusive: the only opener; its pid is written into the lock file while it holds it.
        Write,
        /// Shared with other readers, excluding writers (e.g. rendering a still of a project).
        /// In a folder this process cannot write (a read-only mount, another user's project)
        /// it proceeds without a lock and without creating anything: held() is false then.
        ReadOnly,
    };

    /// Opens (in Write mode, or ReadOnly in a writable folder: creating) `<dir>/lock` with
    /// O_NOFOLLOW, so a symlink planted there is refused, never followed, and takes the lock
    /// without waiting. Throws ProjectError: "<dir>: the project is open in another vsculpt
    /// (pid N); close it first" when another holder conflicts, or naming the lock file and the
    /// OS reason when it cannot be opened or locked. `dir` must exist.
    explicit ProjectLock(const std::filesystem::path& dir, Mode mode = Mode::Write);
    /// Releases the lock. A writer first empties the file, so a pid left in it always names a
    /// live holder. The file itself stays: removing it could let a later opener lock a new file
    /// while a slower one still holds the old.
    ~ProjectLock();
    ProjectLock(ProjectLock&& other) noexcept;
    ProjectLock& operator=(ProjectLock&& other) noexcept;
    ProjectLock(const ProjectLock&) = delete;
    ProjectLock& operator=(const ProjectLock&) = delete;

    /// False only for a ReadOnly lock in a folder that could not hold a lock file.
    bool held() const { return mFd >= 0; }
    Mode mode() const { return mMode; }
    const std::filesystem::path& dir() const { return mDir; }

  private:
    void release() noexcept;

    std::filesystem::path mDir;
    Mode mMode = Mode::Write;
    int mFd = -1;
};

}  // namespace vsculpt::core
