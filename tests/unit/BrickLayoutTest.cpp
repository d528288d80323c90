#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rangefuse/volume/BrickLayout.h"
#include "rangefuse/volume/VoxelGrid.h"

using namespace rangefuse;

TEST(Morton, RoundTripAndOrder) {
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> u(0, (1 << 21) - 1);
  for (int i = 0; i < 1000; ++i) {
    BrickCoord b(u(rng), u(rng), u(rng));
    EXPECT_EQ(mortonDecode(mortonEncode(b)), b);
  }
  EXPECT_EQ(mortonEncode({1, 0, 0}), 1u);
  EXPECT_EQ(mortonEncode({0, 1, 0}), 2u);
  EXPECT_EQ(mortonEncode({0, 0, 1}), 4u);
  EXPECT_EQ(mortonEncode({1, 1, 1}), 7u);
  EXPECT_EQ(mortonEncode({2, 0, 0}), 8u);
}

TEST(Partition, ContiguousRunsOfNearEqualWork) {
  std::vector<uint64_t> work(1000);
  std::mt19937 rng(2);
  std::uniform_int_distribution<int> u(1, 100);
  uint64_t total = 0, maxItem = 0;
  for (auto& w : work) total += w = u(rng), maxItem = std::max(maxItem, w);
  for (int ranks : {1, 2, 3, 7}) {
    auto start = partitionWork(work, ranks);
    ASSERT_EQ(start.size(), size_t(ranks + 1));
    EXPECT_EQ(start.front(), 0u);
    EXPECT_EQ(start.back(), work.size());
    for (int r = 0; r < ranks; ++r) {
      uint64_t sum = 0;
      for (size_t i = start[r]; i < start[r + 1]; ++i) sum += work[i];
      EXPECT_NEAR(double(sum), double(total) / ranks, double(maxItem) + 1) << ranks << " " << r;
    }
  }
  EXPECT_EQ(partitionWork({}, 3), (std::vector<size_t>{0, 0, 0, 0}));
}

TEST(FloorDiv, NegativeIndices) {
  EXPECT_EQ(floorDiv(-1, 8), -1);
  EXPECT_EQ(floorDiv(-8, 8), -1);
  EXPECT_EQ(floorDiv(-9, 8), -2);
  EXPECT_EQ(floorDiv(7, 8), 0);
}

TEST(CeilFloorToInt, EqualStdCeilAndFloorAcrossIntRange) {
  // Integers, values a hair either side of them, halves, signed zeros, and random values over
  // the whole int range: the int conversion must round as std::ceil and std::floor do.
  std::vector<double> xs = {0.0, -0.0, 0.5, -0.5, 1e-300, -1e-300, 2147483646.5, -2147483647.5};
  for (int k = -5; k <= 5; ++k)
    for (double e : {0.0, 1e-12, -1e-12, 0.25, -0.25})
      xs.push_back(k + e), xs.push_back(std::nextafter(k + e, 1e9)),
          xs.push_back(std::nextafter(k + e, -1e9));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> any(-2.1e9, 2.1e9), near(-100, 100);
  for (int i = 0; i < 100000; ++i) xs.push_back(i % 2 ? any(rng) : near(rng));
  for (double x : xs) {
    EXPECT_EQ(ceilToInt(x), static_cast<int>(std::ceil(x))) << x;
    EXPECT_EQ(floorToInt(x), static_cast<int>(std::floor(x))) << x;
  }
}
