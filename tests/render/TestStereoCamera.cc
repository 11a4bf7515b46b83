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

// Stills frame the box itself: every corner inside the picture less its 4 % margins, and the
// outline on those margins along one axis (so it fills the picture); the windows' sphere fit,
// which must keep a turning sculpture in view, draws the same box smaller. Tall, wide, deep and
// flat boxes off the origin, in portrait, square and wide pictures.
TEST(StereoCamera, AStillFramesTheBoxItselfTheWindowsItsBoundingSphere) {
    const glm::dvec3 sizes[] = {{80, 80, 160}, {200, 40, 50}, {40, 200, 40}, {60, 60, 0.5}};
    for (const glm::dvec3& size : sizes)
        for (double aspect : {2.0 / 3.0, 1.0, 16.0 / 9.0}) {
            const glm::dvec3 lo = glm::dvec3(-3, 7, 11) - 0.5 * size, hi = lo + size;
            double extent[2] = {0, 0};  // largest |NDC| over the corners: box fit, sphere fit
            for (FrameFit fit : {FrameFit::Box, FrameFit::Sphere}) {
                StereoDisplay d;
                d.ipdMm = 0;
                const glm::dmat4 head = frameFromFront(lo, hi, aspect, d, fit);
                const EyeView eye = stereoEyes(head, d)[0];
                double& e = extent[fit == FrameFit::Box ? 0 : 1];
                for (int c = 0; c < 8; ++c) {
                    const glm::dvec3 p(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y,
                                       c & 4 ? hi.z : lo.z);
                    const glm::dvec3 ndc = projectToNdc(eye, p);
                    EXPECT_GT(ndc.z, -1) << "in front of the near plane";
                    EXPECT_LT(ndc.z, 1) << "before the far plane";
                    if (fit == FrameFit::Box) {
                        EXPECT_LE(std::abs(ndc.x), 0.92 + 1e-9) << size.x << " " << aspect;
                        EXPECT_LE(std::abs(ndc.y), 0.92 + 1e-9) << size.x << " " << aspect;
                    }
                    e = std::max({e, std::abs(ndc.x), std::abs(ndc.y)});
                }
            }
            EXPECT_NEAR(extent[0], 0.92, 1e-9) << size.x << " " << size.z << " " << aspect;
            EXPECT_LT(extent[1], extent[0]) << size.x << " " << size.z << " " << aspect;
        }
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
