// SPDX-License-Identifier: MIT
#include "vsculpt/core/PatchConfigText.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using namespace vsculpt::core;

namespace {

// A user's file: comments of both kinds, its own order and layout, some sections only.
const std::string kFile = R"(// my vsculpt settings
{
  "render": {
    "ipd_mm": 63.0,   // measured at the optician
    /* the stereo I like */ "stereo": "sbs"
  },
  // nothing else here
  "interaction": {
    "rotate_rad_per_pixel": 0.01
  }
}
)";

SculptConfig loaded() {
    return parseConfig(kFile, "sculpt.json");
}

}  // namespace

TEST(PatchConfigText, NothingChangedLeavesTheTextByteForByte) {
    EXPECT_EQ(patchConfigText(kFile, loaded(), "sculpt.json"), kFile);
}

TEST(PatchConfigText, ChangedValuesAreReplacedWhereTheyStandAndCommentsStay) {
    SculptConfig cfg = loaded();
    cfg.render.ipdMm = 58.5;
    cfg.render.stereo = "anaglyph";
    const std::string out = patchConfigText(kFile, cfg, "sculpt.json");
    std::string expected = kFile;
    expected.replace(expected.find("63.0"), 4, "58.5");
    expected.replace(expected.find("\"sbs\""), 5, "\"anaglyph\"");
    EXPECT_EQ(out, expected);
    EXPECT_EQ(configToJson(parseConfig(out, "out")), configToJson(cfg));
}

TEST(PatchConfigText, KeysTheFileLacksAreAddedOnlyWhereTheyDifferFromTheDefault) {
    SculptConfig cfg = loaded();
    cfg.render.uiScale = 1.5;                     // a section the file has, a key it lacks
    cfg.interaction.depthStepOverDiameter = 0.5;  // likewise, in the other section
    cfg.d4Mm = 12;                                // a section the file lacks
    const std::string out = patchConfigText(kFile, cfg, "sculpt.json");
    EXPECT_EQ(configToJson(parseConfig(out, "out")), configToJson(cfg));
    // Everything the user wrote is still there, in order.
    size_t at = 0;
    for (const char* kept :
         {"// my vsculpt settings", "\"ipd_mm\": 63.0,   // measured at the optician",
          "/* the stereo I like */ \"stereo\": \"sbs\"", "// nothing else here",
          "\"rotate_rad_per_pixel\": 0.01"}) {
        const size_t p = out.find(kept, at);
        ASSERT_NE(p, std::string::npos) << kept << "\n" << out;
        at = p;
    }
    // Only the three keys were added (and "tools" around d4_mm): the rest are defaults.
    EXPECT_NE(out.find("\"ui_scale\": 1.5"), std::string::npos) << out;
    EXPECT_NE(out.find("\"depth_step_over_diameter\": 0.5"), std::string::npos) << out;
    EXPECT_NE(out.find("\"tools\": {\n    \"d4_mm\": 12.0\n  }"), std::string::npos) << out;
    EXPECT_EQ(out.find("\"growth\""), std::string::npos) << out;
    EXPECT_EQ(out.find("\"iso\""), std::string::npos) << out;
    EXPECT_EQ(out.find("\"bindings\""), std::string::npos) << out;
}

TEST(PatchConfigText, TheShippedTemplateTakesChangesEverywhereAndKeepsEveryComment) {
    // configs/sculpt.json: every key, nested sections, arrays of objects, a comment on most lines.
    std::ifstream in(std::filesystem::path(VSCULPT_CONFIG_DIR) / "sculpt.json");
    const std::string shipped((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
    ASSERT_FALSE(shipped.empty());
    SculptConfig cfg = parseConfig(shipped, "sculpt.json");
    cfg.d4Mm = 11;
    cfg.render.ipdMm = 60;
    cfg.render.stereo = "anaglyph";
    cfg.interaction.bindings["undo"] = "BACKSPACE";
    cfg.polygonizer.rootTolerance = 0.02;
    const std::string out = patchConfigText(shipped, cfg, "sculpt.json");
    EXPECT_EQ(configToJson(parseConfig(out, "out")), configToJson(cfg));
    // Every comment line of the template is still there, in order.
    size_t at = 0, comments = 0;
    for (size_t p = shipped.find("//"); p != std::string::npos; p = shipped.find("//", p + 1)) {
        const std::string comment = shipped.substr(p, shipped.find('\n', p) - p);
        const size_t q = out.find(comment, at);
        ASSERT_NE(q, std::string::npos) << comment;
        at = q;
        ++comments;
        p += comment.size() - 1;
    }
    EXPECT_GT(comments, 20u);
}

TEST(PatchConfigText, AnEmptyFileObjectTakesTheChanges) {
    SculptConfig cfg;
    cfg.render.ipdMm = 60;
    const std::string out = patchConfigText("{}\n", cfg, "sculpt.json");
    EXPECT_EQ(out, "{\n  \"render\": {\n    \"ipd_mm\": 60.0\n  }\n}\n");
    EXPECT_EQ(configToJson(parseConfig(out, "out")), configToJson(cfg));
    EXPECT_EQ(patchConfigText("{ /* empty */ }", SculptConfig{}, "s.json"), "{ /* empty */ }");
    // A byte order mark (some editors write one) stays where it is.
    EXPECT_EQ(patchConfigText("\xEF\xBB\xBF{}", cfg, "s.json"),
              "\xEF\xBB\xBF{\n  \"render\": {\n    \"ipd_mm\": 60.0\n  }\n}");
}

TEST(PatchConfigText, ABrokenFileIsAConfigErrorWithItsLine) {
    try {
        patchConfigText("{\n  \"render\": {\n    \"ipd_mm\": ,\n  }\n}\n", SculptConfig{},
                        "sculpt.json");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("sculpt.json:3"), std::string::npos) << e.what();
    }
}
