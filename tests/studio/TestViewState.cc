// SPDX-License-Identifier: MIT
// Where a sculptor left off (view.json): the tool, size, zoom, mirror and pose go to text and
// come back bit for bit; a file that was edited or damaged is refused naming the file and
// the field, never half read.
#include "vsculpt/studio/ViewState.h"

#include "vsculpt/studio/Session.h"
#include "vsculpt/studio/Studio.h"

#include "../TestFixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

using namespace vsculpt;
using core::Vec3;
using studio::ViewState;

namespace {

ViewState turnedAndZoomed() {
    ViewState v;
    v.tool = studio::ToolKind::Carve;
    v.mirror = core::MirrorAxis::Y;
    v.size = 3;
    v.zoom = 3;
    v.zoomCentreMm = Vec3(1.0 / 3, -12.75, 31.125);
    // Not a round rotation: every bit of it must survive the text.
    v.worldFromObject.rotation = glm::angleAxis(0.7318, glm::normalize(Vec3(0.3, -0.8, 0.52))) *
                                 glm::angleAxis(2.1, glm::normalize(Vec3(-0.1, 0.2, 0.97)));
    v.worldFromObject.translation = Vec3(12.5, -1e-7, 1234.5678901234);
    return v;
}

std::string replaced(const std::string& field, const nlohmann::json& value) {
    nlohmann::json j = nlohmann::json::parse(studio::viewStateJson(turnedAndZoomed()));
    j[field] = value;
    return j.dump();
}

std::string refusal(const std::string& text) {
    try {
        studio::parseViewState(text, "P/view.json");
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(ViewState, TextRoundTripsBitForBit) {
    const ViewState v = turnedAndZoomed();
    const ViewState back = studio::parseViewState(studio::viewStateJson(v), "view.json");
    EXPECT_EQ(back, v);  // operator== compares every double exactly
    for (studio::ToolKind t : {studio::ToolKind::Add, studio::ToolKind::Carve,
                               studio::ToolKind::Smooth, studio::ToolKind::Select}) {
        for (core::MirrorAxis m : {core::MirrorAxis::None, core::MirrorAxis::X, core::MirrorAxis::Y,
                                   core::MirrorAxis::Z}) {
            ViewState w = v;
            w.tool = t;
            w.mirror = m;
            EXPECT_EQ(studio::parseViewState(studio::viewStateJson(w), "view.json"), w);
        }
    }
}

TEST(ViewState, BadFieldsAreRefusedNamingTheFileAndTheField) {
    struct Case {
        std::string field;
        nlohmann::json value;
        std::string says;
    };
    const std::vector<Case> cases = {
        {"tool", "chisel", "field 'tool': 'chisel' is not add, carve, smooth or select"},
        {"mirror", "w", "field 'mirror': 'w' is not x, y, z or off"},
        {"size", 8, "field 'size': 8 is not a whole number in 1..7"},
        {"size", 2.5, "field 'size': 2.5 is not a whole number in 1..7"},
        {"zoom", 0, "field 'zoom': 0 is not a whole number in 1..5"},
        {"zoom_centre_mm", nlohmann::json::array({0, 1e300, 0}),
         "field 'zoom_centre_mm': not a point within 1e6 mm of the origin"},
        {"zoom_centre_mm", nlohmann::json::array({0, 1}),
         "field 'zoom_centre_mm': not an array of 3 numbers"},
        {"object_translation_mm", nlohmann::json::array({0, "a", 0}),
         "field 'object_translation_mm': element 1 is not a finite number"},
        {"object_rotation_wxyz", nlohmann::json::array({1, 0, 0, 0.1}),
         "field 'object_rotation_wxyz': not a unit quaternion"},
        {"object_rotation_wxyz", nlohmann::json::array({0, 0, 0, 0}),
         "field 'object_rotation_wxyz': not a unit quaternion"},
        {"format", "vsculpt-snapshot", "field 'format': not \"vsculpt-view\""},
        {"version", 2, "field 'version': 2 is newer than this vsculpt reads (1)"},
    };
    for (const Case& c : cases) {
        const std::string said = refusal(replaced(c.field, c.value));
        EXPECT_EQ(said, "P/view.json: " + c.says) << c.field << " = " << c.value.dump();
    }
    nlohmann::json j = nlohmann::json::parse(studio::viewStateJson(turnedAndZoomed()));
    j.erase("zoom");
    EXPECT_EQ(refusal(j.dump()), "P/view.json: field 'zoom': missing");
    EXPECT_EQ(refusal("[1, 2]"), "P/view.json: not a JSON object");
    // nlohmann stops at a NUL: what follows one must not pass unread.
    EXPECT_EQ(refusal(studio::viewStateJson(turnedAndZoomed()) + std::string(1, '\0') + "{"),
              "P/view.json: a NUL byte at offset " +
                  std::to_string(studio::viewStateJson(turnedAndZoomed()).size()) +
                  " (not a view file)");
    // A file cut short (a full disk): the line and column where the text stops.
    const std::string text = studio::viewStateJson(turnedAndZoomed());
    const std::string cut = refusal(text.substr(0, text.size() / 2));
    EXPECT_EQ(cut.rfind("P/view.json:", 0), 0u) << cut;
    EXPECT_NE(cut.find("invalid JSON"), std::string::npos) << cut;
}

TEST(ViewState, ASessionsStateGoesToTheFileAndBackOntoAnotherStudio) {
    test::TempDir temp;
    const core::SculptConfig cfg = test::smallConfig(25);
    ViewState kept;
    {
        studio::Studio a(cfg);
        studio::applyViewState(a, turnedAndZoomed());
        kept = studio::viewStateOf(a.session());
        EXPECT_EQ(kept, turnedAndZoomed());
        studio::writeViewState(temp.path, kept);
    }
    EXPECT_FALSE(studio::readViewState(temp.path / "nowhere").has_value());
    const auto read = studio::readViewState(temp.path);
    ASSERT_TRUE(read.has_value());
    studio::Studio b(cfg);
    studio::applyViewState(b, *read);
    EXPECT_EQ(studio::viewStateOf(b.session()), kept);
    // The zoom region is the one the first studio had.
    studio::Studio c(cfg);
    c.setZoom(3, kept.zoomCentreMm);
    EXPECT_EQ(b.session().region().originCell, c.session().region().originCell);
    EXPECT_EQ(b.session().region().spacingMm, c.session().region().spacingMm);
}

TEST(ViewState, ASizeTheZoomDoesNotOfferIsASessionError) {
    studio::Studio s(test::smallConfig(25));
    ViewState v = turnedAndZoomed();
    v.zoom = 1;
    v.size = 2;  // zoom 1 offers 5, 6, 7
    EXPECT_THROW(studio::applyViewState(s, v), studio::SessionError);
}
