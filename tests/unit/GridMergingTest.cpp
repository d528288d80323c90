// Merging range-grid cells: known answers on planes, depth edges and pinhole pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "rangefuse/surface/GridMerging.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {
namespace {

/// A pinhole image of the plane z = -2 + 0.1 x + 0.05 y, `cols` x `rows` pixels.
RangeGrid planeImage(int cols, int rows) {
  RangeGrid g;
  g.cols = cols, g.rows = rows;
  g.pinhole = Pinhole{200, 200, 0.5 * (cols - 1), 0.5 * (rows - 1)};
  g.cell.assign(static_cast<size_t>(cols) * rows, -1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector3d ray((c - g.pinhole->cx) / 200, (r - g.pinhole->cy) / 200, -1);
      // n . (t ray) = -2 with n = (-0.1, -0.05, 1) and z = -2 + 0.1 x + 0.05 y.
      const double t = -2 / Eigen::Vector3d(-0.1, -0.05, 1).dot(ray);
      g.cell[static_cast<size_t>(r) * cols + c] = static_cast<int32_t>(g.points.size());
      g.points.push_back(t * ray);
    }
  return g;
}

double planeOffset(const Eigen::Vector3d& p) {
  return p.z() - (-2 + 0.1 * p.x() + 0.05 * p.y());
}

TEST(GridMerging, FactorKeepsCoarseGridsAndStaysWithinTheTarget) {
  EXPECT_EQ(mergeFactor(0.3, 1.0, 480), 3);
  EXPECT_EQ(mergeFactor(0.26, 1.0, 480), 3);
  EXPECT_EQ(mergeFactor(0.6, 1.0, 480), 1);
  EXPECT_EQ(mergeFactor(1.5, 1.0, 480), 1);
  EXPECT_EQ(mergeFactor(0.3, 0.0, 480), 1);  // 0: never merge
  EXPECT_EQ(mergeFactor(0.0, 1.0, 480), 1);  // no spacing known
  EXPECT_EQ(mergeFactor(1e-9, 1.0, 4800), 64);
  // A small grid keeps 16 cells across, however large the voxel.
  EXPECT_EQ(mergeFactor(0.01, 1.0, 24), 1);
  EXPECT_EQ(mergeFactor(0.01, 1.0, 100), 6);
}

TEST(GridMerging, LateralSpacingIgnoresRangeNoise) {
  // Fronto-parallel plane at 1.5 m, 200 px focal length: a pixel spans 7.5 mm across the ray.
  RangeGrid g = planeImage(40, 30);
  for (auto& p : g.points) p *= -1.5 / p.z();
  EXPECT_NEAR(lateralSpacing(g), 0.0075, 1e-4);
  // Range noise of a pixel's size along each ray, in a checkerboard: neighbours are 15 mm apart
  // along their rays, so gridSpacing doubles; the lateral step does not change.
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) g.points[g.at(r, c)] *= (r + c) % 2 ? 1.005 : 0.995;
  EXPECT_GT(gridSpacing(g), 0.015);
  EXPECT_NEAR(lateralSpacing(g), 0.0075, 1e-4);
}

TEST(GridMerging, BothSpacingsFromOnePassAreEachOnesOwn) {
  // A small grid takes every pair; a 640 x 480 one a sample on diagonals. Noise, holes and a
  // far patch make the two measures' medians differ.
  for (const auto& [cols, rows] : {std::pair{40, 30}, std::pair{640, 480}}) {
    RangeGrid g = planeImage(cols, rows);
    uint64_t state = 7;
    for (size_t i = 0; i < g.points.size(); ++i) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      g.points[i] *= 1 + 1e-3 * static_cast<double>(state >> 40) / double(1 << 24);
      if (i % 3 == 0) g.points[i] *= 1.5;
    }
    for (size_t c = 0; c < g.cell.size(); c += 11) g.cell[c] = -1;
    const auto [lateral, step] = lateralAndGridSpacing(g);
    EXPECT_EQ(lateral, lateralSpacing(g)) << cols;
    EXPECT_EQ(step, gridSpacing(g)) << cols;
    EXPECT_NE(lateral, step);
  }
}

TEST(GridMerging, MergedPointsStayOnAPlaneAndTheGridShrinks) {
  const RangeGrid g = planeImage(50, 31);
  const RangeGrid m = mergeCells(g, 4, gridSpacing(g), 4.0);
  EXPECT_EQ(m.cols, 13);
  EXPECT_EQ(m.rows, 8);
  ASSERT_EQ(m.points.size(), 13u * 8u);
  for (const auto& p : m.points) EXPECT_NEAR(planeOffset(p), 0, 1e-12);
  EXPECT_EQ(mergeCells(g, 1, gridSpacing(g), 4.0).points, g.points);
}

TEST(GridMerging, PinholeFollowsTheMergedPixels) {
  // A plane facing the sensor: a 3 x 3 block's mean is its centre pixel's point, which the new
  // intrinsics must project onto the merged pixel.
  RangeGrid g = planeImage(30, 21);
  for (auto& p : g.points) p *= -1.5 / p.z();
  const RangeGrid m = mergeCells(g, 3, gridSpacing(g), 4.0);
  ASSERT_TRUE(m.pinhole);
  for (int R = 0; R < m.rows; ++R)
    for (int C = 0; C < m.cols; ++C) {
      const Eigen::Vector3d& p = m.points[m.at(R, C)];
      EXPECT_NEAR(m.pinhole->fx * p.x() / -p.z() + m.pinhole->cx, C, 1e-9);
      EXPECT_NEAR(m.pinhole->fy * p.y() / -p.z() + m.pinhole->cy, R, 1e-9);
    }
}

TEST(GridMerging, ABlockAcrossADepthEdgeKeepsItsCentresSide) {
  RangeGrid g = planeImage(9, 9);
  const double spacing = gridSpacing(g);
  // Columns 5.. step back by a metre: the block of columns 3-5 mixes both surfaces.
  for (int r = 0; r < 9; ++r)
    for (int c = 5; c < 9; ++c) g.points[g.at(r, c)] *= 1.5;
  // And a hole: a block with no valid cell stays empty.
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) g.cell[r * 9 + c] = -1;
  const RangeGrid m = mergeCells(g, 3, spacing, 4.0);
  EXPECT_EQ(m.at(0, 0), -1);
  for (int R = 0; R < 3; ++R) {
    EXPECT_NEAR(planeOffset(m.points[m.at(R, 1)]), 0, 1e-12) << "block row " << R;
    EXPECT_GT(std::abs(planeOffset(m.points[m.at(R, 2)])), 0.5);
  }
}

TEST(GridMerging, BlockMeansMatchABruteForceSearchForEachBlocksCentre) {
  // Each merged point, against its definition done the long way: the valid cell nearest the
  // block's centre (first in row order on ties), then the mean of the block's cells within the
  // edge test of it. Holes (a third of the cells, the central ones too), blocks cut by the
  // grid's last rows and columns, odd and even k, and depths that step so the test drops cells.
  std::srand(11);
  for (const int k : {2, 3, 4, 5}) {
    RangeGrid g = planeImage(23, 17);
    for (size_t i = 0; i < g.cell.size(); ++i) {
      if (std::rand() % 3 == 0) g.cell[i] = -1;
      if (std::rand() % 7 == 0 && g.cell[i] >= 0) g.points[g.cell[i]] *= 1.3;
    }
    const double spacing = gridSpacing(g), step = 4.0 * spacing;
    const RangeGrid m = mergeCells(g, k, spacing, 4.0);
    int blocks = 0;
    for (int R = 0; R < m.rows; ++R)
      for (int C = 0; C < m.cols; ++C) {
        const double mid = 0.5 * (k - 1);
        int rc = -1, cc = -1;
        double best = 1e300;
        for (int r = R * k; r < std::min(R * k + k, g.rows); ++r)
          for (int c = C * k; c < std::min(C * k + k, g.cols); ++c) {
            const double d =
                (r - R * k - mid) * (r - R * k - mid) + (c - C * k - mid) * (c - C * k - mid);
            if (g.at(r, c) >= 0 && d < best) best = d, rc = r, cc = c;
          }
        if (rc < 0) {
          EXPECT_EQ(m.at(R, C), -1);
          continue;
        }
        const Eigen::Vector3d& ref = g.points[g.at(rc, cc)];
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        int n = 0;
        for (int r = R * k; r < std::min(R * k + k, g.rows); ++r)
          for (int c = C * k; c < std::min(C * k + k, g.cols); ++c) {
            if (g.at(r, c) < 0) continue;
            const int apart = std::max({std::abs(r - rc), std::abs(c - cc), 1});
            if ((g.points[g.at(r, c)] - ref).norm() > step * apart) continue;
            sum += g.points[g.at(r, c)];
            ++n;
          }
        ASSERT_GE(m.at(R, C), 0) << "k " << k << " block " << R << ", " << C;
        EXPECT_EQ(m.points[m.at(R, C)], sum / n) << "k " << k << " block " << R << ", " << C;
        ++blocks;
      }
    EXPECT_GT(blocks, m.rows * m.cols / 2) << "k " << k;
  }
}

TEST(GridMerging, AMergedNoisyGrazingFloorKeepsTheTrianglesOfTheFineGrid) {
  // A wall facing the sensor over 70 % of the rows, then a floor receding from it (steps along
  // the rows six times the wall's), with range noise above a cell's step. The noise lengthens
  // the fine grid's median step, averaging removes it, and the merged grid's own median alone
  // would drop the floor's long triangles, which the fine grid keeps.
  RangeGrid g;
  g.cols = 90, g.rows = 120;
  g.cell.assign(static_cast<size_t>(g.cols) * g.rows, -1);
  uint32_t state = 1;
  const auto noise = [&] {  // uniform in [-1, 1], the same on every platform
    state = state * 1664525u + 1013904223u;
    return 2.0 * (state >> 8) / double(1u << 24) - 1;
  };
  const int floorFrom = 84;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const int f = std::max(0, r - floorFrom);
      g.cell[static_cast<size_t>(r) * g.cols + c] = static_cast<int32_t>(g.points.size());
      g.points.emplace_back(0.01 * c, 0.01 * (r - f) + 0.02 * f, -5 - 0.057 * f + 0.03 * noise());
    }
  const auto floorShare = [&](const ScanSurface& s, double cells) {
    size_t n = 0;
    for (const Triangle& t : s.triangles) n += s.points[t[0]].z() < -5.2;
    return n / (2 * cells);
  };
  SurfaceOptions o;
  const double fine = floorShare(buildScanSurface(g, Pose{}, o), 89.0 * (g.rows - floorFrom - 5));
  o.mergeTarget = 3.5 * lateralSpacing(g);
  ASSERT_EQ(mergeFactor(lateralSpacing(g), o.mergeTarget, g.cols), 3);
  const double merged = floorShare(buildScanSurface(g, Pose{}, o), 29.0 * (g.rows - floorFrom) / 3);
  std::printf("floor triangles kept: fine %.3f, merged %.3f\n", fine, merged);
  EXPECT_GT(fine, 0.5);
  EXPECT_GT(merged, 0.8 * fine);
}

}  // namespace
}  // namespace rangefuse
