// SPDX-License-Identifier: MIT
#include "vsculpt/core/Project.h"

#include "vsculpt/core/Sculpture.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace vsculpt::core {

namespace {

constexpr char kJournalMagic[8] = {'V', 'S', 'J', 'R', 'N', 'L', '0', '1'};
constexpr char kSnapshotMagic[8] = {'V', 'S', 'S', 'N', 'A', 'P', '0', '1'};
constexpr uint32_t kRecordMark = 0x5245434Bu;  // "RECK"
constexpr uint32_t kMaxRecordBytes = 64u << 20;

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

class Reader {
  public:
    Reader(const std::string& data, size_t begin, size_t end, std::string file)
        : mData(data), mPos(begin), mEnd(end), mFile(std::move(file)) {}
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
    [[noreturn]] void fail(const std::string& why) const {
        throw ProjectError(mFile + ": byte " + std::to_string(mPos) + ": " + why);
    }
    void need(size_t n) const {
        if (mEnd - mPos < n) fail("unexpected end of data");
    }

  private:
    const std::string& mData;
    size_t mPos, mEnd;
    std::string mFile;
};

uint32_t crc(const char* p, size_t n) {
    return uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(p), uInt(n)));
}

std::string readAll(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ProjectError(path.string() + ": cannot open");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void writeAllOrThrow(int fd, const std::string& data, const std::filesystem::path& path) {
    size_t done = 0;
    while (done < data.size()) {
        const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw ProjectError(path.string() + ": write failed: " + std::strerror(errno));
        }
        done += size_t(n);
    }
}

void encodeStroke(Writer& w, const StrokeRecord& r) {
    w.pod(uint8_t(r.solid ? 2 : r.op == ToolOp::Add ? 0 : 1));
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

StrokeRecord decodeStroke(Reader& r) {
    StrokeRecord s;
    const uint8_t op = r.pod<uint8_t>();
    if (op > 2) r.fail("bad tool operation");
    s.op = op == 1 ? ToolOp::Carve : ToolOp::Add;
    s.solid = op == 2;
    s.level = r.pod<uint8_t>();
    if (s.level < 1 || s.level > kLevelCount) r.fail("bad tool level");
    const uint32_t n = r.pod<uint32_t>();
    r.need(size_t(n) * 24);
    for (uint32_t i = 0; i < n; ++i)
        s.samples.push_back(r.vec());
    const uint32_t m = r.pod<uint32_t>();
    r.need(size_t(m) * 22);
    for (uint32_t i = 0; i < m; ++i) {
        SkeletonChange c;
        c.level = r.pod<uint8_t>();
        c.coord.x = r.pod<int32_t>();
        c.coord.y = r.pod<int32_t>();
        c.coord.z = r.pod<int32_t>();
        const uint8_t has = r.pod<uint8_t>();
        const float before = r.pod<float>(), after = r.pod<float>();
        if (has & 1) c.before = before;
        if (has & 2) c.after = after;
        s.changes.push_back(c);
    }
    return s;
}

}  // namespace

// ------------------------------------------------------------------------------ journal

JournalContents readJournal(const std::filesystem::path& path) {
    JournalContents out;
    if (!std::filesystem::exists(path)) return out;
    const std::string data = readAll(path);
    if (data.size() < sizeof kJournalMagic) {
        out.warning = path.string() + ": shorter than its header; treated as empty";
        return out;
    }
    if (std::memcmp(data.data(), kJournalMagic, sizeof kJournalMagic) != 0)
        throw ProjectError(path.string() + ": byte 0: not a vsculpt journal (bad magic)");
    size_t pos = sizeof kJournalMagic;
    out.validBytes = pos;
    uint64_t expected = 0;
    while (pos < data.size()) {
        // Frame: mark, payload length, payload crc, payload.
        auto bad = [&](const std::string& why) {
            out.warning = path.string() + ": byte " + std::to_string(pos) + ": record " +
                          std::to_string(out.records.size() + 1) + " " + why + "; kept the " +
                          std::to_string(out.records.size()) + " complete record(s) before it";
        };
        if (data.size() - pos < 12) {
            bad("is truncated");
            break;
        }
        uint32_t mark, len, sum;
        std::memcpy(&mark, data.data() + pos, 4);
        std::memcpy(&len, data.data() + pos + 4, 4);
        std::memcpy(&sum, data.data() + pos + 8, 4);
        if (mark != kRecordMark || len > kMaxRecordBytes) {
            bad("has a damaged header");
            break;
        }
        if (data.size() - pos - 12 < len) {
            bad("is truncated");
            break;
        }
        if (crc(data.data() + pos + 12, len) != sum) {
            bad("fails its checksum");
            break;
        }
        try {
            Reader r(data, pos + 12, pos + 12 + len, path.string());
            JournalRecord rec;
            rec.sequence = r.pod<uint64_t>();
            const uint8_t op = r.pod<uint8_t>();
            if (op < 1 || op > 4) r.fail("unknown journal operation");
            rec.op = JournalOp(op);
            if (rec.op == JournalOp::Stroke || rec.op == JournalOp::Solid) {
                StrokeRecord s = decodeStroke(r);
                if (s.solid != (rec.op == JournalOp::Solid))
                    r.fail("stroke and solid records mixed up");
                rec.tool = s.op;
                rec.level = s.level;
                rec.samples = std::move(s.samples);
                if (s.solid) {
                    rec.solidLevel = s.level;
                    for (const SkeletonChange& c : s.changes)
                        if (c.level < 1 || c.level > kLevelCount) r.fail("bad solid level");
                    rec.changes = std::move(s.changes);
                }
            }
            if (expected != 0 && rec.sequence != expected) r.fail("sequence number out of order");
            expected = rec.sequence + 1;
            out.records.push_back(std::move(rec));
        } catch (const ProjectError& e) {
            bad(std::string("cannot be decoded (") + e.what() + ")");
            break;
        }
        pos += 12 + len;
        out.validBytes = pos;
    }
    return out;
}

JournalWriter::JournalWriter(const std::filesystem::path& path, uint64_t validBytes) : mPath(path) {
    mFd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
    if (mFd < 0)
        throw ProjectError(path.string() + ": cannot open for writing: " + std::strerror(errno));
    if (validBytes < sizeof kJournalMagic) {
        if (::ftruncate(mFd, 0) != 0)
            throw ProjectError(path.string() + ": cannot truncate: " + std::strerror(errno));
        writeAllOrThrow(mFd, std::string(kJournalMagic, sizeof kJournalMagic), path);
        ::fdatasync(mFd);
    } else if (::ftruncate(mFd, off_t(validBytes)) != 0) {
        throw ProjectError(path.string() + ": cannot truncate: " + std::strerror(errno));
    }
    if (::lseek(mFd, 0, SEEK_END) < 0)
        throw ProjectError(path.string() + ": cannot seek: " + std::strerror(errno));
}

JournalWriter::~JournalWriter() {
    if (mFd >= 0) ::close(mFd);
}

void JournalWriter::append(const JournalRecord& rec) {
    Writer payload;
    payload.pod(rec.sequence);
    payload.pod(uint8_t(rec.op));
    if (rec.op == JournalOp::Stroke) {
        StrokeRecord s;
        s.op = rec.tool;
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
    if (payload.bytes.size() > kMaxRecordBytes)
        throw ProjectError(mPath.string() + ": record " + std::to_string(rec.sequence) +
                           " would be " + std::to_string(payload.bytes.size()) +
                           " bytes, more than a journal record may hold");
    Writer frame;
    frame.pod(kRecordMark);
    frame.pod(uint32_t(payload.bytes.size()));
    frame.pod(crc(payload.bytes.data(), payload.bytes.size()));
    frame.bytes += payload.bytes;
    writeAllOrThrow(mFd, frame.bytes, mPath);
    if (::fdatasync(mFd) != 0)
        throw ProjectError(mPath.string() + ": cannot flush: " + std::strerror(errno));
}

void JournalWriter::reset() {
    if (::ftruncate(mFd, 0) != 0 || ::lseek(mFd, 0, SEEK_SET) < 0)
        throw ProjectError(mPath.string() + ": cannot truncate: " + std::strerror(errno));
    writeAllOrThrow(mFd, std::string(kJournalMagic, sizeof kJournalMagic), mPath);
    ::fdatasync(mFd);
}

// ------------------------------------------------------------------------------ snapshot

void writeSnapshot(const std::filesystem::path& path, const std::string& configJson,
                   uint64_t lastSequence, const Sculpture& sculpture, const History& history) {
    Writer w;
    w.bytes.append(kSnapshotMagic, sizeof kSnapshotMagic);
    w.pod(lastSequence);
    w.str(configJson);
    w.pod(uint64_t(sculpture.store().vertexCount()));
    sculpture.store().forEach([&](const SkeletonEntry& e) {
        w.pod(uint8_t(e.level));
        w.pod(e.coord.x);
        w.pod(e.coord.y);
        w.pod(e.coord.z);
        w.pod(e.weight);
    });
    for (const auto* stack : {&history.done(), &history.undone()}) {
        w.pod(uint32_t(stack->size()));
        for (const StrokeRecord& r : *stack)
            encodeStroke(w, r);
    }
    w.pod(crc(w.bytes.data(), w.bytes.size()));

    const std::filesystem::path tmp = path.string() + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw ProjectError(tmp.string() + ": cannot create: " + std::strerror(errno));
    try {
        writeAllOrThrow(fd, w.bytes, tmp);
        if (::fsync(fd) != 0) throw ProjectError(tmp.string() + ": fsync failed");
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::close(fd);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw ProjectError(path.string() + ": cannot replace: " + ec.message());
    const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : ".";
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
}

SnapshotContents readSnapshot(const std::filesystem::path& path) {
    const std::string data = readAll(path);
    const std::string file = path.string();
    if (data.size() < sizeof kSnapshotMagic + 4 ||
        std::memcmp(data.data(), kSnapshotMagic, sizeof kSnapshotMagic) != 0)
        throw ProjectError(file + ": byte 0: not a vsculpt snapshot (bad magic or version)");
    uint32_t sum;
    std::memcpy(&sum, data.data() + data.size() - 4, 4);
    if (crc(data.data(), data.size() - 4) != sum)
        throw ProjectError(file + ": checksum mismatch: the snapshot is damaged (" +
                           std::to_string(data.size()) + " bytes)");
    Reader r(data, sizeof kSnapshotMagic, data.size() - 4, file);
    SnapshotContents out;
    out.lastSequence = r.pod<uint64_t>();
    out.configJson = r.str();
    const uint64_t n = r.pod<uint64_t>();
    r.need(size_t(n) * 17);
    for (uint64_t i = 0; i < n; ++i) {
        SkeletonEntry e;
        e.level = r.pod<uint8_t>();
        if (e.level < 1 || e.level > kLevelCount) r.fail("bad skeleton level");
        e.coord.x = r.pod<int32_t>();
        e.coord.y = r.pod<int32_t>();
        e.coord.z = r.pod<int32_t>();
        e.weight = r.pod<float>();
        out.skeletons.push_back(e);
    }
    for (auto* stack : {&out.done, &out.undone}) {
        const uint32_t m = r.pod<uint32_t>();
        for (uint32_t i = 0; i < m; ++i)
            stack->push_back(decodeStroke(r));
    }
    if (r.pos() != data.size() - 4) r.fail("trailing bytes");
    return out;
}

}  // namespace vsculpt::core
