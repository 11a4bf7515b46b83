// SPDX-License-Identifier: MIT
// What an export at a given spacing says it loses: the smallest tool size the done strokes
// used, the zoom that first offers it, and a spacing that keeps it.
#include "vsculpt/app/ExportDetail.h"
#include "vsculpt/core/Zoom.h"
#include "vsculpt/studio/Session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

using namespace vsculpt;
using core::Vec3;

namespace {

core::SculptConfig smallSphere() {
    core::SculptConfig cfg;
    cfg.sphereRadiusMm = 25;
    cfg.polygonizer.gridN = 32;
    return cfg;
}

/// The number after "--export-spacing " in a warning.
double namedSpacing(const std::string& said) {
    const size_t at = said.find("--export-spacing ");
    EXPECT_NE(at, std::string::npos) << said;
    return at == std::string::npos ? 0 : std::stod(said.substr(at + 17));
}

double spacingAt(const studio::Session& s, int zoom) {
    return core::zoomSpacing(s.sculpture().config(), s.sculpture().levels(), zoom);
}

}  // namespace

TEST(ExportDetail, NamesTheFinestSizeItsZoomAndASpacingThatKeepsIt) {
    studio::Session s(smallSphere());
    const double zoom1 = spacingAt(s, 1);
    // The initial sphere and zoom-1 sizes: nothing lost at zoom 1's spacing.
    EXPECT_EQ(app::exportDetailWarning(s, zoom1), "");
    s.setSize(6);
    s.stroke({Vec3(-20, 0, 20), Vec3(20, 0, 20)}, false);
    EXPECT_EQ(app::exportDetailWarning(s, zoom1), "");

    // A size-3 stroke (offered from zoom 3 on).
    s.setZoom(3, Vec3(0, 0, 25));
    s.setSize(3);
    s.stroke({Vec3(-5, 0, 25), Vec3(5, 0, 25)}, false);
    const double zoom3 = spacingAt(s, 3);
    const std::string said = app::exportDetailWarning(s, zoom1);
    EXPECT_NE(said.find("clay of size 3, shown in full from zoom 3"), std::string::npos) << said;
    // The spacing it names keeps the detail (what the sentence promises) and is zoom 3's
    // within the three digits it prints.
    const double named = namedSpacing(said);
    EXPECT_LE(named, zoom3);
    EXPECT_GT(named, 0.99 * zoom3);
    EXPECT_EQ(app::exportDetailWarning(s, named), "");
    // At that spacing, or finer, nothing is lost; a little coarser is.
    EXPECT_EQ(app::exportDetailWarning(s, zoom3), "");
    EXPECT_EQ(app::exportDetailWarning(s, zoom3 / 2), "");
    EXPECT_NE(app::exportDetailWarning(s, zoom3 * 1.01), "");

    // Undone strokes are not in the sculpture: back to zoom-1 sizes.
    ASSERT_TRUE(s.undo());
    EXPECT_EQ(app::exportDetailWarning(s, zoom1), "");
    ASSERT_TRUE(s.redo());
    EXPECT_NE(app::exportDetailWarning(s, zoom1), "");
}

TEST(ExportDetail, ASculptureTooLargeForItsFinestZoomGetsTheFinestGridThatFits) {
    core::SculptConfig cfg = smallSphere();
    cfg.sphereRadiusMm = 120;  // 240 mm across: zoom 5's 0.18 mm would need ~1 400 cells
    studio::Session s(cfg);
    s.setZoom(5, Vec3(0, 0, 120));
    s.setSize(1);
    s.stroke({Vec3(-1, 0, 120), Vec3(1, 0, 120)}, false);
    const std::string said = app::exportDetailWarning(s, spacingAt(s, 1));
    EXPECT_NE(said.find("clay of size 1, shown in full from zoom 5"), std::string::npos) << said;
    EXPECT_NE(said.find("as much of it as the grid's 1024 cells per axis allow"), std::string::npos)
        << said;
    // The spacing it names fits Session::wholeMesh's 1 024 cells per axis (extent / spacing
    // + 3), and is within a percent of the finest that does.
    const core::Aabb bounds = s.sculpture().supportBounds();
    double extent = 0;
    for (int a = 0; a < 3; ++a)
        extent = std::max(extent, bounds.max[a] - bounds.min[a]);
    const double named = namedSpacing(said);
    EXPECT_GT(named, spacingAt(s, 5));
    EXPECT_LE(extent / named + 3, 1024.0);
    EXPECT_LT(named, 1.01 * extent / 1000);
    EXPECT_EQ(app::exportDetailWarning(s, named), "");
}
