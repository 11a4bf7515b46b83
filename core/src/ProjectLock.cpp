// SPDX-License-Identifier: MIT
#include "vsculpt/core/ProjectLock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace vsculpt::core {

namespace {

namespace fs = std::filesystem;

// O_NONBLOCK: a FIFO planted at the name must not block open(); it is refused below.
constexpr int kOpenFlags = O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK;

[[noreturn]] void failOpen(const fs::path& file, int err) {
    std::string why = std::strerror(err);
    if (err == ELOOP) why = "it is a symbolic link, which is never followed";
    throw ProjectError(file.string() + ": cannot open the project's lock file: " + why);
}

/// The pid a writer left in the file, or "unknown" (a writer between locking and writing).
std::string holderPid(int fd) {
    char buf[32] = {};
    const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    std::string s = n > 0 ? std::string(buf, size_t(n)) : std::string();
    while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
        s.pop_back();
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) return "unknown";
    return s;
}

bool isPermissionProblem(int err) {
    return err == EACCES || err == EPERM || err == EROFS;
}

}  // namespace

ProjectLock::ProjectLock(const fs::path& dir, Mode mode) : mDir(dir), mMode(mode) {
    const fs::path file = lockPath(dir);
    if (mode == Mode::Write) {
        mFd = ::open(file.c_str(), O_RDWR | O_CREAT | kOpenFlags, 0644);
        if (mFd < 0) failOpen(file, errno);
    } else {
        mFd = ::open(file.c_str(), O_RDONLY | kOpenFlags);
        if (mFd < 0 && errno == ENOENT)
            mFd = ::open(file.c_str(), O_RDONLY | O_CREAT | kOpenFlags, 0644);
        if (mFd < 0) {
            // A project this process may only read: nothing can be created there, and no
            // writer of ours can be running in it under this process's rights either.
            if (isPermissionProblem(errno) && fs::is_directory(dir)) return;
            failOpen(file, errno);
        }
    }
    struct stat st {};
    if (::fstat(mFd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(mFd);
        mFd = -1;
        throw ProjectError(file.string() + ": the project's lock file is not a regular file");
    }

    const int how = mode == Mode::Write ? LOCK_EX : LOCK_SH;
    int r;
    do {
        r = ::flock(mFd, how | LOCK_NB);
    } while (r != 0 && errno == EINTR);
    if (r != 0) {
        const int err = errno;
        std::string message;
        if (err != EWOULDBLOCK) {
            message = file.string() + ": cannot lock: " + std::strerror(err);
        } else if (mode == Mode::Write && ::flock(mFd, LOCK_SH | LOCK_NB) == 0) {
            // Only readers hold it; they write no pid (there may be several).
            message =
                dir.string() + ": the project is open read-only in another vsculpt; close it first";
        } else {
            message = dir.string() + ": the project is open in another vsculpt (pid " +
                      holderPid(mFd) + "); close it first";
        }
        ::close(mFd);
        mFd = -1;
        throw ProjectError(message);
    }

    if (mode == Mode::Write) {
        const std::string pid = std::to_string(::getpid()) + "\n";
        // Only a hint for the error above, so a failure here does not refuse the project.
        if (::ftruncate(mFd, 0) == 0) {
            [[maybe_unused]] const ssize_t n = ::pwrite(mFd, pid.data(), pid.size(), 0);
        }
    }
}

ProjectLock::~ProjectLock() {
    release();
}

ProjectLock::ProjectLock(ProjectLock&& other) noexcept
    : mDir(std::move(other.mDir)), mMode(other.mMode), mFd(std::exchange(other.mFd, -1)) {}

ProjectLock& ProjectLock::operator=(ProjectLock&& other) noexcept {
    if (this != &other) {
        release();
        mDir = std::move(other.mDir);
        mMode = other.mMode;
        mFd = std::exchange(other.mFd, -1);
    }
    return *this;
}

void ProjectLock::release() noexcept {
    if (mFd < 0) return;
    if (mMode == Mode::Write) {
        // A failure leaves a stale pid, shown only in a conflict message, and there is none.
        [[maybe_unused]] const int ignored = ::ftruncate(mFd, 0);
    }
    ::close(mFd);  // closing the last descriptor of the open file releases the flock
    mFd = -1;
}

}  // namespace vsculpt::core
