// SPDX-License-Identifier: MIT
#include "vsculpt/core/WriteFileAtomically.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
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

fs::path folderOf(const fs::path& path) {
    return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

void requireFileName(const fs::path& path) {
    const std::string name = path.filename().string();
    if (name.empty() || name == "." || name == "..")
        fail(path, "names a folder, not a file", EISDIR);
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
    auto failAndRemove = [&](const std::string& what, int err) {
        if (file.get() >= 0) file.closeNow();
        ::unlinkat(dirFd.get(), tmp.c_str(), 0);
        fail(path, what, err);
    };

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

namespace detail {

std::string temporaryName(const std::string& fileName, uint64_t n) {
    // NAME_MAX is 255 bytes: a long target name is shortened in the temporary name only.
    return "." + fileName.substr(0, 180) + "." + std::to_string(::getpid()) + "." +
           std::to_string(n) + ".tmp";
}

void setNextTemporaryNumber(uint64_t n) {
    tempCounter().store(n, std::memory_order_relaxed);
}

}  // namespace detail

}  // namespace vsculpt::core
