// SPDX-License-Identifier: MIT
#include "vsculpt/devices/Recording.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string_view>

namespace vsculpt::devices {

namespace {

constexpr const char* kMagic = "vsculpt-recording 1";
// An editor that saved a recording may have put a UTF-8 byte order mark first (found by QA:
// the recording was then read as a script, "unknown command 'vsculpt-recording'").
constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

const char* kindName(DeviceEventKind k) {
    return toString(k);
}

bool parseKind(const std::string& s, DeviceEventKind& k) {
    for (DeviceEventKind c :
         {DeviceEventKind::Report, DeviceEventKind::Arrived, DeviceEventKind::Left,
          DeviceEventKind::Stalled, DeviceEventKind::Resumed})
        if (s == toString(c)) {
            k = c;
            return true;
        }
    return false;
}

int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

bool parseHexId(const std::string& s, uint16_t& out) {
    unsigned value = 0;
    const char* begin = s.data();
    if (s.rfind("0x", 0) == 0) begin += 2;
    const auto r = std::from_chars(begin, s.data() + s.size(), value, 16);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || value > 0xffff ||
        begin == s.data() + s.size())
        return false;
    out = static_cast<uint16_t>(value);
    return true;
}

std::string hexId(uint16_t v) {
    char b[8];
    std::snprintf(b, sizeof b, "%04x", v);
    return b;
}

}  // namespace

RecordingWriter::RecordingWriter(const std::filesystem::path& path,
                                 const std::vector<DeviceRule>& devices,
                                 const std::map<std::string, std::string>& meta)
    : mPath(path), mOut(path, std::ios::binary | std::ios::trunc) {
    if (!mOut) throw RecordingError(path.string() + ": cannot create the recording file");
    mOut << kMagic << "\n";
    for (const auto& [key, value] : meta) {
        if (key.empty() || key.find_first_of(" \n") != std::string::npos ||
            value.find('\n') != std::string::npos)
            throw RecordingError(path.string() + ": meta '" + key +
                                 "' must be one word and one line");
        mOut << "meta " << key << " " << value << "\n";
    }
    for (const auto& d : devices) {
        mOut << "device " << d.name << " " << toString(d.driver) << " " << toString(d.access) << " "
             << hexId(d.vendor) << " ";
        for (size_t i = 0; i < d.products.size(); ++i)
            mOut << (i ? "," : "") << hexId(d.products[i]);
        mOut << "\n";
    }
    mOut.flush();
    if (!mOut) throw RecordingError(path.string() + ": write error");
}

void RecordingWriter::write(const DeviceEvent& e) {
    static const char* kHex = "0123456789abcdef";
    std::string line = std::to_string(e.timeNs) + " " + e.device + " " + kindName(e.kind);
    if (!e.bytes.empty()) {
        line += ' ';
        for (uint8_t b : e.bytes) {
            line += kHex[b >> 4];
            line += kHex[b & 15];
        }
    }
    line += '\n';
    mOut << line;
    ++mEvents;
}

void RecordingWriter::flush() {
    mOut.flush();
    if (!mOut) throw RecordingError(mPath.string() + ": write error (disk full?)");
}

Recording parseRecording(const std::string& whole, const std::string& source) {
    const std::string text =
        std::string_view(whole).substr(0, kByteOrderMark.size()) == kByteOrderMark
            ? whole.substr(kByteOrderMark.size())
            : whole;
    Recording rec;
    std::istringstream in(text);
    std::string line;
    size_t lineNo = 0;
    auto fail = [&](const std::string& why) -> void {
        // Words quoted from a damaged line may hold control bytes (a NUL cut the message
        // short): escaped, as scripts' messages show them.
        std::string shown;
        for (const char c : why) {
            const auto u = static_cast<unsigned char>(c);
            if (u < 0x20 || u == 0x7f) {
                char esc[8];
                std::snprintf(esc, sizeof esc, "\\x%02x", u);
                shown += esc;
            } else {
                shown += c;
            }
        }
        throw RecordingError(source + ":" + std::to_string(lineNo) + ": " + shown);
    };
    bool header = false;
    // Every line the writer writes ends with '\n': a last line without one was cut short.
    const bool cutShort = !text.empty() && text.back() != '\n';
    const size_t lastLine = size_t(std::count(text.begin(), text.end(), '\n')) + 1;
    while (std::getline(in, line)) {
        ++lineNo;
        if (cutShort && lineNo == lastLine && header) {
            // Even a line that would parse may have lost bytes (a report's hex cut short).
            rec.warnings.push_back(source + ":" + std::to_string(lineNo) +
                                   ": the last line is cut short (the recording ended while "
                                   "it was written): dropped");
            break;
        }
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            if (line != kMagic) {
                // Another version of the format: say so, rather than "not a recording".
                const std::string word = "vsculpt-recording ";
                if (line.rfind(word, 0) == 0)
                    fail("recording format version '" + line.substr(word.size()) +
                         "': this vsculpt reads version " +
                         std::string(kMagic).substr(word.size()) + " only");
                fail("not a vsculpt device recording (expected '" + std::string(kMagic) + "')");
            }
            header = true;
            continue;
        }
        std::istringstream words(line);
        std::string first;
        words >> first;
        if (first == "meta") {
            if (!rec.events.empty()) fail("meta after the first event");
            std::string key;
            words >> key;
            std::string value;
            std::getline(words, value);
            if (!value.empty() && value[0] == ' ') value.erase(0, 1);
            if (key.empty()) fail("meta without a key");
            rec.meta[key] = value;
            continue;
        }
        if (first == "device") {
            if (!rec.events.empty()) fail("device after the first event");
            std::string name, driver, access, vendor, products, extra;
            words >> name >> driver >> access >> vendor >> products;
            if (products.empty() || (words >> extra))
                fail("expected: device <name> <driver> <access> <vendor> <product,...>");
            DeviceRule rule;
            rule.name = name;
            const auto d = parseDeviceDriver(driver);
            if (!d) fail("unknown driver '" + driver + "'");
            rule.driver = *d;
            const auto a = parseDeviceAccess(access);
            if (!a) fail("unknown access '" + access + "' (hidraw or libusb)");
            rule.access = *a;
            if (!parseHexId(vendor, rule.vendor)) fail("bad vendor id '" + vendor + "'");
            std::istringstream list(products);
            std::string p;
            while (std::getline(list, p, ',')) {
                uint16_t id = 0;
                if (!parseHexId(p, id)) fail("bad product id '" + p + "'");
                rule.products.push_back(id);
            }
            for (const auto& other : rec.devices)
                if (other.name == name) fail("device '" + name + "' declared twice");
            rec.devices.push_back(rule);
            continue;
        }
        DeviceEvent e;
        {
            const auto r = std::from_chars(first.data(), first.data() + first.size(), e.timeNs);
            const bool digits = first.find_first_not_of("-0123456789") == std::string::npos;
            if (r.ec == std::errc::result_out_of_range && digits)
                fail("timestamp " + first + " ns out of range (at most " +
                     std::to_string(std::numeric_limits<decltype(e.timeNs)>::max()) +
                     " either way)");
            if (r.ec != std::errc() || r.ptr != first.data() + first.size())
                fail(
                    "expected 'meta', 'device' or an event '<timeNs> <device> <kind> [hex]', got "
                    "'" +
                    first + "'");
        }
        std::string kind, hex, extra;
        words >> e.device >> kind >> hex;
        if (words >> extra) fail("trailing text after the bytes");
        bool known = false;
        for (const auto& d : rec.devices)
            known |= d.name == e.device;
        if (!known) fail("event for undeclared device '" + e.device + "'");
        if (!parseKind(kind, e.kind)) fail("unknown event kind '" + kind + "'");
        if (hex.size() % 2) fail("odd number of hex digits");
        e.bytes.reserve(hex.size() / 2);
        for (size_t i = 0; i < hex.size(); i += 2) {
            const int hi = hexDigit(hex[i]), lo = hexDigit(hex[i + 1]);
            if (hi < 0 || lo < 0) fail("bad hex byte '" + hex.substr(i, 2) + "'");
            e.bytes.push_back(static_cast<uint8_t>(hi * 16 + lo));
        }
        if (e.kind == DeviceEventKind::Report && e.bytes.empty()) fail("a report without bytes");
        // Only reports and arrivals (the USB ids) carry bytes: others with bytes are damaged.
        if (!e.bytes.empty() && e.kind != DeviceEventKind::Report &&
            e.kind != DeviceEventKind::Arrived)
            fail("a '" + kind + "' event carries no bytes");
        rec.events.push_back(std::move(e));
    }
    if (!header) throw RecordingError(source + ": empty file, not a vsculpt device recording");
    return rec;
}

bool isRecordingFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string first;
    std::getline(in, first);
    if (first.rfind(kByteOrderMark, 0) == 0) first.erase(0, kByteOrderMark.size());
    return first.rfind("vsculpt-recording", 0) == 0;
}

Recording readRecording(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw RecordingError(path.string() + ": cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    return parseRecording(text.str(), path.string());
}

}  // namespace vsculpt::devices
