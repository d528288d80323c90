// A scan's texels cut to the blocks a part's triangles use, and parts put back together: against
// brute force over every cell, on random sets of blocks.
#include <gtest/gtest.h>

#include <climits>
#include <random>
#include <set>

#include "rangefuse/surface/TexelImage.h"

using namespace rangefuse;

namespace {

/// A grid of rows x cols cells, one in five without a sample, the others all different.
TexelImage randomImage(int rows, int cols, std::mt19937& rng) {
  TexelImage t = TexelImage::blank(0, 0, rows, cols);
  for (size_t i = 0; i < t.cells.size(); ++i)
    if (rng() % 5) t.cells[i] = {uint8_t(i), uint8_t(i >> 8), uint8_t(i >> 16), 255};
  return t;
}

using Block = std::array<int32_t, 2>;

/// Whether cell (r, c) lies in one of the blocks.
bool inBlocks(const std::set<Block>& blocks, int k, long r, long c) {
  return blocks.count({int32_t(r / k), int32_t(c / k)}) > 0;
}

/// Every cell of `part` found in `whole`; those in `blocks` all held.
void expectPartOf(const TexelImage& part, const TexelImage& whole, const std::set<Block>& blocks,
                  int k, int rows, int cols) {
  for (long r = -2; r < rows + 2; ++r)
    for (long c = -2; c < cols + 2; ++c) {
      const Texel* got = part.at(r, c);
      const Texel* want = whole.at(r, c);
      if (got) {
        ASSERT_NE(want, nullptr) << r << ", " << c;
        EXPECT_EQ(*got, *want) << r << ", " << c;
      } else if (inBlocks(blocks, k, r, c)) {
        EXPECT_EQ(want, nullptr) << r << ", " << c << " is missing";
      }
    }
}

/// Random triangles over a grid of blockRows x blockCols blocks, one point a block: most with
/// corners within two blocks of each other (as merged and joined cells), a few closing a
/// station's seam (its first column to its last).
struct RandomSurface {
  std::vector<Block> blocks;
  std::vector<Triangle> triangles;

  RandomSurface(int blockRows, int blockCols, std::mt19937& rng) {
    for (int R = 0; R < blockRows; ++R)
      for (int C = 0; C < blockCols; ++C) blocks.push_back({R, C});
    const auto point = [&](int R, int C) {
      return int32_t(std::min(R, blockRows - 1) * blockCols + std::min(C, blockCols - 1));
    };
    for (int n = int(rng() % 12); n >= 0; --n) {
      const int R = int(rng() % blockRows), C = int(rng() % blockCols);
      if (rng() % 8 == 0)
        triangles.push_back({point(R, 0), point(R, blockCols - 1), point(R + 1, 0)});
      else
        triangles.push_back({point(R, C), point(R + int(rng() % 3), C + int(rng() % 3)),
                             point(R + int(rng() % 3), C)});
    }
  }

  /// The blocks between the corners of each listed triangle that takes texels, blocks of k.
  std::set<Block> needed(const std::vector<uint32_t>& pick, int k) const {
    std::set<Block> out;
    for (uint32_t t : pick) {
      int r0 = INT32_MAX, r1 = -1, c0 = INT32_MAX, c1 = -1;
      for (int32_t v : triangles[t]) {
        r0 = std::min(r0, blocks[v][0]), r1 = std::max(r1, blocks[v][0]);
        c0 = std::min(c0, blocks[v][1]), c1 = std::max(c1, blocks[v][1]);
      }
      if (!takesTexels(k, r1 - r0, c1 - c0)) continue;
      for (int R = r0; R <= r1; ++R)
        for (int C = c0; C <= c1; ++C) out.insert({R, C});
    }
    return out;
  }
};

}  // namespace

TEST(TexelImage, ABlankRectangleHoldsItsCellsUnsampled) {
  TexelImage t = TexelImage::blank(3, 5, 4, 6);
  EXPECT_EQ(t.rows(), 4);
  EXPECT_EQ(t.cells.size(), 24u);
  t.cell(4, 7) = {1, 2, 3, 255};
  for (long r = 0; r < 10; ++r)
    for (long c = 0; c < 14; ++c)
      EXPECT_EQ(t.at(r, c) != nullptr, r == 4 && c == 7) << r << ", " << c;
}

TEST(TexelImage, TriangleTexelsHoldTheCellsBetweenEachTrianglesCorners) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 60; ++trial) {
    const int k = 1 + int(rng() % 4), rows = 5 + int(rng() % 40), cols = 9 + int(rng() % 40);
    const TexelImage whole = randomImage(rows, cols, rng);
    // The last row and column of blocks partly outside the grid.
    const RandomSurface s((rows + k - 1) / k, (cols + k - 1) / k, rng);
    std::vector<uint32_t> pick, all;
    for (uint32_t t = 0; t < s.triangles.size(); ++t) {
      all.push_back(t);
      if (rng() % 2) pick.push_back(t);
    }
    const std::set<Block> needed = s.needed(pick, k);
    const TexelImage part = triangleTexels(whole, s.blocks, s.triangles, k, &pick);
    expectPartOf(part, whole, needed, k, rows, cols);
    // Held tightly: no row holds cells beyond the first and last of its needed blocks.
    for (long r = 0; r < part.rows(); ++r)
      for (uint32_t i = part.from[r]; i < part.from[r + 1]; ++i) {
        const long row = part.top + r, col = part.left[r] + long(i - part.from[r]);
        long first = cols, last = -1;
        for (const Block& b : needed)
          if (b[0] == row / k)
            first = std::min<long>(first, b[1]), last = std::max<long>(last, b[1]);
        EXPECT_TRUE(col / k >= first && col / k <= last) << row << ", " << col;
      }
    // Every triangle, without a list.
    expectPartOf(triangleTexels(whole, s.blocks, s.triangles, k), whole, s.needed(all, k), k, rows,
                 cols);
  }
}

TEST(TexelImage, PartsIncludedGiveBackEveryCellOfEither) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 40; ++trial) {
    const int k = 1 + int(rng() % 3), rows = 8 + int(rng() % 30), cols = 8 + int(rng() % 30);
    const TexelImage whole = randomImage(rows, cols, rng);
    const RandomSurface s((rows + k - 1) / k, (cols + k - 1) / k, rng);
    // Three parts of random triangles, overlapping.
    TexelImage joined;
    std::vector<uint32_t> all;
    for (int p = 0; p < 3; ++p) {
      std::vector<uint32_t> pick;
      for (uint32_t t = 0; t < s.triangles.size(); ++t)
        if (rng() % 3 == 0) pick.push_back(t), all.push_back(t);
      joined.include(triangleTexels(whole, s.blocks, s.triangles, k, &pick));
    }
    expectPartOf(joined, whole, s.needed(all, k), k, rows, cols);
  }
}
