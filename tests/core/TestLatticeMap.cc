// LatticeMap: a sparse map over lattice vertices in dense bricks (placement's targets).
#include "vsculpt/core/LatticeMap.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <vector>

using namespace vsculpt::core;

namespace {

// Against std::map over random vertices on both sides of every brick boundary (negative
// coordinates included, where a brick is found by flooring): the same keys, the same values,
// and references that stay where they were while the map grows.
TEST(LatticeMap, HoldsWhatAnOrderedMapHoldsAndNeverMovesAValue) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int32_t> coord(-20, 20);
    LatticeMap<int> map;
    std::map<LatticeCoord, int> reference;
    std::vector<std::pair<const int*, int>> kept;  // a value's address and what it must hold
    for (int i = 0; i < 20000; ++i) {
        const LatticeCoord v{coord(rng), coord(rng), coord(rng)};
        auto [value, inserted] = map.tryEmplace(v);
        const auto [it, refInserted] = reference.try_emplace(v, 0);
        ASSERT_EQ(inserted, refInserted);
        if (inserted) {
            EXPECT_EQ(*value, 0);  // default-constructed
            *value = i;
            it->second = i;
            kept.emplace_back(value, i);
        }
        EXPECT_EQ(*value, it->second);
    }
    EXPECT_EQ(map.size(), reference.size());
    for (const auto& [address, expected] : kept)
        EXPECT_EQ(*address, expected);
    for (int32_t x = -22; x <= 22; ++x)
        for (int32_t y = -22; y <= 22; ++y)
            for (int32_t z = -22; z <= 22; ++z) {
                const LatticeCoord v{x, y, z};
                const auto it = reference.find(v);
                const int* found = map.find(v);
                ASSERT_EQ(found != nullptr, it != reference.end()) << x << " " << y << " " << z;
                if (found) {
                    EXPECT_EQ(*found, it->second);
                }
                EXPECT_EQ(map.contains(v), found != nullptr);
            }
}

// The map remembers the bricks it looked up last, absent ones too, in slots shared by bricks
// 4 apart: lookups of absent vertices mixed with insertions, over 10 bricks per axis, must
// still agree with std::map at every step (a brick cached as absent and then created, or a
// slot's brick replaced by another, would show here).
TEST(LatticeMap, LookupsOfAbsentVerticesMixedWithInsertionsStayExact) {
    std::mt19937 rng(11);
    std::uniform_int_distribution<int32_t> coord(-40, 39);
    std::bernoulli_distribution insert(0.3);
    LatticeMap<int> map;
    std::map<LatticeCoord, int> reference;
    for (int i = 0; i < 40000; ++i) {
        const LatticeCoord v{coord(rng), coord(rng), coord(rng)};
        if (insert(rng)) {
            auto [value, inserted] = map.tryEmplace(v);
            ASSERT_EQ(inserted, reference.try_emplace(v, i).second);
            if (inserted) *value = i;
        }
        const auto it = reference.find(v);
        const int* found = map.find(v);
        ASSERT_EQ(found != nullptr, it != reference.end()) << i;
        if (found) {
            ASSERT_EQ(*found, it->second) << i;
        }
    }
    EXPECT_EQ(map.size(), reference.size());
}

TEST(LatticeMap, NeighboursAcrossABrickBoundaryAreDistinct) {
    LatticeMap<int> map;
    *map.tryEmplace({-1, 0, 0}).first = 1;
    *map.tryEmplace({0, 0, 0}).first = 2;
    *map.tryEmplace({7, 0, 0}).first = 3;
    *map.tryEmplace({8, 0, 0}).first = 4;
    *map.tryEmplace({-8, -8, -8}).first = 5;
    *map.tryEmplace({-9, -8, -8}).first = 6;
    EXPECT_EQ(*map.find({-1, 0, 0}), 1);
    EXPECT_EQ(*map.find({0, 0, 0}), 2);
    EXPECT_EQ(*map.find({7, 0, 0}), 3);
    EXPECT_EQ(*map.find({8, 0, 0}), 4);
    EXPECT_EQ(*map.find({-8, -8, -8}), 5);
    EXPECT_EQ(*map.find({-9, -8, -8}), 6);
    EXPECT_EQ(map.find({1, 0, 0}), nullptr);
    EXPECT_EQ(map.find({-2, 0, 0}), nullptr);
    EXPECT_EQ(map.size(), 6u);
}

}  // namespace
