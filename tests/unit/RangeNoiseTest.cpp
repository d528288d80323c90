#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rangefuse/robust/RangeNoise.h"
#include "rangefuse/robust/SightMap.h"

namespace rangefuse {
namespace {

/// A pinhole camera 1.5 above a floor, looking down it at 30 degrees: depths from about 2 to
/// 6. Each range is moved along its ray by `noise(depth)` deviations of a normal variable and,
/// when `step` > 0, rounded to a multiple of step * depth^2 (a structured-light camera's steps).
RangeGrid floorGrid(double (*noise)(double), double step, int seed = 3) {
  RangeGrid g;
  g.cols = 320, g.rows = 240;
  g.pinhole = Pinhole{400, 400, 159.5, 119.5};
  g.cell.assign(g.cols * g.rows, -1);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0, 1);
  const double tilt = 30 * M_PI / 180;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      // The ray in the camera frame (rows go with y, as the lens has it); the floor is where
      // the height along the camera tilted up by 30 degrees reaches -1.5.
      const Eigen::Vector3d ray((c - 159.5) / 400, (r - 119.5) / 400, -1);
      const double up = ray.y() * std::cos(tilt) + ray.z() * std::sin(tilt);
      if (!(up < -0.05)) continue;
      double t = -1.5 / up;  // the ray's parameter at the floor; depth (-z) is t
      t += noise(t) * normal(rng);
      if (step > 0) t = std::round(t / (step * t * t)) * step * t * t;
      g.cell[r * g.cols + c] = static_cast<int32_t>(g.points.size());
      g.points.push_back(t * ray);
    }
  return g;
}

double depthSquared(double z) {
  return 0.002 * z * z;
}
double none(double) {
  return 0;
}

TEST(RangeNoise, MeasuresNoiseGrowingWithTheSquareOfDepth) {
  const RangeNoise n = RangeNoise::measure(floorGrid(depthSquared, 0));
  ASSERT_GE(n.depths().size(), 8u);
  for (double z : {2.5, 3.0, 4.0, 5.0})
    EXPECT_NEAR(n.at(z), depthSquared(z), 0.2 * depthSquared(z));
}

TEST(RangeNoise, ASmoothSurfaceHasNoneAndQuantisedDepthsCount) {
  const RangeNoise clean = RangeNoise::measure(floorGrid(none, 0));
  for (double z : {2.5, 4.0}) EXPECT_LT(clean.at(z), 0.02 * depthSquared(z));
  // Steps of 0.01 z^2 without noise: the median second difference is zero, the steps are not.
  const RangeNoise stepped = RangeNoise::measure(floorGrid(none, 0.01));
  for (double z : {2.5, 4.0}) {
    EXPECT_GT(stepped.at(z), 0.05 * 0.01 * z * z) << z;
    EXPECT_LT(stepped.at(z), 0.01 * z * z) << z;
  }
}

TEST(RangeNoise, InterpolatesBetweenMeasuredDepthsAndHoldsBeyond) {
  const RangeNoise n = RangeNoise::fromPoints({1, 3}, {0.1, 0.3});
  EXPECT_DOUBLE_EQ(n.at(0.5), 0.1);
  EXPECT_DOUBLE_EQ(n.at(2), 0.2);
  EXPECT_DOUBLE_EQ(n.at(5), 0.3);
  EXPECT_EQ(RangeNoise().at(2), 0);
}

TEST(SightMap, LooksThroughOnlyBeyondItsOwnNoise) {
  // A noisy floor's map: a point one metre in front of the floor was looked through; one a
  // few deviations in front of it, where the camera's own depths scatter, was not.
  const RangeGrid grid = floorGrid(depthSquared, 0);
  SightMap m = SightMap::fromPinholeGrid(grid, 1);
  m.setNoise(RangeNoise::measure(grid), 1);
  const double tilt = 30 * M_PI / 180;
  const Eigen::Vector3d dir = Eigen::Vector3d(0, -0.2, -1).normalized();
  // The floor along `dir`, in the camera frame.
  const double up = dir.y() * std::cos(tilt) + dir.z() * std::sin(tilt);
  const double t = -1.5 / up, z = -t * dir.z();
  const double margin = 0.02, sigma = depthSquared(z);
  EXPECT_NEAR(m.noiseAt(t * dir), sigma, 0.25 * sigma);
  EXPECT_TRUE(m.lookedThrough((t - 1) * dir, margin));
  EXPECT_FALSE(m.lookedThrough((t - (margin + 2 * sigma) / -dir.z()) * dir, margin));
  // Without a noise model, the same point counts as looked through (the fixed margin alone).
  SightMap fixed = SightMap::fromPinholeGrid(grid, 1);
  EXPECT_TRUE(fixed.lookedThrough((t - (margin + 5 * sigma) / -dir.z()) * dir, margin));
}

}  // namespace
}  // namespace rangefuse
