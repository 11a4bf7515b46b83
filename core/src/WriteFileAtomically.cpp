// SPDX-License-Identifier: MIT
#include "vsculpt/core/WriteFileAtomically.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <random>

namespace vsculpt::core {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& what, int err) {
    throw FileWriteError(path.string() + ": " + what + ": " + std::strerror(err), err);
}

/// Closes on scope exit; for the paths that throw.
class FdGuard {
  public:
    explicit FdGuard(int fd) : mFd(fd) {}
    ~FdGuard() {
        if (mFd >= 0) ::close(mFd);
    }
    FdGuard(const FdGuard&) = delete;
    FdGuard& operator=(const FdGuard&) = delete;
    int get() const { return mFd; }
    /// Closes now and reports close()'s error (NFS reports write errors there).
    int closeNow() {
        const int r = ::close(mFd);
        mFd = -1;
        return r;
    }

  private:
    int mFd;
};

// A random start makes the names hard to predict, so planting files at them to make every
// attempt collide is impractical; counting keeps the threads of one process apart.
std::atomic<uint64_t>& tempCounter() {
    static std::atomic<uint64_t> counter{[] {
        std::random_device rd;
        return ((uint64_t(rd()) << 32) ^ rd()) % 1'000'000'000'000ull;
    }()};
    return counter;
}

std::string tempName(const std::string& name) {
    return detail::temporaryName(name, tempCounter().fetch_add(1, std::memory_order_relaxed));
}

// The temporary files of this process's writes in progress, for a signal handler to remove:
// fixed slots (no allocation, no lock), each a state and an absolute path. A slot is claimed
// by a compare-and-swap from free to being filled, filled, then published as live; the
// handler reads only live slots. More writes at once than slots: the extra ones are not
// tracked.
struct PendingSlot {
    std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
    char path[PATH_MAX];
};
constexpr int kPendingSlots = 32;
PendingSlot gPending[kPendingSlots];
std::atomic<void (*)(const char*)> gAfterTemporaryCreated{nullptr};

/// Tracks one temporary file from its creation until it is renamed or removed.
class PendingTemp {
  public:
    PendingTemp(const fs::path& dir, const std::string& tmp) {
        std::error_code ec;
        const std::string full = (fs::absolute(dir, ec) / tmp).string();
        if (ec || full.size() >= PATH_MAX) return;
        for (int i = 0; i < kPendingSlots; ++i) {
            int expected = 0;
            if (gPending[i].state.compare_exchange_strong(expected, 1)) {
                std::memcpy(gPending[i].path, full.c_str(), full.size() + 1);
                gPending[i].state.store(2, std::memory_order_release);
                mSlot = i;
                return;
            }
        }
    }
    ~PendingTemp() { done(); }
    PendingTemp(const PendingTemp&) = delete;
    PendingTemp& operator=(const PendingTemp&) = delete;
    /// The file is renamed or removed: no longer the handler's.
    void done() {
        if (mSlot >= 0) gPending[mSlot].state.store(0, std::memory_order_release);
        mSlot = -1;
    }

  private:
    int mSlot = -1;
};

/// The pid in a temporary name of `name` (".NAME.PID.N.tmp", see detail::temporaryName), or 0
/// when `entry` is not one.
pid_t temporaryNamePid(const std::string& entry, const std::string& name) {
    const std::string prefix = "." + name.substr(0, 180) + ".";
    if (entry.size() <= prefix.size() + 4 || entry.compare(0, prefix.size(), prefix) != 0 ||
        entry.compare(entry.size() - 4, 4, ".tmp") != 0)
        return 0;
    const std::string rest = entry.substr(prefix.size(), entry.size() - prefix.size() - 4);
    const size_t dot = rest.find('.');
    if (dot == 0 || dot == std::string::npos || dot > 9 ||
        rest.find_first_not_of("0123456789.") != std::string::npos ||
        rest.find('.', dot + 1) != std::string::npos || dot + 1 == rest.size())
        return 0;
    return pid_t(std::stol(rest.substr(0, dot)));
}

/// Removes the temporary files of `name` in the folder that a process killed outright left:
/// their process is gone and they have not changed for 10 s (so a writer on another machine
/// sharing the folder, whose pid means nothing here, is left alone while it writes).
void removeAbandonedTemporaries(int dirFd, const std::string& name) {
    const int fd = ::dup(dirFd);
    if (fd < 0) return;
    DIR* d = ::fdopendir(fd);
    if (!d) {
        ::close(fd);
        return;
    }
    ::rewinddir(d);
    const std::time_t now = std::time(nullptr);
    while (const dirent* e = ::readdir(d)) {
        const pid_t pid = temporaryNamePid(e->d_name, name);
        if (pid <= 0 || pid == ::getpid()) continue;
        if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to tell
        struct stat st {};
        if (::fstatat(dirFd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode))
            continue;
        if (now - st.st_mtime < 10) continue;
        ::unlinkat(dirFd, e->d_name, 0);
    }
    ::closedir(d);
}

fs::path folderOf(const fs::path& path) {
    return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

void requireFileName(const fs::path& path) {
    const std::string name = path.filename().string();
    if (name.empty() || name == "." || name == "..")
        fail(path, "names a folder, not a file", EISDIR);
    // Found before a long run rather than at its end (found by QA: "cannot replace: File name
    // too long" after the meshing, of a file that did not exist).
    if (name.size() > NAME_MAX)
        fail(path,
             "its name is " + std::to_string(name.size()) + " bytes, over the " +
                 std::to_string(NAME_MAX) + " a file name may have",
             ENAMETOOLONG);
}

/// A rename replaces whatever the name held: a device node (/dev/full, for a process running
/// as root), a pipe or a socket would be gone, a file left in its place. Only a regular file
/// (or a symlink, itself replaced) may be; a folder makes the rename fail.
void requireReplaceable(int dirFd, const fs::path& path) {
    struct stat st {};
    if (::fstatat(dirFd, path.filename().c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return;
    if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode) && !S_ISDIR(st.st_mode))
        fail(path, "is a device, pipe or socket, not a file: not replaced", EINVAL);
}

}  // namespace

void writeFileAtomically(const fs::path& path, std::string_view bytes, bool durable) {
    requireFileName(path);
    const fs::path dir = folderOf(path);
    const std::string name = path.filename().string();
    FdGuard dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dirFd.get() < 0) fail(path, "cannot open its folder " + dir.string(), errno);
    requireReplaceable(dirFd.get(), path);
    removeAbandonedTemporaries(dirFd.get(), name);

    std::string tmp;
    int fd = -1;
    for (int attempt = 0;; ++attempt) {
        tmp = tempName(name);
        fd = ::openat(dirFd.get(), tmp.c_str(),
                      O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0) break;
        const int err = errno;
        if ((err == EEXIST || err == EINTR) && attempt < 100) continue;
        fail(path, "cannot create a temporary file in " + dir.string(), err);
    }
    FdGuard file(fd);
    PendingTemp pending(dir, tmp);
    auto failAndRemove = [&](const std::string& what, int err) {
        if (file.get() >= 0) file.closeNow();
        ::unlinkat(dirFd.get(), tmp.c_str(), 0);
        pending.done();
        fail(path, what, err);
    };
    if (auto hook = gAfterTemporaryCreated.load()) hook((dir / tmp).c_str());

    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            failAndRemove("cannot write", errno);
        }
        if (n == 0) failAndRemove("cannot write", EIO);  // no progress: do not spin
        done += size_t(n);
    }
    if (durable && ::fsync(fd) != 0) failAndRemove("cannot flush to disk", errno);
    if (file.closeNow() != 0) failAndRemove("cannot write", errno);
    if (::renameat(dirFd.get(), tmp.c_str(), dirFd.get(), name.c_str()) != 0)
        failAndRemove("cannot replace", errno);
    pending.done();
    if (durable && ::fsync(dirFd.get()) != 0)
        fail(path, "was replaced, but its folder could not be flushed to disk", errno);
}

void replaceWithHardLink(const fs::path& existing, const fs::path& target, bool durable) {
    requireFileName(target);
    const fs::path dir = folderOf(target);
    const std::string name = target.filename().string();
    FdGuard dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dirFd.get() < 0) fail(target, "cannot open its folder " + dir.string(), errno);
    requireReplaceable(dirFd.get(), target);
    std::string tmp;
    for (int attempt = 0;; ++attempt) {
        tmp = tempName(name);
        // Flags 0: a symlink at `existing` is linked itself, not followed.
        if (::linkat(AT_FDCWD, existing.c_str(), dirFd.get(), tmp.c_str(), 0) == 0) break;
        const int err = errno;
        if ((err == EEXIST || err == EINTR) && attempt < 100) continue;
        fail(target, "cannot link " + existing.string() + " to it", err);
    }
    if (::renameat(dirFd.get(), tmp.c_str(), dirFd.get(), name.c_str()) != 0) {
        const int err = errno;
        ::unlinkat(dirFd.get(), tmp.c_str(), 0);
        fail(target, "cannot replace", err);
    }
    // rename() between two names of one file does nothing and succeeds (target was already a
    // name of `existing`): the temporary name is then still there.
    ::unlinkat(dirFd.get(), tmp.c_str(), 0);
    if (durable && ::fsync(dirFd.get()) != 0)
        fail(target, "was replaced, but its folder could not be flushed to disk", errno);
}

fs::path damagedName(const fs::path& path, int n) {
    fs::path out = path;
    out += n == 1 ? ".damaged" : ".damaged-" + std::to_string(n);
    return out;
}

fs::path setAsideAsDamaged(const fs::path& path, bool durable) {
    requireFileName(path);
    const fs::path dir = folderOf(path);
    FdGuard dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dirFd.get() < 0) fail(path, "cannot open its folder " + dir.string(), errno);
    const std::string name = path.filename().string();
    for (int n = 1;; ++n) {
        const fs::path kept = damagedName(path, n);
        // RENAME_NOREPLACE: a copy kept earlier is never replaced, even by a racing process.
        if (::renameat2(dirFd.get(), name.c_str(), dirFd.get(), kept.filename().c_str(),
                        RENAME_NOREPLACE) == 0) {
            if (durable && ::fsync(dirFd.get()) != 0)
                fail(path,
                     "was set aside as " + kept.string() +
                         ", but its folder could not be flushed to disk",
                     errno);
            return kept;
        }
        const int err = errno;
        if (err == EEXIST && n < 10000) continue;
        fail(path, "cannot set it aside as " + kept.string(), err);
    }
}

void ensureWritable(const fs::path& path) {
    requireFileName(path);
    const fs::path dir = folderOf(path);
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0) fail(path, "its folder " + dir.string(), errno);
    if (!S_ISDIR(st.st_mode)) fail(path, dir.string() + " is not a folder", ENOTDIR);
    // AT_EACCESS: the rights this process acts with (effective ids), as open() will check.
    if (::faccessat(AT_FDCWD, dir.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
        fail(path, "cannot create files in " + dir.string(), errno);
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) fail(path, "is a folder", EISDIR);
    FdGuard dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dirFd.get() < 0) fail(path, "cannot open its folder " + dir.string(), errno);
    requireReplaceable(dirFd.get(), path);
}

void removeTemporaryFilesInProgress() noexcept {
    for (PendingSlot& slot : gPending)
        if (slot.state.load(std::memory_order_acquire) == 2) ::unlink(slot.path);
}

namespace detail {

std::string temporaryName(const std::string& fileName, uint64_t n) {
    // NAME_MAX is 255 bytes: a long target name is shortened in the temporary name only.
    return "." + fileName.substr(0, 180) + "." + std::to_string(::getpid()) + "." +
           std::to_string(n) + ".tmp";
}

void setNextTemporaryNumber(uint64_t n) {
    tempCounter().store(n, std::memory_order_relaxed);
}

void setAfterTemporaryCreated(void (*hook)(const char* temporaryPath)) {
    gAfterTemporaryCreated.store(hook);
}

}  // namespace detail

}  // namespace vsculpt::core
