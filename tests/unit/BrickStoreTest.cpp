// A store that grows brick by brick against one built on the final layout at once, and one
// that a new split rehomes: the bricks that stay keep their values, the arriving ones start at
// zero.
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

TEST(BrickStore, RehomedKeepsTheBricksThatStayAndTakesTheArrivingOnesAtZero) {
  // Rank 1 of two holds codes from 100 on of 0..297 (every third code a brick), with colour;
  // a new split moves its range's start to 150: its bricks below 150 leave.
  std::vector<uint64_t> codes;
  for (uint64_t c = 0; c < 300; c += 3) codes.push_back(c);
  BrickLayout before = oneRank(codes), after = oneRank(codes);
  before.firstCodes = {0, 100, ~uint64_t{0}};
  after.firstCodes = {0, 150, ~uint64_t{0}};
  before.rankStart = runsOf(codes, before.firstCodes);
  after.rankStart = runsOf(codes, after.firstCodes);
  BrickStore store(before, 1);
  store.enableColour(ColourKind::rgb);
  const size_t per = store.voxelsPerBrick();
  for (size_t b = 0; b < store.brickCount(); ++b)
    for (size_t v = 0; v < per; ++v) {
      store.sums()[b * per + v].w = tag(store.code(b), v);
      store.colours()[b * per + v].c[0] = static_cast<uint16_t>(store.code(b));
    }
  std::vector<uint64_t> arriving;  // none arrive in this split: rank 1 loses [100, 150)
  store.rehome(after, arriving);
  std::set<uint64_t> held;
  for (size_t b = 0; b < store.brickCount(); ++b) {
    const uint64_t code = store.code(b);
    held.insert(code);
    ASSERT_EQ(store.localBrick(code), static_cast<int64_t>(b));
    for (size_t v = 0; v < per; ++v) {
      ASSERT_EQ(store.sums()[b * per + v].w, tag(code, v));
      ASSERT_EQ(store.colours()[b * per + v].c[0], code);
    }
  }
  std::set<uint64_t> expected;
  for (uint64_t c : codes)
    if (c >= 150) expected.insert(c);
  EXPECT_EQ(held, expected);
  for (uint64_t c : codes) {
    if (c < 150) {
      EXPECT_EQ(store.localBrick(c), -1);
    }
  }
  EXPECT_FALSE(store.ordered());

  // Back to [100, ...): the bricks of [100, 150) arrive, at zero, after the others.
  for (uint64_t c : codes)
    if (c >= 100 && c < 150) arriving.push_back(c);
  store.rehome(before, arriving);
  ASSERT_EQ(store.brickCount(), expected.size() + arriving.size());
  for (uint64_t c : arriving) {
    const int64_t b = store.localBrick(c);
    ASSERT_GE(b, static_cast<int64_t>(expected.size()));
    for (size_t v = 0; v < per; ++v) {
      ASSERT_EQ(store.sums()[static_cast<size_t>(b) * per + v].w, 0);
      ASSERT_EQ(store.colours()[static_cast<size_t>(b) * per + v].c[0], 0);
    }
  }
  for (uint64_t c : expected) {
    const size_t b = static_cast<size_t>(store.localBrick(c));
    ASSERT_EQ(store.sums()[b * per].w, tag(c, 0));
  }
}
