// SPDX-License-Identifier: MIT
#include "vsculpt/core/SkeletonStore.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

using namespace vsculpt::core;

namespace {

using Key = std::tuple<int, int, int, int>;  // level, x, y, z

void expectEqual(const SkeletonStore& s, const std::map<Key, float>& ref) {
    ASSERT_EQ(s.vertexCount(), ref.size());
    size_t visited = 0;
    s.forEach([&](const SkeletonEntry& e) {
        auto it = ref.find(Key{e.level, e.coord.x, e.coord.y, e.coord.z});
        ASSERT_NE(it, ref.end());
        EXPECT_EQ(it->second, e.weight);
        ++visited;
    });
    EXPECT_EQ(visited, ref.size());
    for (const auto& [k, w] : ref) {
        const auto [level, x, y, z] = k;
        EXPECT_EQ(s.get(level, LatticeCoord{x, y, z}), w);
    }
}

// Random sets, overwrites and erases (enough to trigger pool compaction) against std::map.
TEST(SkeletonStore, MatchesAReferenceMapUnderRandomEdits) {
    SkeletonStore s;
    std::map<Key, float> ref;
    std::mt19937 rng(17);
    std::uniform_int_distribution<int> level(1, kLevelCount), coord(-40, 40), op(0, 9);
    std::uniform_real_distribution<float> w(-2, 2);
    for (int i = 0; i < 200000; ++i) {
        const Key k{level(rng), coord(rng), coord(rng), coord(rng) / 4};
        const auto [l, x, y, z] = k;
        if (op(rng) < 3) {
            s.erase(l, LatticeCoord{x, y, z});
            ref.erase(k);
        } else {
            const float v = w(rng);
            s.set(l, LatticeCoord{x, y, z}, v);
            ref[k] = v;
        }
        ASSERT_EQ(s.vertexCount(), ref.size());
        if (i % 50000 == 49999) {
            const size_t before = s.memoryBytes();
            s.compact();
            EXPECT_LE(s.memoryBytes(), before);
            expectEqual(s, ref);
        }
    }
    expectEqual(s, ref);
    for (int k = 1; k <= kLevelCount; ++k) {
        size_t n = 0;
        for (const auto& [key, v] : ref)
            n += std::get<0>(key) == k;
        EXPECT_EQ(s.vertexCount(k), n);
    }
    const SkeletonStore copy = s.clone();
    s.set(1, LatticeCoord{1000, 0, 0}, 3.0f);  // the copy is deep
    expectEqual(copy, ref);
}

TEST(SkeletonStore, NegativeCoordinatesAndBlockEdges) {
    SkeletonStore s;
    const LatticeCoord cs[] = {{-1, -1, -1}, {-4, 0, 3}, {-5, -8, 4}, {3, 3, 3}, {0, 0, 0}};
    float v = 1;
    for (const auto& c : cs)
        s.set(2, c, v++);
    v = 1;
    for (const auto& c : cs)
        EXPECT_EQ(s.get(2, c), v++);
    EXPECT_FALSE(s.get(2, LatticeCoord{-2, -1, -1}).has_value());
    EXPECT_FALSE(s.get(3, LatticeCoord{0, 0, 0}).has_value());
}

TEST(SkeletonStore, RejectsOutOfRangeInput) {
    SkeletonStore s;
    EXPECT_THROW(s.set(0, LatticeCoord{}, 1), std::out_of_range);
    EXPECT_THROW(s.set(8, LatticeCoord{}, 1), std::out_of_range);
    EXPECT_THROW(s.set(1, LatticeCoord{1 << 23, 0, 0}, 1), std::out_of_range);
    EXPECT_EQ(s.vertexCount(), 0u);
}

}  // namespace
