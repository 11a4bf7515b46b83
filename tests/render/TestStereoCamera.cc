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

namespace {

// The UI's disparity (eyeShiftNdc) against the projection itself: a point straight ahead at
// the UI's depth lands where the shifted UI is drawn in each eye, whatever the display.
TEST(StereoCamera, EyeShiftIsWhereAPointAtThatDepthIsDrawn) {
    for (double aspect : {0.8, 1.6})
        for (double depth : {150.0, 400.0, 600.0, 2000.0}) {
            StereoDisplay d;
            d.ipdMm = 63;
            d.focalDistanceMm = 600;
            d.aspect = aspect;
            const auto eyes = stereoEyes(glm::dmat4(1.0), d);
            for (int e = 0; e < 2; ++e)
                EXPECT_NEAR(eyeShiftNdc(d, depth, Eye(e)),
                            projectToNdc(eyes[size_t(e)], {0, 0, -depth}).x, 1e-12)
                    << depth << " " << e;
        }
    StereoDisplay d;
    EXPECT_GT(eyeShiftNdc(d, 300, Eye::Left), 0);  // nearer than the plane: crossed
    EXPECT_LT(eyeShiftNdc(d, 300, Eye::Right), 0);
    EXPECT_EQ(eyeShiftNdc(d, d.focalDistanceMm, Eye::Left), 0);
    EXPECT_EQ(eyeShiftNdc(d, 0, Eye::Left), 0);  // 0: on the zero-parallax plane
    d.ipdMm = 0;
    EXPECT_EQ(eyeShiftNdc(d, 300, Eye::Right), 0);
}

}  // namespace
