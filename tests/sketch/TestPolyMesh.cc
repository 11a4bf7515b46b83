#include "vsculpt/sketch/PolyMesh.h"
#include "vsculpt/sketch/Polyline.h"

#include <gtest/gtest.h>

namespace vsculpt::sketch {
namespace {

PolyMesh unitCube() {
    PolyMesh cube;
    for (int i = 0; i < 8; ++i)
        cube.vertices.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    cube.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return cube;
}

TEST(PolyMesh, CubeCountsAndVolume) {
    const PolyMesh cube = unitCube();
    EXPECT_EQ(countEdges(cube), 12u);
    EXPECT_EQ(eulerCharacteristic(cube), 2);
    EXPECT_TRUE(isClosedOriented(cube));
    EXPECT_DOUBLE_EQ(enclosedVolume(cube), 1.0);
}

TEST(PolyMesh, OpenOrFlippedFaceIsDetected) {
    PolyMesh open = unitCube();
    open.faces.pop_back();
    EXPECT_FALSE(isClosedOriented(open));
    PolyMesh flipped = unitCube();
    std::swap(flipped.faces[0][1], flipped.faces[0][3]);
    EXPECT_FALSE(isClosedOriented(flipped));
}

TEST(Polyline, SquareAreaAndLength) {
    const Polyline2 square{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
    EXPECT_DOUBLE_EQ(signedArea(square), 4.0);
    EXPECT_DOUBLE_EQ(length(square, true), 8.0);
    EXPECT_DOUBLE_EQ(length(square, false), 6.0);
    const Polyline2 clockwise(square.rbegin(), square.rend());
    EXPECT_DOUBLE_EQ(signedArea(clockwise), -4.0);
}

}  // namespace
}  // namespace vsculpt::sketch
