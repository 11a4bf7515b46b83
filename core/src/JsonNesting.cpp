// SPDX-License-Identifier: MIT
#include "vsculpt/core/JsonNesting.h"

namespace vsculpt::core {

namespace {

std::string tooDeepAt(std::string_view text, size_t at, int maxDepth) {
    size_t line = 1, lineStart = 0;
    for (size_t i = 0; i < at; ++i)
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    return std::to_string(line) + ":" + std::to_string(at - lineStart + 1) + ": nested more than " +
           std::to_string(maxDepth) + " levels deep";
}

}  // namespace

std::optional<std::string> jsonNestingBeyond(std::string_view text, int maxDepth) {
    int depth = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        switch (text[i]) {
            case '"':
                // To the closing quote; an unterminated string ends the text (the parser
                // reports it).
                for (++i; i < text.size() && text[i] != '"'; ++i)
                    if (text[i] == '\\') ++i;
                break;
            case '/':
                if (i + 1 < text.size() && text[i + 1] == '/') {
                    while (i < text.size() && text[i] != '\n')
                        ++i;
                } else if (i + 1 < text.size() && text[i + 1] == '*') {
                    const size_t end = text.find("*/", i + 2);
                    i = end == std::string_view::npos ? text.size() : end + 1;
                }
                break;
            case '[':
            case '{':
                if (++depth > maxDepth) return tooDeepAt(text, i, maxDepth);
                break;
            case ']':
            case '}':
                --depth;  // unbalanced closers are the parser's to report
                break;
            default:
                break;
        }
    }
    return std::nullopt;
}

}  // namespace vsculpt::core
