// SPDX-License-Identifier: MIT
// Project files made safe: atomic writes that never follow planted symlinks and clean up
// after themselves, the one-writer lock (in one process and across fork()), snapshot backups
// and the read-only recovery, values checked on load (each damaged value written with a
// correct checksum, so only the check can catch it), and redo surviving a reopen.
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/ProjectLock.h"
#include "vsculpt/core/WriteFileAtomically.h"

#include "../TestFiles.h"
#include "TestHelpers.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <future>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace vsculpt::core {
namespace {

namespace fs = std::filesystem;
using test::linePath;

// ------------------------------------------------------------------------------ helpers

struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& suffix = "") {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path = fs::temp_directory_path() / ("vsculpt_project_" + std::to_string(::getpid()) + "_" +
                                            info->test_suite_name() + "_" + info->name() + suffix);
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::permissions(path, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(path, ec);
    }
};

using vsculpt::test::readFile;
using vsculpt::test::writeFile;

std::vector<std::string> listDir(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
        names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// CRC-32 (IEEE, reflected, as zlib computes it), written here so the tests do not share the
// implementation they check.
uint32_t crc32Of(const char* p, size_t n) {
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; ++i) {
        c ^= uint8_t(p[i]);
        for (int k = 0; k < 8; ++k)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

template <typename T>
void put(std::string& s, size_t at, T v) {
    ASSERT_LE(at + sizeof v, s.size());
    std::memcpy(s.data() + at, &v, sizeof v);
}

template <typename T>
void append(std::string& s, T v) {
    s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// Journal frames: "VSJRNL01", then per record u32 mark, u32 length, u32 CRC, payload.
std::vector<std::string> journalPayloads(const std::string& file) {
    std::vector<std::string> out;
    size_t pos = 8;
    while (pos + 12 <= file.size()) {
        uint32_t len;
        std::memcpy(&len, file.data() + pos + 4, 4);
        out.push_back(file.substr(pos + 12, len));
        pos += 12 + len;
    }
    return out;
}

std::string journalFile(const std::vector<std::string>& payloads) {
    std::string f = "VSJRNL01";
    for (const std::string& p : payloads) {
        append(f, uint32_t(0x5245434Bu));
        append(f, uint32_t(p.size()));
        append(f, crc32Of(p.data(), p.size()));
        f += p;
    }
    return f;
}

/// Byte offset just after the first `n` records.
uint64_t journalEnd(const std::vector<std::string>& payloads, size_t n) {
    uint64_t end = 8;
    for (size_t i = 0; i < n; ++i)
        end += 12 + payloads[i].size();
    return end;
}

void fixSnapshotChecksum(std::string& s) {
    const uint32_t sum = crc32Of(s.data(), s.size() - 4);
    std::memcpy(s.data() + s.size() - 4, &sum, 4);
}

using Entry = std::tuple<int, int32_t, int32_t, int32_t, float>;
std::vector<Entry> entries(const Sculpture& s) {
    std::vector<Entry> out;
    s.store().forEach([&](const SkeletonEntry& e) {
        out.emplace_back(e.level, e.coord.x, e.coord.y, e.coord.z, e.weight);
    });
    std::sort(out.begin(), out.end());
    return out;
}

SculptConfig config() {
    SculptConfig cfg;
    cfg.sphereRadiusMm = 20;
    cfg.placement = PlacementMode::Free;
    return cfg;
}

JournalRecord strokeRecord(uint64_t seq, ToolOp tool, int level, const Vec3& a, const Vec3& b) {
    JournalRecord r;
    r.sequence = seq;
    r.op = JournalOp::Stroke;
    r.tool = tool;
    r.level = level;
    r.samples = linePath(a, b, 3.0);
    return r;
}

JournalRecord plainRecord(uint64_t seq, JournalOp op) {
    JournalRecord r;
    r.sequence = seq;
    r.op = op;
    return r;
}

/// A sculpting session as the app runs one: each edit applied, then journaled.
struct Sculptor {
    Sculpture sculpture{config()};
    History history;
    uint64_t sequence = 0;

    void edit(JournalRecord r, JournalWriter& journal) {
        r.sequence = ++sequence;
        applyJournalRecord(sculpture, history, r);
        journal.append(r);
    }
    void stroke(JournalWriter& j, ToolOp op, int level, const Vec3& a, const Vec3& b) {
        edit(strokeRecord(0, op, level, a, b), j);
    }
    void undo(JournalWriter& j) { edit(plainRecord(0, JournalOp::Undo), j); }
    void redo(JournalWriter& j) { edit(plainRecord(0, JournalOp::Redo), j); }
    void save(const fs::path& dir, JournalWriter& j) {
        saveProject(dir, configToJson(sculpture.config()), sequence, sculpture, history, j);
    }
    /// A project in `dir` of one stroke, saved twice: the snapshot and its backup both hold it.
    void strokeSavedTwice(const fs::path& dir) {
        JournalWriter j(journalPath(dir), 0);
        stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        save(dir, j);
        save(dir, j);
    }
};

/// Opens a project as the app would: the snapshot's config, its skeletons and history, then
/// every recovered record replayed.
struct Reopened {
    RecoveredProject project;
    std::unique_ptr<Sculpture> sculpture;
    History history;
    explicit Reopened(const fs::path& dir) : project(readProject(dir)) {
        const SculptConfig cfg = project.snapshot
                                     ? parseConfig(project.snapshot->configJson, "stored config")
                                     : config();
        sculpture = std::make_unique<Sculpture>(cfg);
        if (project.snapshot) restoreSnapshot(*project.snapshot, *sculpture, history);
        for (const JournalRecord& r : project.records)
            applyJournalRecord(*sculpture, history, r);
    }
};

std::string allWarnings(const RecoveredProject& p) {
    std::string s;
    for (const std::string& w : p.warnings)
        s += w + "\n";
    return s;
}

// ------------------------------------------------------------------------------ atomic writes

TEST(WriteFileAtomically, ReplacesTheContentsAndLeavesOnlyTheFile) {
    TempDir dir;
    const fs::path target = dir.path / "out.txt";
    writeFileAtomically(target, "first", false);
    EXPECT_EQ(readFile(target), "first");
    writeFileAtomically(target, std::string(100000, 'x'), true);
    EXPECT_EQ(readFile(target), std::string(100000, 'x'));
    writeFileAtomically(target, "", true);
    EXPECT_EQ(readFile(target), "");
    EXPECT_EQ(listDir(dir.path), std::vector<std::string>{"out.txt"});
}

TEST(WriteFileAtomically, NeverOpensOrFollowsWhatIsPlantedAtATemporaryName) {
    TempDir dir;
    const fs::path target = dir.path / "out.txt", victim = dir.path / "victim.txt";
    writeFile(victim, "precious");
    writeFile(target, "old");
    // The next three names this process will try: a symlink to the victim, a regular file and
    // a dangling symlink. Following or reusing any of them would be the bug.
    detail::setNextTemporaryNumber(4242);
    const fs::path t0 = dir.path / detail::temporaryName("out.txt", 4242);
    const fs::path t1 = dir.path / detail::temporaryName("out.txt", 4243);
    const fs::path t2 = dir.path / detail::temporaryName("out.txt", 4244);
    fs::create_symlink(victim, t0);
    writeFile(t1, "someone else's");
    fs::create_symlink(dir.path / "nowhere", t2);

    writeFileAtomically(target, "new", true);
    EXPECT_EQ(readFile(target), "new");
    EXPECT_EQ(readFile(victim), "precious");
    EXPECT_TRUE(fs::is_symlink(t0));
    EXPECT_EQ(readFile(t1), "someone else's");
    EXPECT_TRUE(fs::is_symlink(t2));
    EXPECT_FALSE(fs::exists(dir.path / "nowhere"));
    EXPECT_FALSE(fs::exists(dir.path / detail::temporaryName("out.txt", 4245)));
    EXPECT_EQ(listDir(dir.path).size(), 5u);  // target, victim, the three planted
}

// A process killed outright (SIGKILL) leaves its temporary file; the next write to that name
// removes it, but only once its process is gone and it has been still for 10 s. Other names,
// live processes' files and fresh files stay.
TEST(WriteFileAtomically, TemporariesAbandonedByDeadProcessesAreRemoved) {
    TempDir dir;
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) ::_exit(0);
    ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // a pid that is gone
    const std::string dead = std::to_string(child), live = std::to_string(::getppid());
    auto plant = [&](const std::string& name, bool old) {
        writeFile(dir.path / name, "partial");
        if (old) {
            const timespec times[2] = {{std::time(nullptr) - 60, 0}, {std::time(nullptr) - 60, 0}};
            ASSERT_EQ(::utimensat(AT_FDCWD, (dir.path / name).c_str(), times, 0), 0);
        }
    };
    plant(".out.txt." + dead + ".7.tmp", true);    // abandoned: removed
    plant(".out.txt." + dead + ".8.tmp", false);   // still changing: kept
    plant(".out.txt." + live + ".9.tmp", true);    // its process lives: kept
    plant(".other.txt." + dead + ".7.tmp", true);  // another target's: kept
    plant(".out.txt." + dead + ".x.tmp", true);    // not a temporary name: kept
    writeFileAtomically(dir.path / "out.txt", "new", false);
    EXPECT_EQ(readFile(dir.path / "out.txt"), "new");
    const std::vector<std::string> expected = {
        ".other.txt." + dead + ".7.tmp", ".out.txt." + dead + ".8.tmp",
        ".out.txt." + dead + ".x.tmp", ".out.txt." + live + ".9.tmp", "out.txt"};
    std::vector<std::string> found = listDir(dir.path);
    std::sort(found.begin(), found.end());
    std::vector<std::string> want = expected;
    std::sort(want.begin(), want.end());
    EXPECT_EQ(found, want);
}

// What a SIGINT or SIGTERM handler calls: the temporary file of a write in progress is removed
// (here the write is stopped right after creating it), and nothing else.
TEST(WriteFileAtomically, TheTemporaryFileOfAWriteInProgressCanBeRemoved) {
    TempDir dir;
    writeFile(dir.path / "out.txt", "old");
    static std::string seen;
    static bool existedThen = false;
    detail::setAfterTemporaryCreated([](const char* tmp) {
        seen = tmp;
        existedThen = ::access(tmp, F_OK) == 0;
        removeTemporaryFilesInProgress();
        throw std::runtime_error("interrupted");  // the process would end here
    });
    EXPECT_THROW(writeFileAtomically(dir.path / "out.txt", "new", false), std::runtime_error);
    detail::setAfterTemporaryCreated(nullptr);
    EXPECT_TRUE(existedThen) << seen;
    EXPECT_FALSE(fs::exists(seen)) << seen;
    EXPECT_EQ(listDir(dir.path), std::vector<std::string>{"out.txt"});
    EXPECT_EQ(readFile(dir.path / "out.txt"), "old");
    // Once a write is done its file is no longer the handler's to remove.
    writeFileAtomically(dir.path / "out.txt", "new", false);
    removeTemporaryFilesInProgress();
    EXPECT_EQ(readFile(dir.path / "out.txt"), "new");
}

TEST(WriteFileAtomically, ASymlinkAtTheTargetIsReplacedNotWrittenThrough) {
    TempDir dir;
    const fs::path target = dir.path / "out.txt", victim = dir.path / "victim.txt";
    writeFile(victim, "precious");
    fs::create_symlink(victim, target);
    writeFileAtomically(target, "new", false);
    EXPECT_FALSE(fs::is_symlink(target));
    EXPECT_EQ(readFile(target), "new");
    EXPECT_EQ(readFile(victim), "precious");
}

// Found by fuzzing, as root: `play --stats /dev/full` renamed a JSON file over the device node.
// A pipe (what a test can make without root) stands for every name that is not a file.
TEST(WriteFileAtomically, ADevicePipeOrSocketAtTheTargetIsNeverReplaced) {
    TempDir dir;
    const fs::path pipe = dir.path / "stats.json", source = dir.path / "source.txt";
    ASSERT_EQ(::mkfifo(pipe.c_str(), 0644), 0);
    writeFile(source, "x");
    const std::string expected = pipe.string() +
                                 ": is a device, pipe or socket, not a file: not "
                                 "replaced: " +
                                 std::strerror(EINVAL);
    auto messageOf = [](auto&& f) {
        try {
            f();
        } catch (const FileWriteError& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    EXPECT_EQ(messageOf([&] { writeFileAtomically(pipe, "{}", false); }), expected);
    EXPECT_EQ(messageOf([&] { ensureWritable(pipe); }), expected);
    EXPECT_EQ(messageOf([&] { replaceWithHardLink(source, pipe, false); }), expected);
    EXPECT_TRUE(fs::is_fifo(pipe));
    EXPECT_EQ(listDir(dir.path).size(), 2u);  // no temporary file left
}

TEST(WriteFileAtomically, FailuresNameTheRealPathAndTheReasonAndLeaveNothingBehind) {
    TempDir dir;
    const fs::path missing = dir.path / "no-such-folder" / "out.txt";
    try {
        writeFileAtomically(missing, "x", true);
        FAIL() << "no error";
    } catch (const FileWriteError& e) {
        EXPECT_EQ(e.code(), ENOENT);
        EXPECT_NE(std::string(e.what()).find(missing.string() + ": "), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find(std::strerror(ENOENT)), std::string::npos) << e.what();
    }
    // Renaming a file over a folder fails after the temporary file was written.
    fs::create_directory(dir.path / "afolder");
    try {
        writeFileAtomically(dir.path / "afolder", "x", false);
        FAIL() << "no error";
    } catch (const FileWriteError& e) {
        EXPECT_NE(std::string(e.what()).find((dir.path / "afolder").string() + ": cannot replace"),
                  std::string::npos)
            << e.what();
        EXPECT_EQ(std::string(e.what()).find(".tmp"), std::string::npos) << e.what();
    }
    EXPECT_EQ(listDir(dir.path), std::vector<std::string>{"afolder"});
}

TEST(WriteFileAtomically, AWriteThatRunsOutOfSpaceKeepsTheOldFile) {
    TempDir dir;
    const fs::path target = dir.path / "out.bin";
    writeFile(target, "old contents");
    // A file size limit makes write() fail part-way (EFBIG) as a full disk would.
    struct sigaction ignore {
    }, previous{};
    ignore.sa_handler = SIG_IGN;
    ASSERT_EQ(::sigaction(SIGXFSZ, &ignore, &previous), 0);
    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string message;
    int code = 0;
    try {
        writeFileAtomically(target, std::string(100000, 'y'), true);
    } catch (const FileWriteError& e) {
        message = e.what();
        code = e.code();
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    ::sigaction(SIGXFSZ, &previous, nullptr);
    EXPECT_EQ(code, EFBIG) << message;
    EXPECT_NE(message.find(target.string() + ": cannot write: " + std::strerror(EFBIG)),
              std::string::npos)
        << message;
    EXPECT_EQ(readFile(target), "old contents");
    EXPECT_EQ(listDir(dir.path), std::vector<std::string>{"out.bin"});
}

TEST(WriteFileAtomically, EnsureWritableChecksTheFolderAndCreatesNothing) {
    TempDir dir;
    EXPECT_NO_THROW(ensureWritable(dir.path / "later.glb"));
    EXPECT_TRUE(listDir(dir.path).empty());
    auto expectError = [](const fs::path& p, int code) {
        try {
            ensureWritable(p);
            ADD_FAILURE() << p << ": no error";
        } catch (const FileWriteError& e) {
            EXPECT_EQ(e.code(), code) << e.what();
            EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": ", 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find(std::strerror(code)), std::string::npos)
                << e.what();
        }
    };
    expectError(dir.path / "missing" / "out.glb", ENOENT);
    writeFile(dir.path / "file", "");
    expectError(dir.path / "file" / "out.glb", ENOTDIR);
    fs::create_directory(dir.path / "sub");
    expectError(dir.path / "sub", EISDIR);
    // A name the file system cannot hold is found before any work (found by QA: after it).
    expectError(dir.path / (std::string(252, 'n') + ".obj"), ENAMETOOLONG);
    EXPECT_NO_THROW(ensureWritable(dir.path / (std::string(251, 'n') + ".obj")));
    if (::geteuid() != 0) {  // root may write anywhere
        fs::permissions(dir.path / "sub", fs::perms::owner_read | fs::perms::owner_exec);
        expectError(dir.path / "sub" / "out.glb", EACCES);
    }
}

TEST(WriteFileAtomically, ExportsLeaveNoTemporaryFilesAndReplaceASymlink) {
    TempDir dir;
    Mesh m;
    m.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
    m.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    std::vector<std::string> expected;
    for (const std::string& ext : exportExtensions()) {
        const fs::path p = dir.path / ("mesh" + ext);
        exportMesh(m, p);
        EXPECT_GT(fs::file_size(p), 0u) << p;
        expected.push_back(p.filename().string());
    }
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(listDir(dir.path), expected);
    // GLB header: magic, version 2, total length.
    const std::string glb = readFile(dir.path / "mesh.glb");
    ASSERT_GE(glb.size(), 12u);
    EXPECT_EQ(glb.substr(0, 4), "glTF");
    uint32_t version, length;
    std::memcpy(&version, glb.data() + 4, 4);
    std::memcpy(&length, glb.data() + 8, 4);
    EXPECT_EQ(version, 2u);
    EXPECT_EQ(length, glb.size());
    // OpenVDB files start with the magic number 0x56444220.
    const std::string vdb = readFile(dir.path / "mesh.vdb");
    ASSERT_GE(vdb.size(), 8u);
    int64_t magic;
    std::memcpy(&magic, vdb.data(), 8);
    EXPECT_EQ(magic, 0x56444220);

    const fs::path victim = dir.path / "victim.txt", link = dir.path / "link.stl";
    writeFile(victim, "precious");
    fs::create_symlink(victim, link);
    exportMesh(m, link);
    EXPECT_EQ(readFile(victim), "precious");
    EXPECT_FALSE(fs::is_symlink(link));

    const fs::path bad = dir.path / "missing" / "mesh.obj";
    try {
        exportMesh(m, bad);
        FAIL() << "no error";
    } catch (const ExportError& e) {
        EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(std::strerror(ENOENT)), std::string::npos) << e.what();
    }
}

// ------------------------------------------------------------------------------ lock

std::string conflictMessage(const fs::path& dir, pid_t pid) {
    return dir.string() + ": the project is open in another vsculpt (pid " + std::to_string(pid) +
           "); close it first";
}

TEST(ProjectLock, TwoLocksInOneProcessConflict) {
    TempDir dir;
    {
        ProjectLock first(dir.path);
        EXPECT_TRUE(first.held());
        EXPECT_EQ(readFile(lockPath(dir.path)), std::to_string(::getpid()) + "\n");
        try {
            ProjectLock second(dir.path);
            FAIL() << "second lock taken";
        } catch (const ProjectError& e) {
            EXPECT_EQ(std::string(e.what()), conflictMessage(dir.path, ::getpid()));
        }
        EXPECT_THROW(ProjectLock(dir.path, ProjectLock::Mode::ReadOnly), ProjectError);
        ProjectLock moved = std::move(first);
        EXPECT_THROW(ProjectLock{dir.path}, ProjectError);
    }
    // Released, and the pid cleared: a later conflict never names a gone process.
    EXPECT_EQ(readFile(lockPath(dir.path)), "");
    ProjectLock again(dir.path);
    EXPECT_TRUE(again.held());
}

TEST(ProjectLock, ReadersShareAndExcludeAWriter) {
    TempDir dir;
    ProjectLock a(dir.path, ProjectLock::Mode::ReadOnly), b(dir.path, ProjectLock::Mode::ReadOnly);
    EXPECT_TRUE(a.held());
    EXPECT_TRUE(b.held());
    try {
        ProjectLock writer(dir.path);
        FAIL() << "writer locked a project being read";
    } catch (const ProjectError& e) {
        EXPECT_EQ(std::string(e.what()),
                  dir.path.string() +
                      ": the project is open read-only in another vsculpt; close it first");
    }
}

TEST(ProjectLock, AnotherProcessHoldingTheLockIsRefusedUntilItDies) {
    TempDir dir;
    int ready[2], release[2];
    ASSERT_EQ(::pipe(ready), 0);
    ASSERT_EQ(::pipe(release), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        int status = 0;
        try {
            ProjectLock lock(dir.path);
            char c = 'r';
            if (::write(ready[1], &c, 1) != 1) status = 3;
            if (::read(release[0], &c, 1) != 1) status = 4;
        } catch (...) {
            status = 2;
        }
        ::_exit(status);
    }
    char c;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    try {
        ProjectLock lock(dir.path);
        ADD_FAILURE() << "locked a project another process holds";
    } catch (const ProjectError& e) {
        EXPECT_EQ(std::string(e.what()), conflictMessage(dir.path, child));
    }
    try {
        ProjectLock lock(dir.path, ProjectLock::Mode::ReadOnly);
        ADD_FAILURE() << "read-locked a project another process writes";
    } catch (const ProjectError& e) {
        EXPECT_EQ(std::string(e.what()), conflictMessage(dir.path, child));
    }
    // kill -9: the kernel releases the lock with the process, no stale lock is left.
    ::kill(child, SIGKILL);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status));
    for (int fd : {ready[0], ready[1], release[0], release[1]})
        ::close(fd);
    ProjectLock lock(dir.path);
    EXPECT_TRUE(lock.held());
}

TEST(ProjectLock, ASymlinkAtTheLockIsRefused) {
    TempDir dir;
    const fs::path victim = dir.path / "victim.txt";
    writeFile(victim, "precious");
    fs::create_symlink(victim, lockPath(dir.path));
    try {
        ProjectLock lock(dir.path);
        FAIL() << "followed the symlink";
    } catch (const ProjectError& e) {
        EXPECT_NE(std::string(e.what()).find(lockPath(dir.path).string() + ": "), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("symbolic link"), std::string::npos) << e.what();
    }
    EXPECT_EQ(readFile(victim), "precious");
}

TEST(ProjectLock, AFolderThatCannotBeWrittenIsReadWithoutALock) {
    TempDir dir;
    fs::create_directory(dir.path / "ro");
    // In a child, as an unprivileged user when running as root (root may write anywhere).
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        if (::geteuid() == 0) {
            if (::setgid(65534) != 0 || ::setuid(65534) != 0) ::_exit(10);
        } else {
            ::chmod((dir.path / "ro").c_str(), 0555);
        }
        int status = 0;
        try {
            ProjectLock reader(dir.path / "ro", ProjectLock::Mode::ReadOnly);
            if (reader.held()) status = 2;
        } catch (...) {
            status = 3;
        }
        if (::access(lockPath(dir.path / "ro").c_str(), F_OK) == 0) status = 4;
        try {
            ProjectLock writer(dir.path / "ro");
            status = 5;
        } catch (const ProjectError& e) {
            if (std::string(e.what()).find(std::strerror(EACCES)) == std::string::npos) status = 6;
        }
        ::_exit(status);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "2: locked, 3: threw, 4: created the lock file, "
                                         "5: writer locked, 6: writer's message, 10: setuid";
}

// ------------------------------------------------------------------------------ save & recover

TEST(Project, SaveKeepsBackupsAndReadProjectReplaysTheJournal) {
    TempDir dir;
    Sculptor s;
    std::vector<Entry> final;
    {
        JournalWriter j(journalPath(dir.path), 0);
        s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        s.save(dir.path, j);
        // A first save has no older snapshot: the new one is also its own backup.
        EXPECT_EQ(readFile(snapshotBackupPath(dir.path)), readFile(snapshotPath(dir.path)));
        s.stroke(j, ToolOp::Carve, 3, {0, -15, 0}, {0, 15, 0});
        s.save(dir.path, j);
        s.stroke(j, ToolOp::Add, 4, {-10, 10, 0}, {10, 10, 0});
        s.save(dir.path, j);
        s.stroke(j, ToolOp::Add, 5, {0, 0, -25}, {0, 0, 25});
        s.undo(j);
        s.stroke(j, ToolOp::Add, 2, {5, 5, 0}, {10, 5, 0});
        final = entries(s.sculpture);
    }
    EXPECT_EQ(readSnapshot(snapshotPath(dir.path)).lastSequence, 3u);
    EXPECT_EQ(readSnapshot(snapshotBackupPath(dir.path)).lastSequence, 2u);
    const JournalContents backupJournal = readJournal(journalBackupPath(dir.path));
    ASSERT_EQ(backupJournal.records.size(), 1u);
    EXPECT_EQ(backupJournal.records[0].sequence, 3u);
    EXPECT_EQ(readJournal(journalPath(dir.path)).records.size(), 3u);  // 4, 5, 6

    Reopened r(dir.path);
    EXPECT_TRUE(r.project.warnings.empty()) << allWarnings(r.project);
    EXPECT_FALSE(r.project.fromBackup);
    ASSERT_EQ(r.project.records.size(), 3u);
    EXPECT_EQ(r.project.records.front().sequence, 4u);
    EXPECT_EQ(r.project.lastSequence(), 6u);
    EXPECT_EQ(r.project.journalValidBytes, fs::file_size(journalPath(dir.path)));
    EXPECT_EQ(entries(*r.sculpture), final);
    EXPECT_EQ(r.history.done().size(), 4u);
    EXPECT_EQ(r.history.undone().size(), 0u);

    // The backup route reaches the same state: the backup pair plus journal.vjl.
    fs::remove(snapshotPath(dir.path));
    Reopened b(dir.path);
    EXPECT_TRUE(b.project.fromBackup);
    ASSERT_EQ(b.project.warnings.size(), 1u) << allWarnings(b.project);
    EXPECT_EQ(b.project.warnings[0].find(snapshotPath(dir.path).string() + ": missing"), 0u);
    EXPECT_EQ(b.project.records.size(), 4u);
    EXPECT_EQ(entries(*b.sculpture), final);
    EXPECT_EQ(b.project.journalValidBytes, fs::file_size(journalPath(dir.path)));
}

// Found by fuzzing: one flipped bit in record 2 of 6 and the next session's writer cut the
// journal after record 1, so records 3-6 (intact, but not replayable without 2) were gone for
// good. The writer now keeps the file as it was before it cuts anything.
TEST(Project, AJournalCutAfterDamageIsFirstKeptWhole) {
    TempDir dir;
    Sculptor s;
    {
        JournalWriter j(journalPath(dir.path), 0);
        EXPECT_TRUE(j.keptDamaged().empty());  // a new journal: nothing to keep
        for (int i = 0; i < 6; ++i)
            s.stroke(j, ToolOp::Add, 4, {-20.0 + 5 * i, 0, 0}, {20, 5.0 * i, 0});
    }
    const fs::path journal = journalPath(dir.path);
    std::string bytes = readFile(journal);
    const JournalContents clean = readJournal(journal);
    ASSERT_EQ(clean.records.size(), 6u);
    // A clean journal is continued where it ends: nothing cut, nothing kept.
    ASSERT_EQ(readProject(dir.path).journalValidBytes, bytes.size());
    EXPECT_TRUE(JournalWriter(journal, bytes.size()).keptDamaged().empty());
    EXPECT_FALSE(fs::exists(dir.path / "journal.vjl.damaged"));
    // A byte inside the second record: readProject keeps record 1 only.
    const size_t second = bytes.size() / 6 + bytes.size() / 12;
    bytes[second] ^= 0x10;
    writeFile(journal, bytes);
    const RecoveredProject damaged = readProject(dir.path);
    EXPECT_EQ(damaged.records.size(), 1u) << allWarnings(damaged);
    ASSERT_LT(damaged.journalValidBytes, bytes.size());
    for (const char* name : {"journal.vjl.damaged", "journal.vjl.damaged-2"}) {
        JournalWriter j(journal, damaged.journalValidBytes);
        EXPECT_EQ(j.keptDamaged(), dir.path / name);
        EXPECT_EQ(readFile(dir.path / name), bytes);  // every byte, the damaged record too
        EXPECT_EQ(fs::file_size(journal), damaged.journalValidBytes);
        writeFile(journal, bytes);  // damaged again: the next copy takes the next name
    }
}

// Found by fuzzing: a pipe at journal.vjl blocked opening forever, a snapshot symlinked to
// /dev/zero read until memory ran out. Only regular files are read: the pipe is refused at
// once, the snapshot that is none falls back to the backup like a damaged one.
TEST(Project, ProjectFilesThatAreNotRegularFilesAreNeverRead) {
    TempDir dir;
    Sculptor s;
    s.strokeSavedTwice(dir.path);  // the backup pair holds the stroke too
    const std::vector<Entry> saved = entries(s.sculpture);
    fs::remove(snapshotPath(dir.path));
    fs::create_symlink("/dev/zero", snapshotPath(dir.path));
    const Reopened r(dir.path);
    EXPECT_TRUE(r.project.fromBackup);
    ASSERT_FALSE(r.project.warnings.empty());
    EXPECT_EQ(r.project.warnings[0].rfind(
                  snapshotPath(dir.path).string() + ": not a regular file; recovered from", 0),
              0u)
        << allWarnings(r.project);
    EXPECT_EQ(entries(*r.sculpture), saved);
    fs::remove(journalPath(dir.path));
    ASSERT_EQ(::mkfifo(journalPath(dir.path).c_str(), 0644), 0);
    try {
        readProject(dir.path);
        ADD_FAILURE() << "a pipe read as a journal";
    } catch (const ProjectError& e) {
        EXPECT_EQ(std::string(e.what()).substr(0, journalPath(dir.path).string().size() + 21),
                  journalPath(dir.path).string() + ": not a regular file;");
    }
}

TEST(Project, ADamagedSnapshotIsRecoveredFromTheBackupAndBothJournals) {
    TempDir dir;
    Sculptor s;
    std::vector<Entry> final;
    {
        JournalWriter j(journalPath(dir.path), 0);
        s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        s.save(dir.path, j);
        s.stroke(j, ToolOp::Carve, 3, {0, -15, 0}, {0, 15, 0});
        s.save(dir.path, j);
        s.stroke(j, ToolOp::Add, 5, {0, 0, -25}, {0, 0, 25});
        final = entries(s.sculpture);
    }
    const fs::path snap = snapshotPath(dir.path);
    std::string bytes = readFile(snap);
    bytes[bytes.size() / 2] ^= 0x40;
    writeFile(snap, bytes);

    Reopened r(dir.path);
    EXPECT_TRUE(r.project.fromBackup);
    ASSERT_FALSE(r.project.warnings.empty());
    EXPECT_NE(r.project.warnings[0].find(snap.string() + ": checksum mismatch"), std::string::npos)
        << allWarnings(r.project);
    EXPECT_NE(r.project.warnings[0].find("recovered from"), std::string::npos);
    ASSERT_EQ(r.project.records.size(), 2u);  // 2 from journal.vjl.bak, 3 from journal.vjl
    EXPECT_EQ(r.project.records[0].sequence, 2u);
    EXPECT_EQ(entries(*r.sculpture), final);
    const std::string snapBefore = readFile(snap),
                      backupBefore = readFile(snapshotBackupPath(dir.path));

    // Saving the recovered state never turns the damaged file into the backup.
    {
        JournalWriter j(journalPath(dir.path), r.project.journalValidBytes);
        saveProject(dir.path, configToJson(r.sculpture->config()), r.project.lastSequence(),
                    *r.sculpture, r.history, j);
    }
    EXPECT_NE(readFile(snap), snapBefore);
    EXPECT_NE(readFile(snapshotBackupPath(dir.path)), backupBefore);
    EXPECT_EQ(readFile(snap), readFile(snapshotBackupPath(dir.path)));
    Reopened clean(dir.path);
    EXPECT_TRUE(clean.project.warnings.empty()) << allWarnings(clean.project);
    EXPECT_EQ(entries(*clean.sculpture), final);
    // And that backup works in turn.
    fs::remove(snap);
    Reopened again(dir.path);
    EXPECT_TRUE(again.project.fromBackup);
    EXPECT_EQ(entries(*again.sculpture), final);
}

// Found by QA: the backup snapshot copied over the snapshot (a restore from an older copy)
// opened as that older state with journal.vjl's edits dropped, and the next save rotated
// journal.vjl.bak, the only copy of the edits between the two, away. journal.vjl.bak now
// bridges the gap.
TEST(Project, AnOlderSnapshotIsBridgedByTheBackupJournal) {
    TempDir dir;
    Sculptor s;
    std::vector<Entry> final;
    {
        JournalWriter j(journalPath(dir.path), 0);
        s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        s.save(dir.path, j);
        s.stroke(j, ToolOp::Carve, 3, {0, -15, 0}, {0, 15, 0});
        s.stroke(j, ToolOp::Add, 4, {-10, 10, 0}, {10, 10, 0});
        s.save(dir.path, j);
        s.stroke(j, ToolOp::Add, 5, {0, 0, -25}, {0, 0, 25});
        s.stroke(j, ToolOp::Carve, 2, {5, 5, 0}, {10, 5, 0});
        final = entries(s.sculpture);
    }
    ASSERT_EQ(readSnapshot(snapshotBackupPath(dir.path)).lastSequence, 1u);
    fs::copy_file(snapshotBackupPath(dir.path), snapshotPath(dir.path),
                  fs::copy_options::overwrite_existing);

    Reopened r(dir.path);
    EXPECT_FALSE(r.project.fromBackup);
    ASSERT_EQ(r.project.records.size(), 4u);  // 2, 3 from journal.vjl.bak; 4, 5 from journal.vjl
    EXPECT_EQ(r.project.records.front().sequence, 2u);
    EXPECT_EQ(r.project.lastSequence(), 5u);
    EXPECT_EQ(entries(*r.sculpture), final);
    ASSERT_EQ(r.project.warnings.size(), 1u) << allWarnings(r.project);
    EXPECT_EQ(r.project.warnings[0],
              snapshotPath(dir.path).string() + " is older than " + journalPath(dir.path).string() +
                  ": edits 2 to 3 taken from " + journalBackupPath(dir.path).string());
    EXPECT_EQ(r.project.journalValidBytes, fs::file_size(journalPath(dir.path)));

    // A save of what was recovered keeps every edit.
    {
        JournalWriter j(journalPath(dir.path), r.project.journalValidBytes);
        saveProject(dir.path, configToJson(r.sculpture->config()), r.project.lastSequence(),
                    *r.sculpture, r.history, j);
    }
    Reopened clean(dir.path);
    EXPECT_TRUE(clean.project.warnings.empty()) << allWarnings(clean.project);
    EXPECT_EQ(entries(*clean.sculpture), final);
    EXPECT_EQ(clean.history.done().size(), 5u);
}

// Found by QA: a journal emptied by a file system (0 bytes) opened without a word, its edits
// gone; one cut inside its header was named. Both are named now.
TEST(Project, AnEmptyOrHeaderlessJournalIsNamed) {
    TempDir dir;
    Sculptor s;
    {
        JournalWriter j(journalPath(dir.path), 0);
        s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        s.save(dir.path, j);
        s.stroke(j, ToolOp::Carve, 3, {0, -15, 0}, {0, 15, 0});
    }
    for (size_t size : {0, 3}) {
        fs::resize_file(journalPath(dir.path), size);
        const RecoveredProject p = readProject(dir.path);
        EXPECT_TRUE(p.records.empty());
        ASSERT_EQ(p.warnings.size(), 1u) << allWarnings(p);
        EXPECT_EQ(p.warnings[0],
                  journalPath(dir.path).string() +
                      (size == 0 ? ": empty (0 bytes)" : ": shorter than its header") +
                      "; treated as a journal without records");
    }
}

TEST(Project, EveryMomentOfASaveRecovers) {
    // The folder as a crash would leave it after each step of saveProject, rebuilt by hand.
    TempDir base;
    Sculptor s;
    std::vector<Entry> final;
    {
        JournalWriter j(journalPath(base.path), 0);
        s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        s.save(base.path, j);
        s.stroke(j, ToolOp::Carve, 3, {0, -15, 0}, {0, 15, 0});
        s.stroke(j, ToolOp::Add, 5, {0, 0, -25}, {0, 0, 25});
        final = entries(s.sculpture);
    }
    const std::string config = configToJson(s.sculpture.config());
    for (int step = 0; step <= 4; ++step) {
        TempDir dir("_step" + std::to_string(step));
        for (const auto& e : fs::directory_iterator(base.path))
            fs::copy(e.path(), dir.path / e.path().filename());
        const fs::path snap = snapshotPath(dir.path), journal = journalPath(dir.path);
        if (step >= 1) replaceWithHardLink(snap, snapshotBackupPath(dir.path), true);
        if (step >= 2) replaceWithHardLink(journal, journalBackupPath(dir.path), true);
        if (step >= 3) writeSnapshot(snap, config, s.sequence, s.sculpture, s.history);
        if (step >= 4) {
            JournalWriter j(journal, fs::file_size(journal));
            j.reset();
        }
        Reopened r(dir.path);
        EXPECT_TRUE(r.project.warnings.empty())
            << "step " << step << ": " << allWarnings(r.project);
        EXPECT_EQ(entries(*r.sculpture), final) << "step " << step;
        EXPECT_EQ(r.history.done().size(), 3u) << "step " << step;
        // The backup route too, as if the snapshot were lost at that moment.
        if (step >= 1) {
            fs::remove(snap);
            Reopened b(dir.path);
            EXPECT_TRUE(b.project.fromBackup);
            EXPECT_EQ(entries(*b.sculpture), final) << "backup, step " << step;
        }
    }
}

TEST(Project, ResetStartsANewFileSoALinkedOldJournalKeepsItsRecords) {
    TempDir dir;
    JournalWriter j(journalPath(dir.path), 0);
    j.append(strokeRecord(1, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
    replaceWithHardLink(journalPath(dir.path), journalBackupPath(dir.path), true);
    j.reset();
    j.append(strokeRecord(2, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
    const JournalContents old = readJournal(journalBackupPath(dir.path));
    const JournalContents now = readJournal(journalPath(dir.path));
    ASSERT_EQ(old.records.size(), 1u);
    EXPECT_EQ(old.records[0].sequence, 1u);
    ASSERT_EQ(now.records.size(), 1u);
    EXPECT_EQ(now.records[0].sequence, 2u);
}

TEST(Project, ABackgroundSaveLosesNoEditMadeWhileItsSnapshotWasWritten) {
    // A background save (Session::saveInBackground): the snapshot of sequence S is written
    // while edits S+1... go on being journaled, then the journal restarts with those edits.
    // Every moment reads back as every edit, by the snapshot and by the backup route.
    TempDir dir;
    Sculptor s;
    JournalWriter j(journalPath(dir.path), 0);
    s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
    s.save(dir.path, j);  // an older snapshot, so the background save rotates backups
    s.stroke(j, ToolOp::Carve, 3, {0, -15, 0}, {0, 15, 0});
    s.stroke(j, ToolOp::Add, 4, {-10, 10, 0}, {10, 10, 0});
    const std::string config = configToJson(s.sculpture.config());
    auto everyEditReadsBack = [&](const std::string& when) {
        const std::vector<Entry> live = entries(s.sculpture);
        Reopened r(dir.path);
        EXPECT_TRUE(r.project.warnings.empty()) << when << ": " << allWarnings(r.project);
        EXPECT_EQ(r.project.lastSequence(), s.sequence) << when;
        EXPECT_EQ(entries(*r.sculpture), live) << when;
        EXPECT_EQ(r.history.done().size(), s.history.done().size()) << when;
        EXPECT_EQ(r.history.undone().size(), s.history.undone().size()) << when;
        const fs::path tmp = dir.path.string() + "_backup_route";
        fs::remove_all(tmp);
        fs::copy(dir.path, tmp);
        fs::remove(snapshotPath(tmp));
        Reopened b(tmp);
        EXPECT_TRUE(b.project.fromBackup) << when;
        EXPECT_EQ(b.project.lastSequence(), s.sequence) << when;
        EXPECT_EQ(entries(*b.sculpture), live) << when << ", by the backup";
        fs::remove_all(tmp);
    };

    // The save is asked for at S = 3: what it writes is copied now.
    const uint64_t saved = s.sequence;
    const uint64_t keepFrom = j.bytes();
    const std::unique_ptr<Sculpture> copy = s.sculpture.clone();
    const History historyCopy = s.history;
    s.stroke(j, ToolOp::Add, 5, {0, 0, -25}, {0, 0, 25});  // while it is being written
    s.undo(j);
    writeProjectSnapshot(dir.path, config, saved, *copy, historyCopy);
    EXPECT_EQ(readSnapshot(snapshotPath(dir.path)).lastSequence, saved);
    everyEditReadsBack("snapshot written, journal not restarted");
    s.stroke(j, ToolOp::Add, 2, {5, 5, 0}, {10, 5, 0});  // before the frame finishes it
    everyEditReadsBack("an edit after the snapshot");

    j.reset(keepFrom);
    std::vector<uint64_t> kept;
    for (const JournalRecord& r : readJournal(journalPath(dir.path)).records)
        kept.push_back(r.sequence);
    EXPECT_EQ(kept, (std::vector<uint64_t>{4, 5, 6}));  // exactly the edits after the snapshot
    EXPECT_EQ(readJournal(journalBackupPath(dir.path)).records.back().sequence, 6u);
    everyEditReadsBack("journal restarted");
    s.undo(j);
    s.stroke(j, ToolOp::Carve, 2, {0, 0, 18}, {6, 0, 18});
    everyEditReadsBack("edits after the restart");

    // An offset that is not between records of this journal is a bug of the caller.
    EXPECT_THROW(j.reset(j.bytes() + 1), std::logic_error);
    EXPECT_THROW(j.reset(3), std::logic_error);
}

TEST(Project, ReadProjectWritesNothingAndAGapEndsTheRecovery) {
    TempDir dir;
    {
        JournalWriter j(journalPath(dir.path), 0);
        // Never saved: sequence 1 must come first, and 3 does not follow it.
        j.append(strokeRecord(3, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
        j.append(strokeRecord(4, ToolOp::Add, 4, {0, 9, 0}, {9, 9, 0}));
    }
    const std::string before = readFile(journalPath(dir.path));
    const auto names = listDir(dir.path);
    const RecoveredProject p = readProject(dir.path);
    EXPECT_FALSE(p.snapshot);
    EXPECT_TRUE(p.records.empty());
    ASSERT_EQ(p.warnings.size(), 1u);
    EXPECT_EQ(p.warnings[0], journalPath(dir.path).string() +
                                 ": record 1 (sequence 3): expected sequence 1 next; it and the "
                                 "rest were dropped");
    EXPECT_EQ(p.journalValidBytes, 8u);  // a writer continues right after the header
    EXPECT_EQ(readFile(journalPath(dir.path)), before);
    EXPECT_EQ(listDir(dir.path), names);

    const RecoveredProject none = readProject(dir.path / "never-created");
    EXPECT_FALSE(none.snapshot);
    EXPECT_TRUE(none.records.empty());
    EXPECT_FALSE(fs::exists(dir.path / "never-created"));
    writeFile(dir.path / "afile", "");
    EXPECT_THROW(readProject(dir.path / "afile"), ProjectError);
}

TEST(Project, NothingUsableIsAnErrorNamingBothFiles) {
    TempDir dir;
    Sculptor s;
    s.strokeSavedTwice(dir.path);
    writeFile(snapshotPath(dir.path), "VSSNAP01 but not much else");
    writeFile(snapshotBackupPath(dir.path), "VSSNAP02 from the future.....");
    try {
        readProject(dir.path);
        FAIL() << "no error";
    } catch (const ProjectError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(snapshotPath(dir.path).string() + ": "), std::string::npos) << m;
        EXPECT_NE(m.find(snapshotBackupPath(dir.path).string() + ": byte 0: a snapshot of format "
                                                                 "version 02"),
                  std::string::npos)
            << m;
    }
}

// A journal.vjl that is not a journal is refused (the writer would overwrite it), and the
// message says what to do (found by QA: no way out was named).
TEST(Project, AForeignJournalIsRefusedWithTheWayOut) {
    TempDir dir;
    Sculptor s;
    s.strokeSavedTwice(dir.path);
    writeFile(journalPath(dir.path), "#!/bin/sh\necho not a journal\n");
    try {
        readProject(dir.path);
        FAIL() << "no error";
    } catch (const ProjectError& e) {
        EXPECT_EQ(std::string(e.what()),
                  journalPath(dir.path).string() +
                      ": byte 0: not a vsculpt journal (bad magic); the project was not opened and "
                      "is left as it is (move journal.vjl out of the folder to open the project "
                      "without it)");
    }
}

TEST(Project, WritersRefuseWhatReadersWouldRefuse) {
    TempDir dir;
    JournalWriter j(journalPath(dir.path), 0);
    j.append(strokeRecord(1, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
    const auto size = fs::file_size(journalPath(dir.path));
    JournalRecord bad = strokeRecord(2, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0});
    bad.samples[1].y = std::numeric_limits<double>::quiet_NaN();
    try {
        j.append(bad);
        FAIL() << "NaN journaled";
    } catch (const ProjectError& e) {
        EXPECT_NE(std::string(e.what()).find("sample 2 y is NaN"), std::string::npos) << e.what();
    }
    EXPECT_THROW(j.append(strokeRecord(3, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0})), ProjectError);
    EXPECT_EQ(fs::file_size(journalPath(dir.path)), size);
    {
        // A new writer takes any first sequence number below kMaxSequence, none from it on.
        JournalWriter fresh(dir.path / "fresh.vjl", 0);
        EXPECT_THROW(fresh.append(strokeRecord(kMaxSequence, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0})),
                     ProjectError);
        fresh.append(strokeRecord(kMaxSequence - 1, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
        EXPECT_EQ(readJournal(dir.path / "fresh.vjl").records.size(), 1u);
    }
    j.append(strokeRecord(2, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
    EXPECT_EQ(readJournal(journalPath(dir.path)).records.size(), 2u);
    // Continuing beyond the file's end would put zeros where records go.
    EXPECT_THROW(JournalWriter(journalPath(dir.path), fs::file_size(journalPath(dir.path)) + 1),
                 ProjectError);

    Sculpture sculpture(config());
    History history;
    writeSnapshot(snapshotPath(dir.path), "{}", 0, sculpture, history);
    const std::string good = readFile(snapshotPath(dir.path));
    sculpture.store().set(4, LatticeCoord{1, 2, 3}, std::numeric_limits<float>::infinity());
    try {
        writeSnapshot(snapshotPath(dir.path), "{}", 0, sculpture, history);
        FAIL() << "infinite weight written";
    } catch (const ProjectError& e) {
        EXPECT_NE(std::string(e.what()).find("skeleton 1: weight is infinite"), std::string::npos)
            << e.what();
    }
    EXPECT_EQ(readFile(snapshotPath(dir.path)), good);
    EXPECT_THROW(
        writeSnapshot(snapshotPath(dir.path), "{}", kMaxSequence, Sculpture(config()), history),
        ProjectError);
    EXPECT_EQ(readFile(snapshotPath(dir.path)), good);
}

TEST(Project, FilesInTheDocumentedFormatStillOpen) {
    // Built byte by byte from docs/projects.md, independently of the writer.
    TempDir dir;
    std::string snap = "VSSNAP01";
    append(snap, uint64_t(1));
    const std::string cfg = configToJson(config());
    append(snap, uint32_t(cfg.size()));
    snap += cfg;
    append(snap, uint64_t(1));
    append(snap, uint8_t(4));
    append(snap, int32_t(1));
    append(snap, int32_t(-2));
    append(snap, int32_t(3));
    append(snap, 0.5f);
    append(snap, uint32_t(0));
    append(snap, uint32_t(0));
    append(snap, uint32_t(0));
    fixSnapshotChecksum(snap);
    writeFile(snapshotPath(dir.path), snap);
    std::string undo, stroke;
    append(stroke, uint64_t(2));
    append(stroke, uint8_t(1));
    append(stroke, uint8_t(1));  // carve
    append(stroke, uint8_t(3));
    append(stroke, uint32_t(2));
    for (double v : {1.0, 2.0, 3.0, 4.0, 5.0, 6.0})
        append(stroke, v);
    append(stroke, uint32_t(0));
    append(undo, uint64_t(3));
    append(undo, uint8_t(2));
    writeFile(journalPath(dir.path), journalFile({stroke, undo}));

    const RecoveredProject p = readProject(dir.path);
    EXPECT_TRUE(p.warnings.empty()) << allWarnings(p);
    ASSERT_TRUE(p.snapshot);
    EXPECT_EQ(p.snapshot->lastSequence, 1u);
    ASSERT_EQ(p.snapshot->skeletons.size(), 1u);
    EXPECT_EQ(p.snapshot->skeletons[0].coord, (LatticeCoord{1, -2, 3}));
    EXPECT_EQ(p.snapshot->skeletons[0].weight, 0.5f);
    ASSERT_EQ(p.records.size(), 2u);
    EXPECT_EQ(p.records[0].tool, ToolOp::Carve);
    EXPECT_EQ(p.records[0].level, 3);
    EXPECT_EQ(p.records[0].samples[1], Vec3(4, 5, 6));
    EXPECT_EQ(p.records[1].op, JournalOp::Undo);
}

// ------------------------------------------------------------------------------ validation

/// Five records: stroke, stroke, stroke (5 samples), solid (3 changes), stroke.
std::vector<std::string> samplePayloads(const fs::path& dir) {
    {
        JournalWriter j(journalPath(dir), 0);
        j.append(strokeRecord(1, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
        j.append(strokeRecord(2, ToolOp::Carve, 3, {0, 0, 0}, {0, 9, 0}));
        j.append(strokeRecord(3, ToolOp::Add, 5, {0, 0, 0}, {0, 0, 12}));
        JournalRecord solid;
        solid.sequence = 4;
        solid.op = JournalOp::Solid;
        solid.solidLevel = 4;
        solid.changes = {{4, {0, 0, 0}, std::nullopt, 1.0f},
                         {4, {1, 0, 0}, 0.5f, 1.0f},
                         {3, {-1, 2, 0}, std::nullopt, 0.75f}};
        j.append(solid);
        j.append(strokeRecord(5, ToolOp::Add, 2, {0, 0, 0}, {3, 3, 3}));
    }
    return journalPayloads(readFile(journalPath(dir)));
}

// Payload offsets (docs/projects.md): u64 sequence, u8 op, then u8 tool, u8 level, u32 n,
// n x 3 f64 samples, u32 m, m x (u8 level, 3 x i32, u8 flags, f32 before, f32 after).
constexpr size_t kOp = 8, kTool = 9, kLevel = 10, kCount = 11, kSamples = 15;
constexpr size_t sampleAt(int i, int axis) {
    return kSamples + size_t(i) * 24 + size_t(axis) * 8;
}
constexpr size_t changeAt(int i) {
    return kSamples + 4 + size_t(i) * 22;  // a solid has no samples
}

struct BadValue {
    const char* name;
    size_t record;  ///< 1-based
    std::function<void(std::string&)> damage;
    std::string expected;  ///< after "record N (sequence N): "
};

TEST(Project, ABadValueDropsItsRecordAndTheRestAndIsNamed) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<BadValue> cases = {
        {"NaN sample", 3, [&](std::string& p) { put(p, sampleAt(2, 0), nan); },
         "sample 3 x is NaN"},
        {"infinite sample", 3, [&](std::string& p) { put(p, sampleAt(1, 1), -inf); },
         "sample 2 y is infinite"},
        {"huge sample", 3, [](std::string& p) { put(p, sampleAt(0, 2), 2.0e6); },
         "sample 1 z is 2e+06 mm, not within +-1e+06 mm"},
        {"level 9", 3, [](std::string& p) { put(p, kLevel, uint8_t(9)); },
         "level 9 is outside 1..7"},
        {"level 0", 1, [](std::string& p) { put(p, kLevel, uint8_t(0)); },
         "level 0 is outside 1..7"},
        {"unknown tool", 2, [](std::string& p) { put(p, kTool, uint8_t(7)); },
         "tool operation 7 is unknown"},
        {"unknown operation", 3, [](std::string& p) { put(p, kOp, uint8_t(9)); },
         "operation 9 is unknown"},
        {"absurd sample count", 3, [](std::string& p) { put(p, kCount, uint32_t(3'000'000)); },
         "3000000 samples, more than the 2000000 a stroke may hold"},
        {"sample count beyond the data", 3, [](std::string& p) { put(p, kCount, uint32_t(1000)); },
         "unexpected end of data"},
        {"NaN weight", 4, [&](std::string& p) { put(p, changeAt(1) + 18, float(nan)); },
         "change 2: weight after is NaN"},
        {"huge weight", 4, [](std::string& p) { put(p, changeAt(1) + 14, 1e30f); },
         "change 2: weight before is 1e+30, beyond +-1e+06"},
        {"lattice overflow", 4, [](std::string& p) { put(p, changeAt(2) + 1, int32_t(1 << 23)); },
         "change 3: lattice x 8388608 is beyond +-4194303"},
        {"lattice int32 min", 4,
         [](std::string& p) { put(p, changeAt(0) + 9, std::numeric_limits<int32_t>::min()); },
         "change 1: lattice z -2147483648 is beyond +-4194303"},
        {"change level", 4, [](std::string& p) { put(p, changeAt(1), uint8_t(8)); },
         "change 2: level 8 is outside 1..7"},
        {"solid level", 4, [](std::string& p) { put(p, kLevel, uint8_t(0)); },
         "level 0 is outside 1..7"},
        {"change flags", 4, [](std::string& p) { put(p, changeAt(0) + 13, uint8_t(6)); },
         "change 1: unknown flags 6"},
        {"stroke with changes", 5,
         [](std::string& p) {
             const size_t m = p.size() - 4;
             put(p, m, uint32_t(1));
             p += std::string(22, '\0');
             put(p, m + 4, uint8_t(4));
         },
         "a stroke with 1 vertex changes (only solids have them)"},
        {"trailing bytes", 5, [](std::string& p) { p += "xyz"; }, "3 bytes after the record's end"},
    };
    TempDir dir;
    const std::vector<std::string> good = samplePayloads(dir.path);
    ASSERT_EQ(good.size(), 5u);
    const fs::path journal = journalPath(dir.path);
    // The control: the test's own framing and checksum reproduce a journal that reads whole.
    writeFile(journal, journalFile(good));
    ASSERT_EQ(readJournal(journal).records.size(), 5u) << readJournal(journal).warning;

    for (const BadValue& c : cases) {
        SCOPED_TRACE(c.name);
        std::vector<std::string> payloads = good;
        c.damage(payloads[c.record - 1]);
        writeFile(journal, journalFile(payloads));
        const JournalContents j = readJournal(journal);
        ASSERT_EQ(j.records.size(), c.record - 1) << j.warning;
        for (size_t i = 0; i < j.records.size(); ++i)
            EXPECT_EQ(j.records[i].sequence, i + 1);
        EXPECT_EQ(j.validBytes, journalEnd(payloads, c.record - 1));
        const std::string seq = std::to_string(c.record);
        EXPECT_EQ(j.warning, journal.string() + ": record " + seq + " (sequence " + seq +
                                 "): " + c.expected + "; it and the rest were dropped");

        // Through readProject: the same warning; a writer continues after the good records.
        const RecoveredProject p = readProject(dir.path);
        EXPECT_EQ(p.records.size(), c.record - 1);
        EXPECT_EQ(allWarnings(p), j.warning + "\n");
        EXPECT_EQ(p.journalValidBytes, j.validBytes);
    }
    // A sequence out of order is caught the same way.
    std::vector<std::string> payloads = good;
    put(payloads[1], 0, uint64_t(7));
    writeFile(journal, journalFile(payloads));
    EXPECT_EQ(readJournal(journal).warning,
              journal.string() +
                  ": record 2 (sequence 7): out of order (expected sequence 2); it and the rest "
                  "were dropped");
}

TEST(Project, ABadSnapshotValueIsNamedAndTheBackupIsUsed) {
    TempDir dir;
    Sculptor s;
    std::vector<Entry> afterFirst;
    {
        JournalWriter j(journalPath(dir.path), 0);
        s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        s.save(dir.path, j);
        afterFirst = entries(s.sculpture);
        s.stroke(j, ToolOp::Add, 3, {0, -15, 0}, {0, 15, 0});
        s.save(dir.path, j);
    }
    const fs::path snap = snapshotPath(dir.path);
    const std::string good = readFile(snap);
    const std::string cfg = configToJson(config());
    // Layout: magic, u64 last sequence, u32 + config, u64 n, n x 17-byte skeletons, then the
    // undo stack's u32 count and its first step (u8 tool, u8 level, u32 n, samples ...).
    const size_t skeletons = 8 + 8 + 4 + cfg.size() + 8;
    uint64_t n;
    std::memcpy(&n, good.data() + skeletons - 8, 8);
    ASSERT_GT(n, 2u);
    const size_t undo = skeletons + n * 17 + 4;
    struct Case {
        const char* name;
        std::function<void(std::string&)> damage;
        std::string expected;
    };
    const std::vector<Case> cases = {
        {"NaN weight",
         [&](std::string& b) { put(b, skeletons + 13, std::numeric_limits<float>::quiet_NaN()); },
         "skeleton 1: weight is NaN"},
        {"level", [&](std::string& b) { put(b, skeletons + 17, uint8_t(9)); },
         "skeleton 2: level 9 is outside 1..7"},
        {"lattice", [&](std::string& b) { put(b, skeletons + 1, int32_t(1 << 22)); },
         "skeleton 1: lattice x 4194304 is beyond +-4194303"},
        {"count", [&](std::string& b) { put(b, skeletons - 8, uint64_t(1) << 60); },
         "1152921504606846976 skeletons, more than the file holds"},
        // Found by fuzzing: 2^64 - 1 opened, and every edit then failed (the next record's
        // sequence number wrapped to 0), blamed on the script's line.
        {"last sequence", [&](std::string& b) { put(b, 8, ~uint64_t(0)); },
         "last sequence 18446744073709551615 out of range"},
        {"history sample",
         [&](std::string& b) { put(b, undo + 6, std::numeric_limits<double>::infinity()); },
         "undo step 1: sample 1 x is infinite"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        std::string bytes = good;
        c.damage(bytes);
        fixSnapshotChecksum(bytes);
        writeFile(snap, bytes);
        try {
            readSnapshot(snap);
            ADD_FAILURE() << "read";
        } catch (const ProjectError& e) {
            EXPECT_EQ(std::string(e.what()).rfind(snap.string() + ": " + c.expected + " (byte ", 0),
                      0u)
                << e.what();
        }
        Reopened r(dir.path);
        EXPECT_TRUE(r.project.fromBackup);
        ASSERT_FALSE(r.project.warnings.empty());
        EXPECT_NE(r.project.warnings[0].find(c.expected), std::string::npos)
            << allWarnings(r.project);
        EXPECT_EQ(entries(*r.sculpture), entries(s.sculpture));
    }
}

// ------------------------------------------------------------------------------ redo

TEST(Project, RedoSurvivesReopeningAfterStrokeAndUndo) {
    TempDir dir;
    Sculptor s;
    std::vector<Entry> beforeUndo, afterUndo;
    {
        JournalWriter j(journalPath(dir.path), 0);
        s.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        beforeUndo = entries(s.sculpture);
        s.undo(j);
        afterUndo = entries(s.sculpture);
    }
    ASSERT_NE(beforeUndo, afterUndo);
    // From the journal alone (never saved).
    {
        Reopened r(dir.path);
        ASSERT_EQ(r.project.records.size(), 2u);
        EXPECT_EQ(entries(*r.sculpture), afterUndo);
        ASSERT_TRUE(r.history.canRedo());
        r.history.redo(*r.sculpture);
        EXPECT_EQ(entries(*r.sculpture), beforeUndo);
    }
    // From a snapshot taken after the undo (the redo stack travels in it).
    {
        JournalWriter j(journalPath(dir.path), fs::file_size(journalPath(dir.path)));
        s.save(dir.path, j);
        Reopened r(dir.path);
        EXPECT_TRUE(r.project.records.empty());
        EXPECT_EQ(entries(*r.sculpture), afterUndo);
        ASSERT_TRUE(r.history.canRedo());
        r.history.redo(*r.sculpture);
        EXPECT_EQ(entries(*r.sculpture), beforeUndo);
        // Redone as a journal record, then reopened once more.
        s.redo(j);
        Reopened again(dir.path);
        EXPECT_EQ(entries(*again.sculpture), beforeUndo);
        EXPECT_FALSE(again.history.canRedo());
        ASSERT_TRUE(again.history.canUndo());
        again.history.undo(*again.sculpture);
        EXPECT_EQ(entries(*again.sculpture), afterUndo);
    }
    // A snapshot holding the stroke, the undo only in the journal.
    {
        TempDir other("_other");
        Sculptor t;
        JournalWriter j(journalPath(other.path), 0);
        t.stroke(j, ToolOp::Add, 4, {-20, 0, 0}, {20, 0, 0});
        t.save(other.path, j);
        t.undo(j);
        Reopened r(other.path);
        ASSERT_EQ(r.project.records.size(), 1u);
        EXPECT_EQ(entries(*r.sculpture), afterUndo);
        ASSERT_TRUE(r.history.canRedo());
        r.history.redo(*r.sculpture);
        EXPECT_EQ(entries(*r.sculpture), beforeUndo);
    }
}

// The journal's fdatasync takes milliseconds on a laptop's disk; a stroke's end on the frame
// thread must not wait for it. append() writes the record (a crash of the process keeps it) and
// returns while the flusher thread is still flushing: here the flush is held until every append
// has returned, which would hang (ctest's timeout) if append() waited for it.
TEST(Project, AppendReturnsWhileTheFlushIsStillGoingOn) {
    TempDir dir;
    std::promise<void> release;
    std::shared_future<void> released = release.get_future().share();
    std::atomic<int> flushes{0}, heldAt{-1};
    JournalWriter j(journalPath(dir.path), 0, [&](int fd) {
        if (heldAt.load() < 0) heldAt = flushes.load();
        ++flushes;
        released.wait();
        return ::fdatasync(fd);
    });
    for (uint64_t seq = 1; seq <= 3; ++seq)
        j.append(strokeRecord(seq, ToolOp::Add, 4, {0, 0, 0}, {9, double(seq), 0}));
    // Written, though not yet flushed: another reader (the next session after a crash of this
    // process) finds all three.
    EXPECT_EQ(readJournal(journalPath(dir.path)).records.size(), 3u);
    EXPECT_LE(flushes.load(), 1);  // the flusher is held in its first flush at most
    release.set_value();
    j.waitDurable();
    EXPECT_GE(flushes.load(), 1);
    EXPECT_EQ(readJournal(journalPath(dir.path)).records.size(), 3u);
}

// A flush that fails (EIO: the disk may not hold the records) is reported by waitDurable() and
// by every later append, which writes nothing, until a save restarts the journal on disk.
TEST(Project, AFailedFlushIsReportedAndStopsTheJournalUntilASave) {
    TempDir dir;
    std::atomic<bool> fail{true};
    JournalWriter j(journalPath(dir.path), 0, [&](int fd) {
        if (!fail.load()) return ::fdatasync(fd);
        errno = EIO;
        return -1;
    });
    j.append(strokeRecord(1, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
    try {
        j.waitDurable();
        ADD_FAILURE() << "a failed flush was not reported";
    } catch (const ProjectError& e) {
        EXPECT_EQ(std::string(e.what()),
                  journalPath(dir.path).string() + ": cannot flush: " + std::strerror(EIO));
    }
    try {
        j.append(strokeRecord(2, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
        ADD_FAILURE() << "a record was appended after a failed flush";
    } catch (const ProjectError& e) {
        EXPECT_NE(std::string(e.what()).find("record with sequence 2 not written: an earlier "
                                             "record could not be flushed to disk"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(readJournal(journalPath(dir.path)).records.size(), 1u);
    // A save wrote the snapshot durably and restarts the journal the same way: it goes on.
    fail = false;
    j.reset();
    j.append(strokeRecord(2, ToolOp::Add, 4, {0, 0, 0}, {9, 0, 0}));
    j.waitDurable();
    EXPECT_EQ(readJournal(journalPath(dir.path)).records.size(), 1u);
}

// A background save restarts the journal on its own thread (Session::saveInBackground) while
// the frame goes on appending. reset() writes and flushes the new file without the writer's
// lock: here its flush is held until two appends from this thread have returned (they would
// hang, ctest's timeout, if reset() held the lock through it). The new journal then holds the
// kept records and those two, in order, and the old file (linked as the backup) has them all.
TEST(Project, AppendsGoOnWhileAResetFlushesTheNewJournal) {
    TempDir dir;
    std::promise<void> resetFlushing, release;
    std::shared_future<void> released = release.get_future().share();
    std::atomic<bool> holding{false};
    JournalWriter j(journalPath(dir.path), 0, [&](int fd) {
        char link[64], target[4096] = {};
        std::snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
        const ssize_t n = ::readlink(link, target, sizeof target - 1);
        const std::string name = n > 0 ? std::string(target, size_t(n)) : std::string();
        if (name.ends_with(".restart") && !holding.exchange(true)) {
            resetFlushing.set_value();
            released.wait();
        }
        return ::fdatasync(fd);
    });
    for (uint64_t seq = 1; seq <= 3; ++seq)
        j.append(strokeRecord(seq, ToolOp::Add, 4, {0, 0, 0}, {9, double(seq), 0}));
    const uint64_t keepFrom = j.bytes();  // records 1-3 are in the snapshot
    replaceWithHardLink(journalPath(dir.path), journalBackupPath(dir.path), true);
    j.append(strokeRecord(4, ToolOp::Add, 4, {0, 0, 0}, {9, 4, 0}));
    std::thread save([&] { j.reset(keepFrom); });
    resetFlushing.get_future().wait();
    j.append(strokeRecord(5, ToolOp::Add, 4, {0, 0, 0}, {9, 5, 0}));
    j.append(strokeRecord(6, ToolOp::Add, 4, {0, 0, 0}, {9, 6, 0}));
    release.set_value();
    save.join();
    j.append(strokeRecord(7, ToolOp::Add, 4, {0, 0, 0}, {9, 7, 0}));
    j.waitDurable();
    auto sequences = [](const fs::path& p) {
        std::vector<uint64_t> out;
        for (const JournalRecord& r : readJournal(p).records)
            out.push_back(r.sequence);
        return out;
    };
    EXPECT_EQ(sequences(journalPath(dir.path)), (std::vector<uint64_t>{4, 5, 6, 7}));
    EXPECT_EQ(sequences(journalBackupPath(dir.path)), (std::vector<uint64_t>{1, 2, 3, 4, 5, 6}));
    EXPECT_FALSE(fs::exists(journalPath(dir.path).string() + ".restart"));
}

TEST(Project, ARestartLeftByACrashIsRemovedWhenTheJournalIsOpened) {
    TempDir dir;
    const fs::path restart = journalPath(dir.path).string() + ".restart";
    {
        JournalWriter j(journalPath(dir.path), 0);
        j.append(strokeRecord(1, ToolOp::Add, 4, {0, 0, 0}, {9, 1, 0}));
        j.waitDurable();
    }
    // What a crash during reset's flush leaves: a half-written restart beside the journal.
    std::ofstream(restart) << "VSJL half a restart";
    const JournalContents before = readJournal(journalPath(dir.path));
    JournalWriter j(journalPath(dir.path), before.validBytes);
    EXPECT_FALSE(fs::exists(restart));
    j.append(strokeRecord(2, ToolOp::Add, 4, {0, 0, 0}, {9, 2, 0}));
    j.waitDurable();
    EXPECT_EQ(readJournal(journalPath(dir.path)).records.size(), 2u);
}

}  // namespace
}  // namespace vsculpt::core
