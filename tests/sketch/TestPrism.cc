#include "vsculpt/sketch/Prism.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

TEST(Prism, ClosedOutwardAndVolumeIsAreaTimesLength) {
    const Polyline2 concave{{0, 0}, {4, 0}, {4, 1}, {1.5, 1.2}, {1, 3}, {0, 3}};
    const Polyline2 clockwise(concave.rbegin(), concave.rend());
    for (Axis axis : {Axis::X, Axis::Y, Axis::Z})
        for (const Polyline2* section : {&concave, &clockwise}) {
            const PolyMesh prism = sweepPrism(*section, axis, -1.5, 2.5);
            EXPECT_TRUE(isClosedOriented(prism));
            EXPECT_EQ(eulerCharacteristic(prism), 2);
            EXPECT_EQ(prism.faces.size(), concave.size() + 2);
            EXPECT_NEAR(enclosedVolume(prism), std::abs(signedArea(concave)) * 4.0, 1e-9);
        }
}

TEST(Prism, SectionCoordinatesRoundTrip) {
    for (Axis axis : {Axis::X, Axis::Y, Axis::Z}) {
        const glm::dvec3 p = sectionToWorld(axis, {1.5, -2.5}, 7);
        EXPECT_EQ(worldToSection(axis, p), glm::dvec2(1.5, -2.5));
    }
    EXPECT_EQ(sectionToWorld(Axis::X, {1, 2}, 3), glm::dvec3(3, 1, 2));
    EXPECT_EQ(sectionToWorld(Axis::Y, {1, 2}, 3), glm::dvec3(1, 3, 2));
}

TEST(Prism, BadSectionsThrow) {
    EXPECT_THROW(sweepPrism({{0, 0}, {1, 0}}, Axis::Z, 0, 1), std::invalid_argument);
    EXPECT_THROW(sweepPrism({{0, 0}, {1, 0}, {2, 0}}, Axis::Z, 0, 1), std::invalid_argument);
    // Bow tie: edges 0 and 2 cross.
    EXPECT_THROW(sweepPrism({{0, 0}, {1, 1}, {1, 0}, {0, 1}}, Axis::Z, 0, 1),
                 std::invalid_argument);
    EXPECT_THROW(sweepPrism({{0, 0}, {1, 0}, {0, 1}}, Axis::Z, 1, 1), std::invalid_argument);
    EXPECT_THROW(sweepPrism({{0, 0}, {1, 0}, {0, std::nan("")}}, Axis::Z, 0, 1),
                 std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
