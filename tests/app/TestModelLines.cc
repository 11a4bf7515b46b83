// SPDX-License-Identifier: MIT
// Drawing on the model through the app's projector (Embree on the mesh on show), as scripts,
// the sketch window and `vsculpt play` get it from the rig.
#include "vsculpt/app/Rig.h"

#include "../TestFixtures.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <iostream>

using namespace vsculpt;
using namespace vsculpt::studio;
using core::Vec3;
core::SculptConfig smallConfig() {
    return test::smallConfig(20);
}
using test::TempDir;

namespace {

app::RigOptions projectOptions(const std::filesystem::path& dir) {
    app::RigOptions o;
    o.project = app::ProjectChoice::Given;
    o.projectDir = dir;
    return o;
}

void runScript(Studio& studio, const std::string& text) {
    for (const ScriptCommand& c : parseScript(text, "test.vsc").commands)
        studio.apply(c);
}

}  // namespace

namespace {

TEST(Studio, DrawingOnTheModelGivesSurfaceLinesThatUndo) {
    TempDir dir;
    std::vector<Vec3> line;
    {
        auto rigStudio = std::make_unique<app::Rig>(smallConfig(), projectOptions(dir.path));
        Studio& studio = rigStudio->studio();
        const Session* session = &studio.session();
        // Across the initial sphere (radius 20) in a 400 x 300 front view, and one stroke that
        // misses it entirely.
        runScript(studio,
                  "model-line 400 300 20,150 120,150 200,151 280,150 380,150\n"
                  "model-line 400 300 5,5 40,10\n");
        ASSERT_EQ(studio.surfaceLines().size(), 1u);
        EXPECT_EQ(studio.stepCount(), 1u);
        const double h = session->view().region().spacingMm;
        line = studio.surfaceLines()[0];
        ASSERT_GT(line.size(), 10u);
        for (size_t i = 0; i < line.size(); ++i) {
            // On the polygonized sphere (within its grid's chord error), on the camera's side.
            EXPECT_NEAR(glm::length(line[i]), 20, 0.5 * h) << i;
            EXPECT_LT(line[i].y, 0) << i;
            if (i > 0) {
                // A third of the spacing apart, except across a step finer than the
                // projection's bisection limit (1/64 px), where the surface turns away from
                // the camera: on the sphere's rim, seen within 18 degrees of edge-on.
                const double gap = glm::distance(line[i], line[i - 1]);
                const bool rim = std::abs(line[i].y) < 0.3 * glm::length(line[i]) &&
                                 std::abs(line[i - 1].y) < 0.3 * glm::length(line[i - 1]);
                EXPECT_LE(gap, rim ? 10 * h : h / 3 + 1e-9)
                    << i << " of " << line.size() << ": " << line[i - 1].x << " " << line[i - 1].y
                    << " " << line[i - 1].z << " -> " << line[i].x << " " << line[i].y << " "
                    << line[i].z;
            }
        }
        // Across the whole silhouette: from one side of the sphere to the other.
        EXPECT_LT(line.front().x, -18);
        EXPECT_GT(line.back().x, 18);
        // The lines go to exports with the sketch's curves, and undo/redo take them away and back.
        EXPECT_EQ(studio.curvesInObjectSpace().size(), 1u);
        studio.undo();
        EXPECT_TRUE(studio.surfaceLines().empty());
        studio.redo();
        ASSERT_EQ(studio.surfaceLines().size(), 1u);
        EXPECT_EQ(studio.surfaceLines()[0], line);
    }  // closed: the project is unlocked
    // Kept in the project.
    auto reopenedPtr = Studio::openProject(dir.path, smallConfig());
    Studio& reopened = *reopenedPtr;
    ASSERT_EQ(reopened.surfaceLines().size(), 1u);
    EXPECT_EQ(reopened.surfaceLines()[0], line);
}

}  // namespace
