#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <unordered_map>

#include "rangefuse/mesh/EdgeIndex.h"
#include "rangefuse/mesh/MarchingCubes.h"

using namespace rangefuse;

TEST(EdgeIndex, AgreesWithAStandardMapThroughGrowth) {
  // Edge keys of a small lattice (neighbours differ in low bits, as marching cubes asks them)
  // and random ones, many asked twice: every answer as std::unordered_map gives it.
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coord(0, 40), axis(0, 2);
  std::uniform_int_distribution<uint64_t> wide(0, (uint64_t{1} << 62) - 1);
  EdgeIndex index;
  std::unordered_map<uint64_t, int32_t> reference;
  for (int i = 0; i < 200000; ++i) {
    const uint64_t key =
        i % 3 ? edgeKey(VoxelIndex(coord(rng), coord(rng), coord(rng)), axis(rng)) : wide(rng);
    const auto [value, isNew] = index.emplace(key, static_cast<int32_t>(reference.size()));
    const auto [it, refNew] = reference.emplace(key, static_cast<int32_t>(reference.size()));
    ASSERT_EQ(isNew, refNew) << "key " << key;
    ASSERT_EQ(value, it->second) << "key " << key;
  }
  ASSERT_EQ(index.size(), reference.size());
  for (const auto& [key, value] : reference) ASSERT_EQ(index.find(key), value);
  EXPECT_GT(reference.size(), 100000u);  // the table grew many times over
  EXPECT_EQ(index.find(uint64_t{1} << 62), -1);
  EXPECT_THROW(index.at(uint64_t{1} << 62), std::out_of_range);
  EdgeIndex empty;
  EXPECT_EQ(empty.find(7), -1);
  empty.reserve(1000);
  EXPECT_EQ(empty.emplace(7, 3).first, 3);
  EXPECT_EQ(empty.emplace(7, 4).first, 3);
  EXPECT_EQ(empty.size(), 1u);
}
