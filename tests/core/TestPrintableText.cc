// SPDX-License-Identifier: MIT
#include "vsculpt/core/Config.h"
#include "vsculpt/core/PrintableText.h"

#include <gtest/gtest.h>

#include <string>

using namespace vsculpt::core;

TEST(PrintableText, EscapesWhatATerminalWouldActOn) {
    EXPECT_EQ(printableText("size 7"), "size 7");
    EXPECT_EQ(printableText(std::string("\x7F"
                                        "ELF\x02\x01",
                                        6)),
              "\\x7FELF\\x02\\x01");
    EXPECT_EQ(printableText("a\tb\x1b[31m"), "a\\tb\\x1B[31m");
    EXPECT_EQ(printableText(std::string("nul\0x", 5)), "nul\\x00x");
    // Valid UTF-8 stays readable; broken sequences are escaped byte by byte.
    EXPECT_EQ(printableText("größe 7 — ok"), "größe 7 — ok");
    EXPECT_EQ(printableText("\xC3(\xE2\x82"), "\\xC3(\\xE2\\x82");
    EXPECT_EQ(printableText("\xED\xA0\x80"), "\\xED\\xA0\\x80");  // a UTF-16 surrogate
    EXPECT_EQ(printableText("\xC0\xAF"), "\\xC0\\xAF");           // overlong '/'
    // Long input is cut.
    EXPECT_EQ(printableText(std::string(500, 'a'), 10), std::string(10, 'a') + "...");
}

TEST(PrintableText, FindsBinaryData) {
    EXPECT_FALSE(firstBinaryByte("tool add\r\nsize 7\n\tstroke 0 0 0\f\n").has_value());
    EXPECT_FALSE(firstBinaryByte("# größe\n").has_value());
    EXPECT_EQ(firstBinaryByte(std::string("abc\0def", 7)), 3u);
    EXPECT_EQ(firstBinaryByte("ok\x1b[0m"), 2u);
    EXPECT_EQ(firstBinaryByte("\x7F"
                              "ELF"),
              0u);
}

TEST(PrintableText, ConfigErrorsNeverQuoteRawBytes) {
    std::string what;
    try {
        parseConfig(std::string("\x7F"
                                "ELF\x02\x01\x01\0\0",
                                9),
                    "bin.json");
    } catch (const ConfigError& e) {
        what = e.what();
    }
    ASSERT_FALSE(what.empty());
    EXPECT_NE(what.find("bin.json:1:1: invalid JSON"), std::string::npos) << what;
    EXPECT_FALSE(firstBinaryByte(what).has_value()) << what;
    what.clear();
    try {
        parseConfig(R"({"render": {"stereo": "\u001b[2J"}})", "esc.json");
    } catch (const ConfigError& e) {
        what = e.what();
    }
    ASSERT_FALSE(what.empty());
    EXPECT_NE(what.find("esc.json: render.stereo"), std::string::npos) << what;
    EXPECT_FALSE(firstBinaryByte(what).has_value()) << what;
}
