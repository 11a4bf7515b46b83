// SPDX-License-Identifier: MIT
#include "vsculpt/core/PlyHeaderProblem.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <sstream>
#include <vector>

namespace vsculpt::core {

namespace {

/// Bytes of a PLY scalar type, 0 for a name that is not one.
size_t typeBytes(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
        t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

}  // namespace

std::string plyHeaderProblem(std::string_view start, uint64_t fileBytes) {
    const std::string_view head = start.substr(0, std::min(start.size(), kMaxPlyHeaderBytes));
    bool binary = false, haveFormat = false;
    uint64_t minimumBody = 0;  // bytes the elements need at least (binary formats)
    uint64_t elementBytes = 0, elementCount = 0;
    bool inElement = false;
    auto closeElement = [&] {
        if (!inElement) return;
        // Saturating: a count no file can hold must not wrap to a small size.
        const uint64_t most = UINT64_MAX - minimumBody;
        minimumBody = elementBytes != 0 && elementCount > most / elementBytes
                          ? UINT64_MAX
                          : minimumBody + elementCount * elementBytes;
        inElement = false;
    };
    size_t lineNo = 0, pos = 0;
    while (pos < head.size()) {
        ++lineNo;
        size_t eol = head.find('\n', pos);
        if (eol == std::string_view::npos) break;  // the header ran out before end_header
        std::string_view line = head.substr(pos, eol - pos);
        pos = eol + 1;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (lineNo == 1) {
            if (line != "ply") return "1: not a PLY file (the first line is not 'ply')";
            continue;
        }
        for (const char c : line)
            if ((c < 0x20 || c > 0x7e) && c != '\t')
                return std::to_string(lineNo) + ": not a text line of a PLY header";
        std::istringstream words{std::string(line)};
        std::string key;
        words >> key;
        const std::string at = std::to_string(lineNo) + ": ";
        if (key == "format") {
            std::string kind, version, extra;
            words >> kind >> version >> extra;
            if (haveFormat) return at + "a second format line";
            if (kind != "ascii" && kind != "binary_little_endian" && kind != "binary_big_endian")
                return at + "format '" + kind +
                       "': expected ascii, binary_little_endian or binary_big_endian";
            if (version != "1.0" || !extra.empty()) return at + "format version: expected 1.0";
            haveFormat = true;
            binary = kind != "ascii";
        } else if (key == "comment" || key == "obj_info" || key.empty()) {
            continue;
        } else if (key == "element") {
            std::string name, count, extra;
            words >> name >> count >> extra;
            uint64_t n = 0;
            const auto [ptr, ec] = std::from_chars(count.data(), count.data() + count.size(), n);
            if (name.empty() || count.empty() || ec != std::errc() ||
                ptr != count.data() + count.size() || !extra.empty())
                return at + "expected 'element NAME COUNT'";
            closeElement();
            inElement = true;
            elementCount = n;
            elementBytes = 0;
        } else if (key == "property") {
            if (!inElement) return at + "a property before any element";
            std::string type;
            words >> type;
            if (type == "list") {
                std::string countType, itemType, name, extra;
                words >> countType >> itemType >> name >> extra;
                if (typeBytes(countType) == 0 || typeBytes(itemType) == 0 || name.empty() ||
                    !extra.empty())
                    return at + "expected 'property list COUNT_TYPE ITEM_TYPE NAME'";
                elementBytes += typeBytes(countType);
            } else {
                std::string name, extra;
                words >> name >> extra;
                if (typeBytes(type) == 0 || name.empty() || !extra.empty())
                    return at + "expected 'property TYPE NAME' with a PLY type (got '" + type +
                           "')";
                elementBytes += typeBytes(type);
            }
        } else if (key == "end_header") {
            if (line != "end_header") return at + "expected 'end_header' alone";
            if (!haveFormat) return at + "no format line before end_header";
            closeElement();
            const uint64_t body = fileBytes > pos ? fileBytes - pos : 0;
            if (binary && body < minimumBody)
                return at + "the elements need at least " + std::to_string(minimumBody) +
                       " bytes after the header, the file has " + std::to_string(body);
            return "";
        } else {
            return at + "'" + key + "' is not a PLY header keyword";
        }
    }
    return std::to_string(lineNo) + ": the header ends without 'end_header'" +
           (fileBytes > kMaxPlyHeaderBytes ? " in its first 64 KiB" : "");
}

}  // namespace vsculpt::core
