#include "vsculpt/sketch/Chaikin.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vsculpt::sketch {
namespace {

const Polyline2 kSquare{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};

TEST(Chaikin, VertexCountDoublesPerLevel) {
    for (int k = 0; k <= 6; ++k)
        EXPECT_EQ(chaikin(kSquare, k).size(), 4u << k);
    const Polyline3 triangle{{0, 0, 0}, {1, 0, 1}, {0, 1, 2}};
    EXPECT_EQ(chaikin(triangle, 3).size(), 24u);
}

TEST(Chaikin, SquareAreaSequenceIsAnalytic) {
    // Each cut removes corner triangles; for [−1,1]² the area is 10/3 + (2/3)·4^−k.
    for (int k = 0; k <= 12; ++k)
        EXPECT_NEAR(signedArea(chaikin(kSquare, k)), 10.0 / 3.0 + (2.0 / 3.0) * std::pow(4.0, -k),
                    1e-12)
            << "level " << k;
}

TEST(Chaikin, NewPointsAreQuarterPoints) {
    const Polyline2 once = chaikin(kSquare, 1);
    EXPECT_EQ(once[0], glm::dvec2(-0.5, -1));
    EXPECT_EQ(once[1], glm::dvec2(0.5, -1));
    EXPECT_EQ(once[7], glm::dvec2(-1, -0.5));
}

TEST(Chaikin, LimitTouchesEdgeMidpointsAndIsTheSubdivisionLimit) {
    const Polyline2 concave{{0, 0}, {4, 0}, {4, 1}, {1.5, 1.2}, {1, 3}, {0, 3}};
    for (std::size_t i = 0; i < concave.size(); ++i) {
        const glm::dvec2 mid = 0.5 * (concave[i] + concave[(i + 1) % concave.size()]);
        const glm::dvec2 p = chaikinLimitPoint(concave, double(i));
        EXPECT_NEAR(p.x, mid.x, 1e-15);
        EXPECT_NEAR(p.y, mid.y, 1e-15);
    }
    // Every level shares the same limit curve, so the midpoint of edge j of the level-k
    // polygon is the limit point at u = j / 2^k, exactly.
    for (int k = 1; k <= 5; ++k) {
        const Polyline2 fine = chaikin(concave, k);
        for (std::size_t j = 0; j < fine.size(); ++j) {
            const glm::dvec2 mid = 0.5 * (fine[j] + fine[(j + 1) % fine.size()]);
            const glm::dvec2 p = chaikinLimitPoint(concave, double(j) / double(1 << k));
            EXPECT_NEAR(p.x, mid.x, 1e-12);
            EXPECT_NEAR(p.y, mid.y, 1e-12);
        }
    }
}

TEST(Chaikin, BadInputThrows) {
    EXPECT_THROW(chaikin(Polyline2{{0, 0}, {1, 0}}, 1), std::invalid_argument);
    EXPECT_THROW(chaikin(kSquare, -1), std::invalid_argument);
    EXPECT_THROW(chaikin(kSquare, 21), std::invalid_argument);
    Polyline2 nan = kSquare;
    nan[2].x = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(chaikin(nan, 1), std::invalid_argument);
    EXPECT_THROW(chaikinLimit(kSquare, 0), std::invalid_argument);
}

}  // namespace
}  // namespace vsculpt::sketch
