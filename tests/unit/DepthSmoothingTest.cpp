#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "FloorGrid.h"
#include "rangefuse/surface/DepthSmoothing.h"

namespace rangefuse {
namespace {

/// floorGrid's floor 1.5 below a 240 x 180 camera (f = 300) and, when `box` is set, a box top
/// 0.3 above it over the middle third of the columns: a depth step. Depths move along their
/// rays by `sigma(depth)` deviations.
RangeGrid cameraOverFloor(double (*sigma)(double), bool box, int seed = 5) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0, 1);
  return test::floorGrid(
      240, 180, 300, [&](int c) { return box && c >= 80 && c < 160 ? 1.2 : 1.5; },
      [&](double t) { return t + sigma(t) * normal(rng); });
}

/// Distance of a scan-frame point from the floor (or the box top) it was made on.
double offSurface(const Eigen::Vector3d& p, bool onBox) {
  return test::aboveFloor(p, onBox ? 1.2 : 1.5);
}

double noiseGrowingWithDepth(double z) {
  return 0.004 * z * z;
}
double noNoise(double) {
  return 0;
}

/// The noise the camera's depths carry, as RangeNoise would measure it.
RangeNoise growingCurve() {
  std::vector<double> depths, sigmas;
  for (double z = 1; z <= 8; z += 0.5)
    depths.push_back(z), sigmas.push_back(noiseGrowingWithDepth(z));
  return RangeNoise::fromPoints(depths, sigmas);
}

DepthSmoothing smoothingTo(double target) {
  DepthSmoothing how;
  how.target = target;
  how.edge = 4 * 6.0 / 300;  // four cells' width at the farthest depth
  return how;
}

TEST(DepthSmoothing, HalfWidthBringsTheNoiseToTheTarget) {
  EXPECT_EQ(smoothingHalfWidth(0.5, 1, 8), 0);
  EXPECT_EQ(smoothingHalfWidth(1, 1, 8), 0);
  EXPECT_EQ(smoothingHalfWidth(3, 1, 8), 1);    // 3 x 3 cells: a third of the noise
  EXPECT_EQ(smoothingHalfWidth(3.5, 1, 8), 2);  // 5 x 5
  EXPECT_EQ(smoothingHalfWidth(100, 1, 8), 8);
  EXPECT_EQ(smoothingHalfWidth(3, 0, 8), 0);
}

TEST(DepthSmoothing, LeavesAGridWithinItsTargetBitForBit) {
  const RangeGrid g = cameraOverFloor(noiseGrowingWithDepth, false);
  EXPECT_EQ(smoothDepths(g, growingCurve(), smoothingTo(1.0)).points, g.points);
  EXPECT_EQ(smoothDepths(g, RangeNoise{}, smoothingTo(0.001)).points, g.points);
  EXPECT_EQ(smoothDepths(g, growingCurve(), smoothingTo(0)).points, g.points);
}

TEST(DepthSmoothing, KeepsAPlaneAndBothSidesOfAStepExact) {
  // Inverse depth is linear across a plane, so a line fit leaves exact depths where they are,
  // and the window stops at the box's edge rather than pulling its top toward the floor.
  const RangeGrid g = cameraOverFloor(noNoise, true);
  const RangeGrid s = smoothDepths(g, growingCurve(), smoothingTo(0.004));
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c)
      if (const int32_t i = g.at(r, c); i >= 0) {
        const bool onBox = c >= 80 && c < 160;
        ASSERT_NEAR(offSurface(s.points[i], onBox), 0, 1e-9) << r << " " << c;
        ASSERT_NEAR(s.points[i].normalized().dot(g.points[i].normalized()), 1, 1e-12);
      }
}

TEST(DepthSmoothing, BringsGrowingNoiseDownToAboutTheTarget) {
  const double target = 0.01;
  const RangeGrid g = cameraOverFloor(noiseGrowingWithDepth, true);
  const RangeGrid s = smoothDepths(g, growingCurve(), smoothingTo(target));
  // Per depth band: the deviation from the true surface along the ray, before and after.
  for (const auto& [near, far] : {std::pair{2.0, 3.0}, {3.0, 4.5}, {4.5, 6.5}}) {
    double before = 0, after = 0;
    int n = 0;
    for (int r = 2; r < g.rows - 2; ++r)
      for (int c = 2; c < g.cols - 2; ++c) {
        const int32_t i = g.at(r, c);
        if (i < 0 || std::abs(c - 80) < 10 || std::abs(c - 160) < 10) continue;
        const double z = -g.points[i].z();
        if (z < near || z >= far) continue;
        const bool onBox = c >= 80 && c < 160;
        before += std::pow(offSurface(g.points[i], onBox), 2);
        after += std::pow(offSurface(s.points[i], onBox), 2);
        ++n;
      }
    ASSERT_GT(n, 100);
    before = std::sqrt(before / n), after = std::sqrt(after / n);
    std::printf("depths %.1f-%.1f: off the surface %.4f before, %.4f after\n", near, far, before,
                after);
    EXPECT_LT(after, 0.6 * before);
    EXPECT_LT(after, 2 * target);
  }
}

TEST(DepthSmoothing, FitsDepthOnGridsWithoutALens) {
  // A near-orthographic grid of a tilted plane z = 0.3 x - 0.1 y - 2, noise 0.05: depth is
  // linear there, and exact depths stay.
  RangeGrid g;
  g.cols = g.rows = 60;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      const double x = 0.01 * c, y = 0.01 * r;
      g.points.emplace_back(x, y, 0.3 * x - 0.1 * y - 2);
    }
  const RangeNoise noise = RangeNoise::fromPoints({1, 3}, {0.05, 0.05});
  DepthSmoothing how;
  how.target = 0.01, how.edge = 0.04;
  const RangeGrid s = smoothDepths(g, noise, how);
  for (size_t i = 0; i < g.points.size(); ++i) {
    ASSERT_NEAR((s.points[i] - g.points[i]).norm(), 0, 1e-12);
  }
}

}  // namespace
}  // namespace rangefuse
