// SPDX-License-Identifier: MIT
#include "vsculpt/render/StereoCamera.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

using namespace vsculpt::render;

namespace {

glm::dmat4 someHeadPose() {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(30, 1200, -50));
    m = glm::rotate(m, glm::radians(25.0), glm::dvec3(0, 1, 0));
    return glm::rotate(m, glm::radians(-10.0), glm::dvec3(1, 0, 0));
}

TEST(StereoCamera, EyesAreOneInterpupillaryDistanceApartAlongTheHeadsX) {
    StereoDisplay d;
    d.ipdMm = 64.5;
    const glm::dmat4 head = someHeadPose();
    const auto eyes = stereoEyes(head, d);
    const glm::dvec3 sep = eyes[1].worldPosition - eyes[0].worldPosition;
    EXPECT_NEAR(glm::length(sep), 64.5, 1e-9);
    const glm::dvec3 headX = glm::normalize(glm::dvec3(head[0]));
    EXPECT_NEAR(glm::dot(glm::normalize(sep), headX), 1.0, 1e-12);
    // The midpoint is the head position.
    const glm::dvec3 mid = 0.5 * (eyes[0].worldPosition + eyes[1].worldPosition);
    EXPECT_NEAR(glm::length(mid - glm::dvec3(head[3])), 0.0, 1e-9);
}

TEST(StereoCamera, PointsOnTheFocalPlaneCoincideInBothEyes) {
    StereoDisplay d;
    d.focalDistanceMm = 700;
    d.aspect = 1.2;
    const glm::dmat4 head = someHeadPose();
    const auto eyes = stereoEyes(head, d);
    for (const glm::dvec2 xy : {glm::dvec2(0, 0), glm::dvec2(120, -40), glm::dvec2(-200, 90)}) {
        const glm::dvec3 p = glm::dvec3(head * glm::dvec4(xy.x, xy.y, -700, 1));
        const glm::dvec3 l = projectToNdc(eyes[0], p), r = projectToNdc(eyes[1], p);
        EXPECT_NEAR(l.x, r.x, 1e-12);
        EXPECT_NEAR(l.y, r.y, 1e-12);
    }
}

TEST(StereoCamera, NearPointsCrossAndFarPointsDoNot) {
    StereoDisplay d;
    d.ipdMm = 63;
    d.focalDistanceMm = 600;
    const glm::dmat4 head(1.0);
    const auto eyes = stereoEyes(head, d);
    const double top = std::tan(glm::radians(d.verticalFovDeg) * 0.5);
    auto parallax = [&](double distance) {  // right-eye x minus left-eye x, in NDC
        const glm::dvec3 p(0, 0, -distance);
        return projectToNdc(eyes[1], p).x - projectToNdc(eyes[0], p).x;
    };
    // Expected screen parallax of a point at distance z: ipd (1 - f/z) on the focal plane,
    // in NDC units of the half-width there (f tan(fov/2) aspect).
    for (double z : {300.0, 450.0, 900.0, 3000.0}) {
        const double expected =
            d.ipdMm * (1 - d.focalDistanceMm / z) / (d.focalDistanceMm * top * d.aspect);
        EXPECT_NEAR(parallax(z), expected, 1e-12) << z;
    }
    EXPECT_LT(parallax(300), 0);  // crossed: in front of the screen
    EXPECT_GT(parallax(3000), 0);
    // Mono: no parallax anywhere.
    d.ipdMm = 0;
    const auto mono = stereoEyes(head, d);
    EXPECT_EQ(projectToNdc(mono[0], {10, 5, -300}), projectToNdc(mono[1], {10, 5, -300}));
}

TEST(StereoCamera, RejectsImpossibleDisplays) {
    StereoDisplay d;
    d.verticalFovDeg = 190;
    EXPECT_THROW(stereoEyes(glm::dmat4(1.0), d), std::invalid_argument);
    d = StereoDisplay{};
    d.farMm = d.nearMm;
    EXPECT_THROW(stereoEyes(glm::dmat4(1.0), d), std::invalid_argument);
}

}  // namespace

#include "vsculpt/render/Palette.h"

namespace {

TEST(Palette, OffersExactlyTheAllowedSizesAndEveryZoomLevel) {
    const auto items = layoutPalette({5, 4, 3}, 4, 3);
    std::vector<int> sizes, zooms;
    for (const PaletteItem& it : items) {
        (it.kind == PaletteItem::Kind::Size ? sizes : zooms).push_back(it.value);
        EXPECT_EQ(it.current, it.kind == PaletteItem::Kind::Size ? it.value == 4 : it.value == 3);
        EXPECT_LT(it.x0, it.x1);
        EXPECT_GE(it.x0, -1.0);
        EXPECT_LE(it.x1, 1.0);
    }
    EXPECT_EQ(sizes, (std::vector<int>{5, 4, 3}));
    EXPECT_EQ(zooms, (std::vector<int>{1, 2, 3, 4, 5}));
    for (size_t i = 1; i < items.size(); ++i)
        EXPECT_GT(items[i].x0, items[i - 1].x1);  // no overlap
    for (const PaletteItem& it : items) {
        const PaletteItem* p = pickPalette(items, 0.5 * (it.x0 + it.x1), 0.5 * (it.y0 + it.y1));
        ASSERT_NE(p, nullptr);
        EXPECT_EQ(p->value, it.value);
        EXPECT_EQ(p->kind, it.kind);
    }
    EXPECT_EQ(pickPalette(items, 0, 0), nullptr);  // the middle of the view is for sculpting
}

}  // namespace

namespace {

TEST(Status, SevenSegmentDigitsAndTheStatusLine) {
    // Segment counts of 0..9: 6 2 5 5 4 5 6 3 7 6.
    const int segments[10] = {6, 2, 5, 5, 4, 5, 6, 3, 7, 6};
    for (int d = 0; d < 10; ++d)
        EXPECT_EQ(sevenSegmentNumber(d, 0, 0, 0.1).size(), size_t(segments[d]));
    EXPECT_EQ(sevenSegmentNumber(1234, 0, 0, 0.1).size(), size_t(2 + 5 + 5 + 4));
    // Digits advance to the right and stay inside their cell.
    const auto q = sevenSegmentNumber(88, 0.1, 0.2, 0.1);
    EXPECT_LT(q[0].x1, q[7].x0 + 1e-12);
    for (const auto& r : q) {
        EXPECT_GE(r.y0, 0.2 - 1e-12);
        EXPECT_LE(r.y1, 0.3 + 1e-12);
    }
    // The status line: a tool-coloured square, then size 5, zoom 3, 1234 skeletons, 17 ms.
    const auto s = statusQuads({1, 5, 3, 1234, 16.6});
    EXPECT_EQ(s.size(), size_t(1 + 5 + 5 + 16 + 2 + 3));
    EXPECT_GT(s[0].r, s[0].g);  // carve: red
    for (const auto& r : s) {
        EXPECT_GE(r.x0, -1.0);
        EXPECT_LE(r.x1, 1.0);
        EXPECT_GT(r.y0, 0.5);  // along the top edge, away from the palette
    }
}

}  // namespace
