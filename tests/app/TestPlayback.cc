// SPDX-License-Identifier: MIT
// Golden playback: the example scripts, checked by mesh properties (not pixels).
#include "vsculpt/app/Session.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace vsculpt;
using namespace vsculpt::app;

namespace {

std::unique_ptr<Session> play(const std::string& name) {
    const Script script = loadScript(std::filesystem::path(VSCULPT_EXAMPLES_DIR) / name);
    auto s = std::make_unique<Session>(core::loadConfig(core::defaultConfigPath()));
    bool world = false;
    for (const ScriptCommand& c : script.commands) {
        using K = ScriptCommand::Kind;
        switch (c.kind) {
            case K::Tool:
                s->setTool(c.tool);
                break;
            case K::Size:
                s->setSize(c.value);
                break;
            case K::Zoom:
                s->setZoom(c.value, c.point);
                break;
            case K::Object:
                s->setObjectPose(c.pose);
                break;
            case K::Space:
                world = c.world;
                break;
            case K::Stroke:
                s->stroke(c.points, world);
                break;
            case K::Undo:
                s->undo();
                break;
            case K::Redo:
                s->redo();
                break;
            case K::Save:
                s->save();
                break;
        }
        EXPECT_EQ(s->verifyMesh(), "") << name << ":" << c.line;
    }
    return s;
}

TEST(Playback, Snowman) {
    auto s = play("snowman.vsc");
    const core::Mesh mesh = s->wholeMesh(0.7);
    const core::MeshTopology topo = core::analyzeTopology(mesh);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.components, 1u);
    EXPECT_EQ(topo.eulerCharacteristic, 2);  // genus 0
    const double v = core::meshVolume(mesh);
    EXPECT_GT(v, 300000);  // body 268 000 mm^3 + head, hat, arms
    EXPECT_LT(v, 420000);
    const auto counts = s->sculpture().counts();
    // Large tools for the body parts, the smallest ones for the face and the letters.
    EXPECT_GT(counts.byLevel[0], 0u);   // level 1: letters
    EXPECT_GT(counts.byLevel[1], 0u);   // level 2: mouth
    EXPECT_GT(counts.byLevel[2], 0u);   // level 3: eyes
    EXPECT_GT(counts.byLevel[4], 20u);  // level 5: arms and brim
    EXPECT_GT(counts.byLevel[6], 0u);   // level 7: head
    EXPECT_LT(counts.total(), 2000u);   // the thesis's scale: hundreds to about a thousand
    // The letters are only visible at fine resolution: the hat front differs between a
    // mesh at the zoom-5 spacing and one at zoom 1 by much more than the eyes region.
    const core::Aabb box = core::meshBounds(mesh);
    EXPECT_GT(box.max.z, 105);  // the hat
    EXPECT_GT(box.max.x, 70);   // the arms
}

TEST(Playback, MugHasAHandle) {
    auto s = play("mug.vsc");
    const core::Mesh mesh = s->wholeMesh(1.0);
    const core::MeshTopology topo = core::analyzeTopology(mesh);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.components, 1u);
    EXPECT_EQ(topo.eulerCharacteristic, 0);  // genus 1: the handle makes a hole
}

TEST(Playback, DumbbellCutInTwo) {
    auto s = play("dumbbell.vsc");
    const core::Mesh mesh = s->wholeMesh(1.0);
    const core::MeshTopology topo = core::analyzeTopology(mesh);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.components, 2u);
    EXPECT_EQ(topo.eulerCharacteristic, 4);
    // Undo the cut: one piece again.
    s->undo();
    EXPECT_EQ(core::analyzeTopology(s->wholeMesh(1.0)).components, 1u);
}

}  // namespace
