// SPDX-License-Identifier: MIT
#include "vsculpt/core/Project.h"

#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/Sculpture.h"
#include "vsculpt/core/WriteFileAtomically.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace vsculpt::core {

namespace {

namespace fs = std::filesystem;

constexpr char kJournalMagic[8] = {'V', 'S', 'J', 'R', 'N', 'L', '0', '1'};
constexpr char kSnapshotMagic[8] = {'V', 'S', 'S', 'N', 'A', 'P', '0', '1'};
constexpr size_t kMagicBytes = sizeof kJournalMagic;
constexpr size_t kVersionBytes = 2;            // the magic's last two characters
constexpr uint32_t kRecordMark = 0x5245434Bu;  // "RECK"
constexpr uint32_t kMaxRecordBytes = 64u << 20;
constexpr size_t kFrameBytes = 12;  // mark, payload length, payload CRC

// Encoded sizes, to check a count against the bytes left before allocating for it.
constexpr size_t kSampleBytes = 24;    // 3 x f64
constexpr size_t kChangeBytes = 22;    // u8 level, 3 x i32, u8 flags, 2 x f32
constexpr size_t kSkeletonBytes = 17;  // u8 level, 3 x i32, f32
constexpr size_t kMinStrokeBytes = 10;

const std::string& journalHeader() {
    static const std::string h(kJournalMagic, kMagicBytes);
    return h;
}

/// Little-endian byte writer/reader (the file format is LE on every platform).
class Writer {
  public:
    std::string bytes;
    template <typename T>
    void pod(T v) {
        static_assert(std::is_trivially_copyable_v<T>);
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        bytes.append(b, sizeof(T));
    }
    void str(const std::string& s) {
        pod(uint32_t(s.size()));
        bytes += s;
    }
    void vec(const Vec3& v) {
        pod(v.x);
        pod(v.y);
        pod(v.z);
    }
};

/// A structure or value problem met while decoding; the caller names the file and entry.
class DecodeError : public std::runtime_error {
  public:
    DecodeError(const std::string& why, size_t at) : std::runtime_error(why), pos(at) {}
    size_t pos;
};

class Reader {
  public:
    Reader(const std::string& data, size_t begin, size_t end)
        : mData(data), mPos(begin), mEnd(end) {}
    template <typename T>
    T pod() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, mData.data() + mPos, sizeof(T));
        mPos += sizeof(T);
        return v;
    }
    std::string str() {
        const uint32_t n = pod<uint32_t>();
        need(n);
        std::string s = mData.substr(mPos, n);
        mPos += n;
        return s;
    }
    Vec3 vec() {
        const double x = pod<double>(), y = pod<double>(), z = pod<double>();
        return Vec3(x, y, z);
    }
    size_t pos() const { return mPos; }
    size_t left() const { return mEnd - mPos; }
    [[noreturn]] void fail(const std::string& why) const { throw DecodeError(why, mPos); }
    void need(size_t n) const {
        if (left() < n) fail("unexpected end of data");
    }

  private:
    const std::string& mData;
    size_t mPos, mEnd;
};

uint32_t crc(const char* p, size_t n) {
    return uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(p), uInt(n)));
}

std::string errnoText(int err) {
    return std::strerror(err);
}

}  // namespace

std::string readProjectFile(const fs::path& path) {
    // O_NONBLOCK: opening a pipe planted at a project file's name must not wait for a writer;
    // only a regular file is read (a pipe would block the read, /dev/zero never end).
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) throw ProjectError(path.string() + ": cannot open: " + errnoText(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        throw ProjectError(path.string() + ": not a regular file");
    }
    std::string data;
    char buf[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int err = errno;
            ::close(fd);
            throw ProjectError(path.string() + ": cannot read: " + errnoText(err));
        }
        if (n == 0) break;
        data.append(buf, size_t(n));
    }
    ::close(fd);
    return data;
}

namespace {

/// Throws ProjectError unless `data` starts with `magic`; names another version as such.
void checkMagic(const std::string& data, const char (&magic)[8], const fs::path& path,
                const char* what) {
    if (data.size() >= kMagicBytes && std::memcmp(data.data(), magic, kMagicBytes) == 0) return;
    const size_t family = kMagicBytes - kVersionBytes;
    if (data.size() >= kMagicBytes && std::memcmp(data.data(), magic, family) == 0)
        throw ProjectError(path.string() + ": byte 0: a " + what + " of format version " +
                           data.substr(family, kVersionBytes) + "; this vsculpt reads version " +
                           std::string(magic + family, kVersionBytes));
    throw ProjectError(path.string() + ": byte 0: not a vsculpt " + what + " (bad magic)");
}

void writeAllOrThrow(int fd, const std::string& data, const fs::path& path) {
    size_t done = 0;
    while (done < data.size()) {
        const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw ProjectError(path.string() + ": write failed: " + errnoText(errno));
        }
        if (n == 0) throw ProjectError(path.string() + ": write failed: no progress");
        done += size_t(n);
    }
}

void syncFolder(const fs::path& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
        const int err = errno;
        if (fd >= 0) ::close(fd);
        throw ProjectError(dir.string() + ": cannot flush the folder to disk: " + errnoText(err));
    }
    ::close(fd);
}

fs::path folderOf(const fs::path& path) {
    return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

// ------------------------------------------------------------------------------ value checks
// Each returns why a value cannot be stored, or "" when it can. The same checks run before
// writing and after reading, so nothing written is ever refused when read back.

std::string number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string pointProblem(const Vec3& p) {
    for (int a = 0; a < 3; ++a) {
        const std::string axis(1, "xyz"[a]);
        if (std::isnan(p[a])) return axis + " is NaN";
        if (std::isinf(p[a])) return axis + " is infinite";
        if (!(std::abs(p[a]) < kMaxProjectCoordinateMm))
            return axis + " is " + number(p[a]) + " mm, not within +-" +
                   number(kMaxProjectCoordinateMm) + " mm";
    }
    return {};
}

std::string weightProblem(float w) {
    if (std::isnan(w)) return "is NaN";
    if (std::isinf(w)) return "is infinite";
    if (std::abs(w) > kMaxSkeletonWeight)
        return "is " + number(w) + ", beyond +-" + number(kMaxSkeletonWeight);
    return {};
}

std::string levelProblem(int level) {
    if (level < 1 || level > kLevelCount)
        return "level " + std::to_string(level) + " is outside 1.." + std::to_string(kLevelCount);
    return {};
}

std::string coordProblem(const LatticeCoord& c) {
    const int32_t v[3] = {c.x, c.y, c.z};
    for (int a = 0; a < 3; ++a)
        if (v[a] < -kMaxLatticeCoord || v[a] > kMaxLatticeCoord)
            return std::string("lattice ") + "xyz"[a] + " " + std::to_string(v[a]) +
                   " is beyond +-" + std::to_string(kMaxLatticeCoord);
    return {};
}

std::string changeProblem(const SkeletonChange& c) {
    if (std::string p = levelProblem(c.level); !p.empty()) return p;
    if (std::string p = coordProblem(c.coord); !p.empty()) return p;
    if (c.before)
        if (std::string p = weightProblem(*c.before); !p.empty()) return "weight before " + p;
    if (c.after)
        if (std::string p = weightProblem(*c.after); !p.empty()) return "weight after " + p;
    return {};
}

std::string samplesProblem(const std::vector<Vec3>& samples) {
    if (samples.size() > kMaxStrokeSamples)
        return std::to_string(samples.size()) + " samples, more than the " +
               std::to_string(kMaxStrokeSamples) + " a stroke may hold";
    for (size_t i = 0; i < samples.size(); ++i)
        if (std::string p = pointProblem(samples[i]); !p.empty())
            return "sample " + std::to_string(i + 1) + " " + p;
    return {};
}

std::string changesProblem(const std::vector<SkeletonChange>& changes) {
    for (size_t i = 0; i < changes.size(); ++i)
        if (std::string p = changeProblem(changes[i]); !p.empty())
            return "change " + std::to_string(i + 1) + ": " + p;
    return {};
}

std::string strokeProblem(const StrokeRecord& r) {
    if (std::string p = levelProblem(r.level); !p.empty()) return p;
    if (r.op != ToolOp::Add && r.op != ToolOp::Carve && r.op != ToolOp::Smooth)
        return "tool operation " + std::to_string(int(r.op)) + " is unknown";
    if (int(r.mirror) < 0 || int(r.mirror) > 3)
        return "mirror axis " + std::to_string(int(r.mirror)) + " is unknown";
    if (std::string p = samplesProblem(r.samples); !p.empty()) return p;
    return changesProblem(r.changes);
}

std::string recordProblem(const JournalRecord& r) {
    if (r.sequence == 0) return "sequence 0 (sequence numbers start at 1)";
    if (r.sequence >= kMaxSequence)
        return "sequence " + std::to_string(r.sequence) + " out of range";
    switch (r.op) {
        case JournalOp::Stroke:
            if (std::string p = levelProblem(r.level); !p.empty()) return p;
            if (r.tool != ToolOp::Add && r.tool != ToolOp::Carve && r.tool != ToolOp::Smooth)
                return "tool operation " + std::to_string(int(r.tool)) + " is unknown";
            if (int(r.mirror) < 0 || int(r.mirror) > 3)
                return "mirror axis " + std::to_string(int(r.mirror)) + " is unknown";
            return samplesProblem(r.samples);
        case JournalOp::Solid:
            if (std::string p = levelProblem(r.solidLevel); !p.empty()) return "solid " + p;
            if (r.changes.size() > kMaxJournalSolidChanges)
                return std::to_string(r.changes.size()) + " vertex changes, more than the " +
                       std::to_string(kMaxJournalSolidChanges) + " a solid may hold";
            return changesProblem(r.changes);
        case JournalOp::Undo:
        case JournalOp::Redo:
            return {};
    }
    return "operation " + std::to_string(int(r.op)) + " is unknown";
}

// ------------------------------------------------------------------------------ encoding

// The operation byte: bits 0-3 the operation (0 add, 1 carve, 2 solid, 3 smooth), bits 4-5
// the stroke's mirror axis (0 none, 1 x, 2 y, 3 z). Files written before the smooth and
// mirror tools only have 0..2.
void encodeStroke(Writer& w, const StrokeRecord& r) {
    const uint8_t op = r.solid ? 2 : r.op == ToolOp::Add ? 0 : r.op == ToolOp::Carve ? 1 : 3;
    w.pod(uint8_t(op | (uint8_t(r.mirror) << 4)));
    w.pod(uint8_t(r.level));
    w.pod(uint32_t(r.samples.size()));
    for (const Vec3& p : r.samples)
        w.vec(p);
    w.pod(uint32_t(r.changes.size()));
    for (const SkeletonChange& c : r.changes) {
        w.pod(uint8_t(c.level));
        w.pod(c.coord.x);
        w.pod(c.coord.y);
        w.pod(c.coord.z);
        w.pod(uint8_t((c.before ? 1 : 0) | (c.after ? 2 : 0)));
        w.pod(c.before.value_or(0.0f));
        w.pod(c.after.value_or(0.0f));
    }
}

/// Decodes one stroke or solid and checks its values; DecodeError says which field is bad.
StrokeRecord decodeStroke(Reader& r) {
    StrokeRecord s;
    const uint8_t opByte = r.pod<uint8_t>();
    const uint8_t op = opByte & 0x0F, mirror = opByte >> 4;
    if (op > 3) r.fail("tool operation " + std::to_string(op) + " is unknown");
    if (mirror > 3) r.fail("mirror axis " + std::to_string(mirror) + " is unknown");
    if (op == 2 && mirror != 0) r.fail("a solid with a mirror axis");
    s.op = op == 1 ? ToolOp::Carve : op == 3 ? ToolOp::Smooth : ToolOp::Add;
    s.mirror = MirrorAxis(mirror);
    s.solid = op == 2;
    s.level = r.pod<uint8_t>();
    if (std::string p = levelProblem(s.level); !p.empty()) r.fail(p);
    const uint32_t n = r.pod<uint32_t>();
    if (n > kMaxStrokeSamples)
        r.fail(std::to_string(n) + " samples, more than the " + std::to_string(kMaxStrokeSamples) +
               " a stroke may hold");
    r.need(size_t(n) * kSampleBytes);
    s.samples.reserve(n);
    for (uint32_t i = 0; i < n; ++i) {
        s.samples.push_back(r.vec());
        if (std::string p = pointProblem(s.samples.back()); !p.empty())
            r.fail("sample " + std::to_string(i + 1) + " " + p);
    }
    const uint32_t m = r.pod<uint32_t>();
    r.need(size_t(m) * kChangeBytes);
    s.changes.reserve(m);
    for (uint32_t i = 0; i < m; ++i) {
        SkeletonChange c;
        c.level = r.pod<uint8_t>();
        c.coord.x = r.pod<int32_t>();
        c.coord.y = r.pod<int32_t>();
        c.coord.z = r.pod<int32_t>();
        const uint8_t has = r.pod<uint8_t>();
        const float before = r.pod<float>(), after = r.pod<float>();
        const std::string at = "change " + std::to_string(i + 1) + ": ";
        if (has & ~3u) r.fail(at + "unknown flags " + std::to_string(has));
        if (has & 1) c.before = before;
        if (has & 2) c.after = after;
        if (std::string p = changeProblem(c); !p.empty()) r.fail(at + p);
        s.changes.push_back(c);
    }
    return s;
}

/// The payload after the sequence number; leaves `rec.sequence` as set by the caller.
void decodeRecordBody(Reader& r, JournalRecord& rec) {
    const uint8_t op = r.pod<uint8_t>();
    if (op < 1 || op > 4) r.fail("operation " + std::to_string(op) + " is unknown");
    rec.op = JournalOp(op);
    if (rec.op == JournalOp::Stroke || rec.op == JournalOp::Solid) {
        StrokeRecord s = decodeStroke(r);
        if (s.solid != (rec.op == JournalOp::Solid)) r.fail("stroke and solid records mixed up");
        if (s.solid) {
            if (!s.samples.empty())
                r.fail("a solid with " + std::to_string(s.samples.size()) + " tool samples");
            if (s.changes.size() > kMaxJournalSolidChanges)
                r.fail(std::to_string(s.changes.size()) + " vertex changes, more than the " +
                       std::to_string(kMaxJournalSolidChanges) + " a solid may hold");
            rec.solidLevel = s.level;
            rec.changes = std::move(s.changes);
        } else {
            if (!s.changes.empty())
                r.fail("a stroke with " + std::to_string(s.changes.size()) +
                       " vertex changes (only solids have them)");
            rec.tool = s.op;
            rec.mirror = s.mirror;
            rec.level = s.level;
            rec.samples = std::move(s.samples);
        }
    }
    if (r.left() != 0) r.fail(std::to_string(r.left()) + " bytes after the record's end");
}

std::string encodeRecord(const JournalRecord& rec) {
    Writer payload;
    payload.pod(rec.sequence);
    payload.pod(uint8_t(rec.op));
    if (rec.op == JournalOp::Stroke) {
        StrokeRecord s;
        s.op = rec.tool;
        s.mirror = rec.mirror;
        s.level = rec.level;
        s.samples = rec.samples;
        encodeStroke(payload, s);
    } else if (rec.op == JournalOp::Solid) {
        StrokeRecord s;
        s.solid = true;
        s.level = rec.solidLevel;
        s.changes = rec.changes;
        encodeStroke(payload, s);
    }
    return std::move(payload.bytes);
}

/// The snapshot file's bytes; throws ProjectError (naming `path` and the entry) for a value
/// readSnapshot would refuse, before anything is written.
std::string encodeSnapshot(const fs::path& path, const std::string& configJson,
                           uint64_t lastSequence, const Sculpture& sculpture,
                           const History& history) {
    if (lastSequence >= kMaxSequence)
        throw ProjectError(path.string() + ": last sequence " + std::to_string(lastSequence) +
                           " out of range; nothing written");
    Writer w;
    w.bytes.append(kSnapshotMagic, kMagicBytes);
    w.pod(lastSequence);
    w.str(configJson);
    w.pod(uint64_t(sculpture.store().vertexCount()));
    std::string problem;
    size_t index = 0;
    sculpture.store().forEach([&](const SkeletonEntry& e) {
        ++index;
        if (problem.empty()) {
            std::string p = levelProblem(e.level);
            if (p.empty()) p = coordProblem(e.coord);
            if (p.empty()) {
                p = weightProblem(e.weight);
                if (!p.empty()) p = "weight " + p;
            }
            if (!p.empty()) problem = "skeleton " + std::to_string(index) + ": " + p;
        }
        w.pod(uint8_t(e.level));
        w.pod(e.coord.x);
        w.pod(e.coord.y);
        w.pod(e.coord.z);
        w.pod(e.weight);
    });
    const std::pair<const char*, HistorySteps> stacks[] = {{"undo step ", history.done()},
                                                           {"redo step ", history.undone()}};
    for (const auto& [name, stack] : stacks) {
        w.pod(uint32_t(stack.size()));
        for (size_t i = 0; i < stack.size(); ++i) {
            const StrokeRecord& r = stack[i];
            if (problem.empty())
                if (std::string p = strokeProblem(r); !p.empty())
                    problem = name + std::to_string(i + 1) + ": " + p;
            encodeStroke(w, r);
        }
    }
    if (!problem.empty())
        throw ProjectError(path.string() + ": not written: " + problem +
                           " (the previous snapshot is kept)");
    w.pod(crc(w.bytes.data(), w.bytes.size()));
    return std::move(w.bytes);
}

// ------------------------------------------------------------------------------ journal scan

struct JournalScan {
    std::vector<JournalRecord> records;
    std::vector<uint64_t> ends;  ///< byte offset just after each record
    uint64_t headerBytes = 0;    ///< 8 when the file has a header, else 0
    uint64_t validBytes = 0;
    std::string warning;
};

JournalScan scanJournal(const fs::path& path) {
    JournalScan out;
    std::error_code ec;
    if (!fs::exists(path, ec)) return out;
    const std::string data = readProjectFile(path);
    if (data.size() < kMagicBytes) {
        // Empty too: the writer writes the header before any record, so an empty file is
        // what a file system left after a crash or a truncation, and edits may be missing.
        out.warning = path.string() +
                      (data.empty() ? ": empty (0 bytes)" : ": shorter than its header") +
                      "; treated as a journal without records";
        return out;
    }
    checkMagic(data, kJournalMagic, path, "journal");
    size_t pos = kMagicBytes;
    out.headerBytes = out.validBytes = pos;
    uint64_t expected = 0;
    while (pos < data.size()) {
        const size_t index = out.records.size() + 1;
        // Framing damage: the record's own bytes cannot be trusted, so only the offset is named.
        auto torn = [&](const std::string& why) {
            out.warning = path.string() + ": byte " + std::to_string(pos) + ": record " +
                          std::to_string(index) + " " + why + "; kept the " +
                          std::to_string(out.records.size()) + " complete record(s) before it";
        };
        if (data.size() - pos < kFrameBytes) {
            torn("is truncated");
            break;
        }
        uint32_t mark, len, sum;
        std::memcpy(&mark, data.data() + pos, 4);
        std::memcpy(&len, data.data() + pos + 4, 4);
        std::memcpy(&sum, data.data() + pos + 8, 4);
        if (mark != kRecordMark || len > kMaxRecordBytes) {
            torn("has a damaged header");
            break;
        }
        if (data.size() - pos - kFrameBytes < len) {
            torn("is truncated");
            break;
        }
        if (crc(data.data() + pos + kFrameBytes, len) != sum) {
            torn("fails its checksum");
            break;
        }
        JournalRecord rec;
        bool haveSequence = false;
        std::string problem;
        try {
            Reader r(data, pos + kFrameBytes, pos + kFrameBytes + len);
            rec.sequence = r.pod<uint64_t>();
            haveSequence = true;
            decodeRecordBody(r, rec);
            if (rec.sequence == 0)
                problem = "sequence 0 (sequence numbers start at 1)";
            else if (rec.sequence >= kMaxSequence)
                problem = "sequence " + std::to_string(rec.sequence) + " out of range";
            else if (expected != 0 && rec.sequence != expected)
                problem = "out of order (expected sequence " + std::to_string(expected) + ")";
        } catch (const DecodeError& e) {
            problem = e.what();
        }
        if (!problem.empty()) {
            out.warning = path.string() + ": record " + std::to_string(index) +
                          (haveSequence ? " (sequence " + std::to_string(rec.sequence) + ")" : "") +
                          ": " + problem + "; it and the rest were dropped";
            break;
        }
        expected = rec.sequence + 1;
        out.records.push_back(std::move(rec));
        pos += kFrameBytes + len;
        out.ends.push_back(pos);
        out.validBytes = pos;
    }
    return out;
}

}  // namespace

// ------------------------------------------------------------------------------ journal

JournalContents readJournal(const fs::path& path) {
    JournalScan scan = scanJournal(path);
    JournalContents out;
    out.records = std::move(scan.records);
    out.validBytes = scan.validBytes;
    out.warning = std::move(scan.warning);
    return out;
}

namespace {

/// The whole journal, copied durably to the first free name of PATH.damaged, .damaged-2, ...
fs::path keepBeforeCutting(int fd, const fs::path& path, off_t size) {
    std::string bytes(size_t(size), '\0');
    for (size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::pread(fd, bytes.data() + done, bytes.size() - done, off_t(done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            throw ProjectError(path.string() +
                               ": cannot read it to keep a copy before cutting "
                               "its damaged tail: " +
                               (n < 0 ? errnoText(errno) : std::string("file shrank")));
        done += size_t(n);
    }
    for (int i = 1;; ++i) {
        const fs::path copy = damagedName(path, i);
        std::error_code ec;
        if (fs::exists(fs::symlink_status(copy, ec))) continue;
        try {
            writeFileAtomically(copy, bytes, true);
        } catch (const FileWriteError& e) {
            throw ProjectError(std::string(e.what()) + " (a copy of " + path.string() +
                               " kept before cutting its damaged tail)");
        }
        return copy;
    }
}

}  // namespace

JournalWriter::JournalWriter(const fs::path& path, uint64_t validBytes, SyncFn sync)
    : mPath(path), mSync(sync ? std::move(sync) : SyncFn([](int fd) { return ::fdatasync(fd); })) {
    // Read too: reset(keepFrom) copies the records appended while a snapshot was written.
    mFd = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (mFd < 0)
        throw ProjectError(path.string() + ": cannot open for writing: " + errnoText(errno));
    try {
        struct stat st {};
        if (::fstat(mFd, &st) != 0 || !S_ISREG(st.st_mode))
            throw ProjectError(path.string() + ": not a regular file");
        if (validBytes > uint64_t(st.st_size))
            // Growing the file would put zeros where the next record must go.
            throw ProjectError(path.string() + ": asked to continue at byte " +
                               std::to_string(validBytes) + " of a " + std::to_string(st.st_size) +
                               "-byte file (changed since read?)");
        const uint64_t kept = validBytes < kMagicBytes ? 0 : validBytes;
        if (uint64_t(st.st_size) > kept) mKeptDamaged = keepBeforeCutting(mFd, path, st.st_size);
        if (validBytes < kMagicBytes) {
            if (::ftruncate(mFd, 0) != 0)
                throw ProjectError(path.string() + ": cannot truncate: " + errnoText(errno));
            writeAllOrThrow(mFd, journalHeader(), path);
            if (::fdatasync(mFd) != 0)
                throw ProjectError(path.string() + ": cannot flush: " + errnoText(errno));
            syncFolder(folderOf(path));  // the new file's name must survive with its records
        } else if (::ftruncate(mFd, off_t(validBytes)) != 0) {
            throw ProjectError(path.string() + ": cannot truncate: " + errnoText(errno));
        }
        if (::lseek(mFd, 0, SEEK_END) < 0)
            throw ProjectError(path.string() + ": cannot seek: " + errnoText(errno));
        // A restart that a crash cut short before its rename (reset, step 2): the journal
        // beside it is whole and the one in use, so the leftover only takes space.
        std::error_code gone;
        fs::remove(path.string() + ".restart", gone);
    } catch (...) {
        ::close(mFd);
        mFd = -1;
        throw;
    }
    mFlusher = std::thread([this] { flushLoop(); });
}

JournalWriter::~JournalWriter() {
    {
        const std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    mFlusher.join();  // after the last flush: the loop drains what was appended
    if (mFd >= 0) ::close(mFd);
}

void JournalWriter::flushLoop() {
    std::unique_lock lock(mMutex);
    for (;;) {
        mWake.wait(lock, [&] { return mStop || mAppended != mDurable; });
        if (mAppended == mDurable) return;  // stopping, nothing left to flush
        const uint64_t upTo = mAppended, generation = mGeneration;
        // A duplicate, flushed without the lock: append() and reset() go on meanwhile.
        const int fd = mFd >= 0 ? ::dup(mFd) : -1;
        int err = fd < 0 ? (mFd < 0 ? EBADF : errno) : 0;
        lock.unlock();
        if (fd >= 0) {
            while (mSync(fd) != 0) {
                if (errno == EINTR) continue;
                err = errno;
                break;
            }
            ::close(fd);
        }
        lock.lock();
        if (generation != mGeneration) continue;  // a reset replaced the file meanwhile
        if (err != 0 && mFlushError.empty()) mFlushError = errnoText(err);
        mDurable = std::max(mDurable, upTo);  // or given up on: mFlushError says so
        mFlushed.notify_all();
    }
}

void JournalWriter::waitDurable() {
    std::unique_lock lock(mMutex);
    const uint64_t upTo = mAppended;
    mFlushed.wait(lock, [&] { return mDurable >= upTo; });
    if (!mFlushError.empty()) throw ProjectError(mPath.string() + ": cannot flush: " + mFlushError);
}

void JournalWriter::append(const JournalRecord& rec) {
    const std::lock_guard lock(mMutex);
    if (!mFlushError.empty())
        throw ProjectError(
            mPath.string() + ": record with sequence " + std::to_string(rec.sequence) +
            " not written: an earlier record could not be flushed to disk (" + mFlushError + ")");
    if (mFd < 0)
        throw ProjectError(mPath.string() + ": the journal was closed by an earlier failure");
    const std::string what = mPath.string() + ": record with sequence " +
                             std::to_string(rec.sequence) + " not written: ";
    if (std::string p = recordProblem(rec); !p.empty()) throw ProjectError(what + p);
    if (mLastSequence != 0 && rec.sequence != mLastSequence + 1)
        throw ProjectError(what + "it does not follow sequence " + std::to_string(mLastSequence));
    const std::string payload = encodeRecord(rec);
    if (payload.size() > kMaxRecordBytes)
        throw ProjectError(what + "it would be " + std::to_string(payload.size()) +
                           " bytes, more than a journal record may hold");
    Writer frame;
    frame.pod(kRecordMark);
    frame.pod(uint32_t(payload.size()));
    frame.pod(crc(payload.data(), payload.size()));
    frame.bytes += payload;
    const off_t start = ::lseek(mFd, 0, SEEK_CUR);
    try {
        writeAllOrThrow(mFd, frame.bytes, mPath);
    } catch (...) {
        // A partial record would hide every later one from readJournal: cut it off.
        if (start >= 0 && ::ftruncate(mFd, start) == 0) ::lseek(mFd, start, SEEK_SET);
        throw;
    }
    mLastSequence = rec.sequence;
    ++mAppended;
    mWake.notify_one();
}

uint64_t JournalWriter::bytes() const {
    const std::lock_guard lock(mMutex);
    if (mFd < 0) return 0;
    const off_t end = ::lseek(mFd, 0, SEEK_CUR);
    return end < 0 ? 0 : uint64_t(end);
}

void JournalWriter::reset() {
    reset(std::numeric_limits<uint64_t>::max());
}

void JournalWriter::reset(uint64_t keepFrom) {
    const bool keep = keepFrom != std::numeric_limits<uint64_t>::max();
    auto readRange = [&](int fd, uint64_t from, uint64_t to, std::string& into) {
        const size_t at = into.size();
        into.resize(at + size_t(to - from));
        for (size_t done = 0; done < to - from;) {
            const ssize_t n =
                ::pread(fd, into.data() + at + done, to - from - done, off_t(from + done));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0)
                throw ProjectError(mPath.string() + ": cannot read back its last records: " +
                                   (n < 0 ? errnoText(errno) : std::string("file shrank")));
            done += size_t(n);
        }
    };
    // 1 (locked): the records kept so far. Whole records: keepFrom was bytes() between two
    // appends, and so is `end`.
    std::string data = journalHeader();
    uint64_t end = 0, appendedAtEnd = 0;
    {
        const std::lock_guard lock(mMutex);
        if (keep && mFd < 0)
            throw ProjectError(mPath.string() +
                               ": the journal was closed by an earlier failure; not restarted");
        if (mFd >= 0) {
            const off_t at = ::lseek(mFd, 0, SEEK_CUR);
            if (at < 0) throw ProjectError(mPath.string() + ": cannot seek: " + errnoText(errno));
            end = uint64_t(at);
        }
        if (keep) {
            if (keepFrom < kMagicBytes || keepFrom > end)
                throw std::logic_error("JournalWriter::reset: keeping from byte " +
                                       std::to_string(keepFrom) + " of a " + std::to_string(end) +
                                       "-byte journal");
            readRange(mFd, keepFrom, end, data);
        }
        appendedAtEnd = mAppended;
    }
    // 2 (unlocked): the new journal, flushed, under a name of its own. Two flushes take
    // milliseconds on a laptop's disk: appends go on meanwhile, into the old file.
    const fs::path next = mPath.string() + ".restart";
    try {
        writeFileAtomically(next, data, false);
    } catch (const FileWriteError& e) {
        throw ProjectError(e.what());
    }
    const int fd = ::open(next.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) throw ProjectError(next.string() + ": cannot open: " + errnoText(errno));
    auto fail = [&](const std::string& why) {
        ::close(fd);
        ::unlink(next.c_str());
        throw ProjectError(why);
    };
    while (mSync(fd) != 0)
        if (errno != EINTR) fail(next.string() + ": cannot flush: " + errnoText(errno));
    // 3 (locked): what was appended meanwhile follows, then the new file takes the name. The
    // old file is never written again: it may now be journal.vjl.bak.
    {
        const std::lock_guard lock(mMutex);
        std::string since;
        if (mFd >= 0) {
            const off_t now = ::lseek(mFd, 0, SEEK_CUR);
            if (now < 0) fail(mPath.string() + ": cannot seek: " + errnoText(errno));
            readRange(mFd, end, uint64_t(now), since);
        }
        if (::lseek(fd, 0, SEEK_END) < 0)
            fail(next.string() + ": cannot seek: " + errnoText(errno));
        try {
            writeAllOrThrow(fd, since, next);
        } catch (const ProjectError& e) {
            fail(e.what());
        }
        if (::rename(next.c_str(), mPath.c_str()) != 0)
            fail(mPath.string() + ": cannot replace it with the new journal: " + errnoText(errno));
        if (mFd >= 0) ::close(mFd);
        mFd = fd;
        ++mGeneration;
        // Every record appended before step 1 is on disk: in the snapshot the caller wrote,
        // or in the new file. Those copied in step 3 are the flusher's (a flush that failed
        // before no longer matters).
        mDurable = appendedAtEnd;
        mFlushError.clear();
        if (mAppended != mDurable) mWake.notify_one();
        mFlushed.notify_all();
    }
    // 4: the new name itself made durable.
    syncFolder(folderOf(mPath));
}

// ------------------------------------------------------------------------------ snapshot

void writeSnapshot(const fs::path& path, const std::string& configJson, uint64_t lastSequence,
                   const Sculpture& sculpture, const History& history) {
    const std::string bytes = encodeSnapshot(path, configJson, lastSequence, sculpture, history);
    try {
        writeFileAtomically(path, bytes, true);
    } catch (const FileWriteError& e) {
        throw ProjectError(e.what());
    }
}

namespace {

/// The snapshot file's bytes once its magic, version and checksum are right.
std::string readCheckedSnapshot(const fs::path& path) {
    std::string data = readProjectFile(path);
    if (data.size() < kMagicBytes + 4)
        throw ProjectError(path.string() + ": byte 0: not a vsculpt snapshot (" +
                           std::to_string(data.size()) + " bytes)");
    checkMagic(data, kSnapshotMagic, path, "snapshot");
    uint32_t sum;
    std::memcpy(&sum, data.data() + data.size() - 4, 4);
    if (crc(data.data(), data.size() - 4) != sum)
        throw ProjectError(path.string() + ": checksum mismatch: the snapshot is damaged (" +
                           std::to_string(data.size()) + " bytes)");
    return data;
}

}  // namespace

SnapshotContents readSnapshot(const fs::path& path) {
    const std::string data = readCheckedSnapshot(path);
    const std::string file = path.string();
    Reader r(data, kMagicBytes, data.size() - 4);
    SnapshotContents out;
    std::string entry;  // what is being decoded, for the message
    try {
        out.lastSequence = r.pod<uint64_t>();
        if (out.lastSequence >= kMaxSequence)
            r.fail("last sequence " + std::to_string(out.lastSequence) + " out of range");
        out.configJson = r.str();
        const uint64_t n = r.pod<uint64_t>();
        if (n > r.left() / kSkeletonBytes)
            r.fail(std::to_string(n) + " skeletons, more than the file holds");
        out.skeletons.reserve(size_t(n));
        for (uint64_t i = 0; i < n; ++i) {
            entry = "skeleton " + std::to_string(i + 1) + ": ";
            SkeletonEntry e;
            e.level = r.pod<uint8_t>();
            e.coord.x = r.pod<int32_t>();
            e.coord.y = r.pod<int32_t>();
            e.coord.z = r.pod<int32_t>();
            e.weight = r.pod<float>();
            if (std::string p = levelProblem(e.level); !p.empty()) r.fail(p);
            if (std::string p = coordProblem(e.coord); !p.empty()) r.fail(p);
            if (std::string p = weightProblem(e.weight); !p.empty()) r.fail("weight " + p);
            out.skeletons.push_back(e);
        }
        const std::pair<const char*, std::vector<StrokeRecord>*> stacks[] = {
            {"undo step ", &out.done}, {"redo step ", &out.undone}};
        for (const auto& [name, stack] : stacks) {
            entry = std::string(name) + "count: ";
            const uint32_t m = r.pod<uint32_t>();
            if (m > r.left() / kMinStrokeBytes)
                r.fail(std::to_string(m) + " steps, more than the file holds");
            for (uint32_t i = 0; i < m; ++i) {
                entry = name + std::to_string(i + 1) + ": ";
                stack->push_back(decodeStroke(r));
            }
        }
        entry.clear();
        if (r.left() != 0) r.fail("trailing bytes");
    } catch (const DecodeError& e) {
        throw ProjectError(file + ": " + entry + e.what() + " (byte " + std::to_string(e.pos) +
                           ")");
    }
    return out;
}

// ------------------------------------------------------------------------------ projects

namespace {

/// The records of one journal file, or nullopt (with a warning in `out`) for a backup that
/// cannot be read. `isCurrent`: journal.vjl, which the caller will append to; one that cannot
/// be read is refused rather than later overwritten by the writer.
std::optional<JournalScan> scanned(RecoveredProject& out, const fs::path& path, bool isCurrent) {
    try {
        return scanJournal(path);
    } catch (const ProjectError& e) {
        // The way out named (found by QA: a project refused without a word on what to do).
        if (isCurrent)
            throw ProjectError(std::string(e.what()) + "; the project was not opened and is left " +
                               "as it is (move " + path.filename().string() +
                               " out of the folder to open the project without it)");
        out.warnings.push_back(std::string(e.what()) + "; its records were not used");
        return std::nullopt;
    }
}

/// Appends the records of `scan` (of the file `path`) that continue the chain at `last`.
/// Records up to `last` are already in: skipped.
void takeScanned(RecoveredProject& out, const fs::path& path, bool isCurrent, JournalScan scan,
                 uint64_t& last) {
    if (isCurrent) out.journalValidBytes = scan.headerBytes;
    for (size_t i = 0; i < scan.records.size(); ++i) {
        JournalRecord& rec = scan.records[i];
        if (rec.sequence > last + 1) {
            out.warnings.push_back(path.string() + ": record " + std::to_string(i + 1) +
                                   " (sequence " + std::to_string(rec.sequence) +
                                   "): expected sequence " + std::to_string(last + 1) +
                                   " next; it and the rest were dropped");
            scan.warning.clear();  // any damage lies among what was dropped
            break;
        }
        if (rec.sequence == last + 1) {
            last = rec.sequence;
            out.records.push_back(std::move(rec));
        }
        if (isCurrent) out.journalValidBytes = scan.ends[i];
    }
    if (!scan.warning.empty()) out.warnings.push_back(std::move(scan.warning));
}

/// Both: the records of one journal file that continue the chain at `last`.
void takeRecords(RecoveredProject& out, const fs::path& path, bool isCurrent, uint64_t& last) {
    if (std::optional<JournalScan> scan = scanned(out, path, isCurrent))
        takeScanned(out, path, isCurrent, std::move(*scan), last);
}

/// Whether the journal's first record after `last` leaves a gap (its sequence is past
/// last + 1).
bool skipsPast(const JournalScan& scan, uint64_t last) {
    for (const JournalRecord& rec : scan.records)
        if (rec.sequence > last) return rec.sequence > last + 1;
    return false;
}

bool cannotLink(int err) {
    return err == EPERM || err == EOPNOTSUPP || err == EXDEV || err == EMLINK || err == ENOSYS;
}

/// `to` becomes another name of `from` (or, where links are impossible, an atomic copy).
void keepAs(const fs::path& from, const fs::path& to) {
    try {
        replaceWithHardLink(from, to, false);
    } catch (const FileWriteError& e) {
        if (!cannotLink(e.code())) throw;
        writeFileAtomically(to, readProjectFile(from), false);
    }
}

}  // namespace

RecoveredProject readProject(const fs::path& dir) {
    RecoveredProject out;
    std::error_code ec;
    const fs::file_status st = fs::status(dir, ec);
    if (!fs::exists(st)) return out;
    if (!fs::is_directory(st)) throw ProjectError(dir.string() + ": not a project folder");

    const fs::path snap = snapshotPath(dir), backup = snapshotBackupPath(dir);
    std::string primaryProblem;
    if (fs::exists(snap, ec)) {
        try {
            out.snapshot = readSnapshot(snap);
        } catch (const ProjectError& e) {
            primaryProblem = e.what();
        }
    } else if (!fs::exists(backup, ec)) {
        uint64_t last = 0;  // never saved: the journal must start at sequence 1
        takeRecords(out, journalPath(dir), true, last);
        return out;
    } else {
        primaryProblem = snap.string() + ": missing";
    }
    if (out.snapshot) {
        uint64_t last = out.snapshot->lastSequence;
        // A snapshot older than journal.vjl (one restored from a copy, or the backup pair
        // swapped in by hand) leaves a gap that journal.vjl.bak may hold: bridged from it,
        // else the next save would rotate the backup journal away with the only copy of the
        // edits between them.
        // journal.vjl read once: scanned here, its records taken after the bridge.
        JournalScan current = *scanned(out, journalPath(dir), true);
        if (skipsPast(current, last)) {
            const uint64_t from = last;
            takeRecords(out, journalBackupPath(dir), false, last);
            if (last > from)
                out.warnings.push_back(snap.string() + " is older than " +
                                       journalPath(dir).string() + ": edits " +
                                       std::to_string(from + 1) + " to " + std::to_string(last) +
                                       " taken from " + journalBackupPath(dir).string());
        }
        takeScanned(out, journalPath(dir), true, std::move(current), last);
        return out;
    }

    if (!fs::exists(backup, ec))
        throw ProjectError(primaryProblem + "; and there is no backup (" + backup.string() + ")");
    try {
        out.snapshot = readSnapshot(backup);
    } catch (const ProjectError& e) {
        throw ProjectError(primaryProblem + "; the backup is unusable too: " + e.what());
    }
    out.fromBackup = true;
    out.warnings.push_back(primaryProblem + "; recovered from " + backup.string() + " and " +
                           journalBackupPath(dir).string() + " then " + journalPath(dir).string());
    uint64_t last = out.snapshot->lastSequence;
    takeRecords(out, journalBackupPath(dir), false, last);
    takeRecords(out, journalPath(dir), true, last);
    return out;
}

void writeProjectSnapshot(const fs::path& dir, const std::string& configJson, uint64_t lastSequence,
                          const Sculpture& sculpture, const History& history) {
    const fs::path snap = snapshotPath(dir), journalFile = journalPath(dir);
    // Every check before the first file changes.
    const std::string bytes = encodeSnapshot(snap, configJson, lastSequence, sculpture, history);
    std::error_code ec;
    bool currentReadable = false;
    if (fs::exists(snap, ec)) {
        try {
            // Its checksum, not a decoding of every entry: a file this build wrote and the
            // disk kept intact decodes (a third of what a save at 1e5 skeletons took).
            readCheckedSnapshot(snap);
            currentReadable = true;
        } catch (const ProjectError&) {
            // A damaged snapshot must not become the backup: the backup is what rescues it.
        }
    }
    try {
        if (currentReadable) {
            // Backups first, and on disk before the snapshot changes: at every moment the
            // folder holds either the old pair or the old pair plus its backups. (The journal
            // may be growing meanwhile, a background save: its backup is the same file.)
            keepAs(snap, snapshotBackupPath(dir));
            if (fs::exists(journalFile, ec))
                keepAs(journalFile, journalBackupPath(dir));
            else
                writeFileAtomically(journalBackupPath(dir), journalHeader(), false);
            syncFolder(dir);
            writeFileAtomically(snap, bytes, true);
        } else {
            // The new snapshot is also its own backup, so the backup's journal can start
            // empty (journal.vjl's records after lastSequence continue either).
            writeFileAtomically(snap, bytes, true);
            writeFileAtomically(snapshotBackupPath(dir), bytes, false);
            writeFileAtomically(journalBackupPath(dir), journalHeader(), false);
            syncFolder(dir);
        }
    } catch (const FileWriteError& e) {
        throw ProjectError(e.what());
    }
}

void saveProject(const fs::path& dir, const std::string& configJson, uint64_t lastSequence,
                 const Sculpture& sculpture, const History& history, JournalWriter& journal) {
    if (journal.path() != journalPath(dir))
        throw std::invalid_argument("saveProject: the journal writer writes " +
                                    journal.path().string() + ", not " + journalPath(dir).string());
    writeProjectSnapshot(dir, configJson, lastSequence, sculpture, history);
    journal.reset();
}

void restoreSnapshot(const SnapshotContents& snapshot, Sculpture& sculpture, History& history) {
    for (const SkeletonEntry& e : snapshot.skeletons)
        sculpture.store().set(e.level, e.coord, e.weight);
    history.restore(snapshot.done, snapshot.undone);
}

Aabb applyJournalRecord(Sculpture& sculpture, History& history, const JournalRecord& r) {
    switch (r.op) {
        case JournalOp::Stroke: {
            StrokeRecord rec;
            rec.op = r.tool;
            rec.mirror = r.mirror;
            rec.level = r.level;
            rec.samples = r.samples;
            const EditResult e =
                applyStroke(sculpture, r.tool, r.level, r.samples, &rec.changes, r.mirror);
            history.push(std::move(rec));
            return e.changedRegion;
        }
        case JournalOp::Solid: {
            SolidPlacement placed = replaySolid(sculpture, r.solidLevel, r.changes);
            StrokeRecord rec;
            rec.solid = true;
            rec.level = placed.level;
            rec.changes = std::move(placed.changes);
            history.push(std::move(rec));
            return placed.edit.changedRegion;
        }
        case JournalOp::Undo:
            return history.undo(sculpture);
        case JournalOp::Redo:
            return history.redo(sculpture);
    }
    throw std::invalid_argument("journal record " + std::to_string(r.sequence) +
                                ": unknown operation");
}

}  // namespace vsculpt::core
