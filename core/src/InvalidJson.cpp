// SPDX-License-Identifier: MIT
#include "vsculpt/core/InvalidJson.h"

#include "vsculpt/core/PrintableText.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <regex>

namespace vsculpt::core {
namespace {

std::string lineColumnAt(std::string_view text, size_t byte) {
    byte = std::min(byte, text.size());
    size_t line = 1, lineStart = 0;
    for (size_t i = 0; i < byte; ++i)
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    return std::to_string(line) + ":" + std::to_string(byte - lineStart + 1);
}

/// Where the number token `number` first stands alone in `text` (not inside a longer token),
/// or npos. Strings are not skipped: a key spelled like the number is rare enough.
size_t findNumber(std::string_view text, std::string_view number) {
    auto partOfNumber = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '+' || c == '-';
    };
    for (size_t at = text.find(number); at != std::string_view::npos;
         at = text.find(number, at + 1)) {
        const size_t end = at + number.size();
        if ((at == 0 || !partOfNumber(text[at - 1])) &&
            (end == text.size() || !partOfNumber(text[end])))
            return at;
    }
    return std::string_view::npos;
}

}  // namespace

std::string invalidJsonMessage(const std::string& name, std::string_view text,
                               const std::exception& e) {
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 2, column 1: syntax error ...":
    // the id means nothing to a user, and the position is given before the message.
    what = std::regex_replace(what, std::regex(R"(^\[json\.exception\.[a-z_]+\.[0-9]+\] )"), "");
    what =
        std::regex_replace(what, std::regex(R"(^parse error at line [0-9]+, column [0-9]+: )"), "");
    what = std::regex_replace(what, std::regex(R"(^parse error: )"), "");
    std::string where;
    if (const auto* pe = dynamic_cast<const nlohmann::json::parse_error*>(&e)) {
        // byte is 1-based and points just past the character the parser stopped at.
        where = lineColumnAt(text, pe->byte > 0 ? pe->byte - 1 : 0);
    } else if (dynamic_cast<const nlohmann::json::out_of_range*>(&e)) {
        std::smatch m;
        if (std::regex_search(what, m, std::regex(R"(number overflow parsing '([^']*)')"))) {
            const std::string number = m[1];
            what = "the number " + number + " is out of range (a double reaches about 1.8e308)";
            if (const size_t at = findNumber(text, number); at != std::string_view::npos)
                where = lineColumnAt(text, at);
        }
    }
    return name + (where.empty() ? "" : ":" + where) +
           ": invalid JSON: " + printableText(what, 240);
}

}  // namespace vsculpt::core
