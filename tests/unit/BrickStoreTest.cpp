// A store that grows brick by brick against one built on the final layout at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "rangefuse/volume/BrickStore.h"

using namespace rangefuse;

namespace {

/// A layout of `codes` (sorted) owned by one rank, on a lattice of 4-voxel bricks.
BrickLayout oneRank(const std::vector<uint64_t>& codes) {
  BrickLayout l;
  l.grid.voxel = 1;
  l.grid.brick = 4;
  l.codes = codes;
  l.work.assign(codes.size(), 1);
  l.setRuns({0, codes.size()});
  return l;
}

/// A value that names its brick and voxel.
float tag(uint64_t code, size_t voxel) {
  return static_cast<float>(code * 100 + voxel);
}

}  // namespace

TEST(BrickStore, GrowsWithoutMovingAndSortsBackToTheStoreBuiltAtOnce) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<uint64_t> u(0, 5000);
  std::set<uint64_t> all;
  BrickStore grown(oneRank({}), 0);
  for (int batch = 0; batch < 20; ++batch) {
    std::vector<uint64_t> fresh;
    for (int k = 0; k < 15; ++k) {
      const uint64_t code = u(rng);
      if (all.insert(code).second) fresh.push_back(code);
    }
    const std::vector<uint64_t> sorted(all.begin(), all.end());
    grown.grow(oneRank(sorted), fresh);
    // The bricks held before keep their values; the new ones start at zero.
    const size_t per = grown.voxelsPerBrick();
    for (const uint64_t code : fresh) {
      const int64_t b = grown.localBrick(code);
      ASSERT_GE(b, 0);
      for (size_t v = 0; v < per; ++v) {
        VoxelSums& s = grown.sums()[static_cast<size_t>(b) * per + v];
        ASSERT_EQ(s.w, 0);
        s.w = tag(code, v);
      }
    }
  }
  EXPECT_FALSE(grown.ordered());
  grown.sortBricks();
  ASSERT_TRUE(grown.ordered());

  const std::vector<uint64_t> sorted(all.begin(), all.end());
  const BrickStore direct(oneRank(sorted), 0);
  ASSERT_EQ(grown.brickCount(), direct.brickCount());
  const size_t per = grown.voxelsPerBrick();
  for (size_t b = 0; b < grown.brickCount(); ++b) {
    ASSERT_EQ(grown.code(b), direct.code(b));
    ASSERT_EQ(grown.localBrick(grown.code(b)), static_cast<int64_t>(b));
    for (size_t v = 0; v < per; ++v) ASSERT_EQ(grown.sums()[b * per + v].w, tag(grown.code(b), v));
  }
}

TEST(BrickStore, GrowingInCodeOrderStaysOrdered) {
  BrickStore store(oneRank({2, 5}), 0);
  store.grow(oneRank({2, 5, 9, 11}), {9, 11});
  EXPECT_TRUE(store.ordered());
  store.grow(oneRank({1, 2, 5, 9, 11}), {1});
  EXPECT_FALSE(store.ordered());
}
