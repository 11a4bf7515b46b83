// SPDX-License-Identifier: MIT
#include "vsculpt/core/Config.h"
#include "vsculpt/core/JsonNesting.h"

#include <gtest/gtest.h>

#include <string>

using namespace vsculpt::core;

namespace {

std::string nested(int levels, const std::string& inner = "1") {
    return std::string(size_t(levels), '[') + inner + std::string(size_t(levels), ']');
}

}  // namespace

TEST(JsonNesting, FindsTheBracketThatOpensOneLevelTooMany) {
    EXPECT_FALSE(jsonNestingBeyond(nested(64)).has_value());
    EXPECT_EQ(jsonNestingBeyond(nested(65)), "1:65: nested more than 64 levels deep");
    EXPECT_EQ(jsonNestingBeyond("{\"a\":\n  [[[1]]]}", 3), "2:5: nested more than 3 levels deep");
    // Levels closed before count no more.
    EXPECT_FALSE(jsonNestingBeyond("[[1],[2],{\"a\":[3]}]", 3).has_value());
}

TEST(JsonNesting, BracketsInStringsAndCommentsDoNotCount) {
    const std::string deep = std::string(100, '[');
    EXPECT_FALSE(jsonNestingBeyond("[\"" + deep + "\"]", 2).has_value());
    // An escaped quote does not end the string.
    EXPECT_FALSE(jsonNestingBeyond("[\"\\\"" + deep + "\"]", 2).has_value());
    EXPECT_FALSE(jsonNestingBeyond("// " + deep + "\n[1]", 2).has_value());
    EXPECT_FALSE(jsonNestingBeyond("/* " + deep + " */ [1]", 2).has_value());
    // After a comment or a string the brackets count again.
    EXPECT_EQ(jsonNestingBeyond("/* [ */ [\"[\", [[1]]]", 2),
              "1:16: nested more than 2 levels deep");
}

// Found by fuzzing: nlohmann::json parses any depth, but quoting the value in the error message
// (dump(), recursive) overflowed the stack on 200 000 nested arrays: the program died without a
// word. Now the file, line and column of the level too many.
TEST(JsonNesting, AConfigNestedTooDeepIsRefusedWithItsLine) {
    const std::string text = "{\n  \"render\": {\"stereo\": " + nested(200000) + "}\n}\n";
    std::string what;
    try {
        parseConfig(text, "deep.json");
    } catch (const ConfigError& e) {
        what = e.what();
    }
    EXPECT_EQ(what, "deep.json:2:86: nested more than 64 levels deep");
    // A config as deep as allowed still parses up to its first wrong value.
    try {
        parseConfig("{\"render\": {\"stereo\": " + nested(62) + "}}", "ok.json");
        ADD_FAILURE() << "a nested array is not a stereo mode";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("ok.json: render.stereo"), std::string::npos)
            << e.what();
    }
}
