// SPDX-License-Identifier: MIT
#include "vsculpt/studio/Script.h"

#include "vsculpt/core/Project.h"

#include <gtest/gtest.h>

using namespace vsculpt::studio;
using Kind = ScriptCommand::Kind;

namespace {

TEST(Script, ParsesEveryCommand) {
    const Script s = parseScript(R"(# a comment line
tool add
tool carve   # trailing comment
tool select
size 5
zoom 1
zoom 3 1.5 -2 30
object 10 20 30
object 1 2 3 0.7071068 0 0 0.7071068
space world
space object
stroke 0 0 0  1 2 3
stroke 0 0 0 \
       4 5 6 \
       7 8 9
undo
redo
save
probe 1 -2 3.5
expect inside 0 0 10
expect outside 0 0 99
)",
                                 "t.vsc");
    const std::vector<Kind> kinds = {
        Kind::Tool,   Kind::Tool,   Kind::Tool,  Kind::Size,  Kind::Zoom,   Kind::Zoom,
        Kind::Object, Kind::Object, Kind::Space, Kind::Space, Kind::Stroke, Kind::Stroke,
        Kind::Undo,   Kind::Redo,   Kind::Save,  Kind::Probe, Kind::Expect, Kind::Expect};
    ASSERT_EQ(s.commands.size(), kinds.size());
    for (size_t i = 0; i < kinds.size(); ++i)
        EXPECT_EQ(s.commands[i].kind, kinds[i]) << i;
    EXPECT_EQ(s.commands[0].tool, ToolKind::Add);
    EXPECT_EQ(s.commands[1].tool, ToolKind::Carve);
    EXPECT_EQ(s.commands[2].tool, ToolKind::Select);
    EXPECT_EQ(s.commands[3].value, 5);
    EXPECT_FALSE(s.commands[4].hasPoint);
    EXPECT_TRUE(s.commands[5].hasPoint);
    EXPECT_EQ(s.commands[5].point, vsculpt::core::Vec3(1.5, -2, 30));
    EXPECT_EQ(s.commands[6].pose.translation, vsculpt::core::Vec3(10, 20, 30));
    EXPECT_NEAR(s.commands[7].pose.rotation.w, 0.7071068, 1e-7);
    EXPECT_TRUE(s.commands[8].world);
    EXPECT_FALSE(s.commands[9].world);
    EXPECT_EQ(s.commands[10].points.size(), 2u);
    ASSERT_EQ(s.commands[11].points.size(), 3u);  // continued over three lines
    EXPECT_EQ(s.commands[11].line, 13);           // reported at its first line
    EXPECT_EQ(s.commands[11].points[2], vsculpt::core::Vec3(7, 8, 9));
    EXPECT_EQ(s.commands[1].line, 3);
    EXPECT_EQ(s.commands[15].point, vsculpt::core::Vec3(1, -2, 3.5));
    EXPECT_TRUE(s.commands[16].expectInside);
    EXPECT_EQ(s.commands[16].point, vsculpt::core::Vec3(0, 0, 10));
    EXPECT_FALSE(s.commands[17].expectInside);
}

struct Bad {
    const char* text;
    const char* expected;
};

TEST(Script, BadLinesNameTheirLine) {
    const Bad cases[] = {
        {"tool add\nstrok 1 2 3\n", "t.vsc:2: unknown command 'strok'"},
        {"\n\nsize\n", "t.vsc:3: 'size' takes a tool level 1..7 (got 0 argument(s))"},
        {"size five\n", "t.vsc:1: expected an integer for the tool level, got 'five'"},
        {"size 9\n", "t.vsc:1: tool level 9 outside 1..7"},
        {"zoom 6\n", "t.vsc:1: zoom level 6 outside 1..5"},
        {"zoom 3\n", "t.vsc:1: zoom 3 needs the region centre"},
        {"zoom 2 1 2\n", "t.vsc:1: 'zoom' takes Z or Z x y z"},
        {"tool brush\n", "t.vsc:1: unknown tool 'brush'"},
        {"stroke 1 2\n", "t.vsc:1: 'stroke' takes points x y z"},
        {"stroke 1 2 x\n", "t.vsc:1: expected a number for a stroke point, got 'x'"},
        {"stroke 1 2 nan\n", "t.vsc:1: expected a number for a stroke point, got 'nan'"},
        {"stroke 1 2 1e9\n", "t.vsc:1: a stroke point lies beyond 1e6 mm"},
        {"object 1 2 3 0 0 0 0\n", "t.vsc:1: the object rotation quaternion has zero length"},
        {"object 1 2\n", "t.vsc:1: 'object' takes x y z [qw qx qy qz]"},
        {"undo now\n", "t.vsc:1: 'undo' takes no arguments"},
        {"space up\n", "t.vsc:1: unknown space 'up'"},
        {"expect above 1 2 3\n", "t.vsc:1: unknown expectation 'above' (use inside or outside)"},
        {"expect inside 1 2\n", "t.vsc:1: 'expect' takes inside or outside, then a point x y z"},
        {"expect inside 1 2 z\n", "t.vsc:1: expected a number for the expected point, got 'z'"},
        {"probe 1 2\n", "t.vsc:1: 'probe' takes a point x y z (got 2 argument(s))"},
        {"tool add\nstroke 0 0 0 \\\n", "t.vsc:2: the command continued with '\\' never ends"},
        // A bad word in a command continued over lines is named on its own line.
        {"tool add\nstroke 0 0 0 \\\n  1 1 1 \\\n  2 x 2\n",
         "t.vsc:4: expected a number for a stroke point, got 'x'"},
        {"page p\npen 0,0 1,1 \\\n  2,2 nan,5 \\\n  6,6\n",
         "t.vsc:3: expected a number for a pen sample, got 'nan'"},
        {"page p\npen 0,0 \\\n 1,1 \\\n 2,2,3,4,5\n", "t.vsc:4: expected a pen sample as"},
    };
    for (const Bad& b : cases) {
        try {
            parseScript(b.text, "t.vsc");
            ADD_FAILURE() << "no error for: " << b.text;
        } catch (const ScriptError& e) {
            EXPECT_NE(std::string(e.what()).find(b.expected), std::string::npos)
                << "got: " << e.what() << "\nwanted: " << b.expected;
        }
    }
}

// A UTF-8 byte order mark (Windows editors write one) is not part of the first command; one
// anywhere else is still an unknown word, named with its line.
TEST(Script, AByteOrderMarkAtTheStartIsSkipped) {
    const Script s = parseScript("\xEF\xBB\xBFtool carve\r\nsize 5\r\n", "bom.vsc");
    ASSERT_EQ(s.commands.size(), 2u);
    EXPECT_EQ(s.commands[0].kind, Kind::Tool);
    EXPECT_EQ(s.commands[0].line, 1);
    EXPECT_EQ(s.commands[1].line, 2);
    try {
        parseScript("tool carve\n\xEF\xBB\xBFsize 5\n", "bom.vsc");
        ADD_FAILURE() << "a mark inside the file was taken";
    } catch (const ScriptError& e) {
        EXPECT_NE(std::string(e.what()).find("bom.vsc:2:"), std::string::npos) << e.what();
    }
}

// Found by QA: a file of lone CR line ends (classic Mac OS) was one line, all a comment when
// it began with one, and played as an empty script with exit 0. LF, CRLF and CR now give the
// same commands on the same lines; a comment line inside a continued command is skipped (it
// ended the command, which ran cut short).
TEST(Script, EveryLineEndGivesTheSameCommandsAndCommentsMayInterruptAContinuation) {
    const std::string lf =
        "# a snowman\ntool add\nsize 6\nstroke 0 0 50 \\\n# up\n  0 0 60 \\\n"
        "   # and on\n  0 0 70\nundo\n";
    auto crlf = lf, cr = lf;
    for (size_t at = 0; (at = crlf.find('\n', at)) != std::string::npos; at += 2)
        crlf.insert(at, "\r");
    for (char& c : cr)
        if (c == '\n') c = '\r';
    for (const std::string& text : {lf, crlf, cr}) {
        const Script s = parseScript(text, "ends.vsc");
        ASSERT_EQ(s.commands.size(), 4u);
        EXPECT_EQ(s.commands[0].kind, Kind::Tool);
        EXPECT_EQ(s.commands[2].kind, Kind::Stroke);
        EXPECT_EQ(s.commands[2].line, 4);
        ASSERT_EQ(s.commands[2].points.size(), 3u);
        EXPECT_EQ(s.commands[2].points[2].z, 70);
        EXPECT_EQ(s.commands[3].kind, Kind::Undo);
        EXPECT_EQ(s.commands[3].line, 9);
    }
    try {
        parseScript("tool add\rsize 6\rstroke 0 0 0 \\\r  0 0 x\r", "cr.vsc");
        ADD_FAILURE() << "a bad word was taken";
    } catch (const ScriptError& e) {
        EXPECT_NE(std::string(e.what()).find("cr.vsc:4:"), std::string::npos) << e.what();
    }
}

// The window names pages "Sketch 1", "Sketch 2": a script reaches them quoted (found by QA:
// `page "Sketch 1"` made a page named '"Sketch' in a group '1"').
TEST(Script, QuotedWordsMayHoldSpaces) {
    const Script s =
        parseScript("page \"Sketch 1\"\npage \"side view\" \"My group\"\npage plain\n", "q.vsc");
    ASSERT_EQ(s.commands.size(), 3u);
    EXPECT_EQ(s.commands[0].sketch.name, "Sketch 1");
    EXPECT_EQ(s.commands[0].sketch.group, "");
    EXPECT_EQ(s.commands[1].sketch.name, "side view");
    EXPECT_EQ(s.commands[1].sketch.group, "My group");
    EXPECT_EQ(s.commands[2].sketch.name, "plain");
    for (const char* bad : {"page \"Sketch 1\n", "page \"Sketch 1\"x\n"}) {
        try {
            parseScript(std::string("mode draft\n") + bad, "q.vsc");
            ADD_FAILURE() << bad;
        } catch (const ScriptError& e) {
            EXPECT_EQ(std::string(e.what()).rfind("q.vsc:2: ", 0), 0u) << e.what();
        }
    }
}

TEST(Script, MissingFileIsAnError) {
    EXPECT_THROW(loadScript("/nonexistent/script.vsc"), ScriptError);
}

}  // namespace

// Found by QA: a stroke of more samples than a journal record holds was refused by the
// project's journal after it had been sculpted (35 minutes for real samples), and the rest of
// the run was lost. It is refused when the script is read, with its line.
TEST(Script, AStrokeLongerThanAJournalHoldsIsRefusedWhenRead) {
    std::string text = "tool add\nstroke";
    text.reserve(text.size() + 6 * (vsculpt::core::kMaxStrokeSamples + 1) + 1);
    for (size_t i = 0; i <= vsculpt::core::kMaxStrokeSamples; ++i)
        text += " 0 0 0";
    text += "\n";
    try {
        parseScript(text, "long.vsc");
        ADD_FAILURE() << "taken";
    } catch (const ScriptError& e) {
        EXPECT_EQ(std::string(e.what()).find("long.vsc:2: a stroke of 2000001 points; a stroke "
                                             "may hold at most 2000000"),
                  0u)
            << e.what();
    }
}
