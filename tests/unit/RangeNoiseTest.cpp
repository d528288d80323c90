#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "FloorGrid.h"
#include "rangefuse/robust/SightMap.h"
#include "rangefuse/surface/RangeNoise.h"

namespace rangefuse {
namespace {

/// test::noisyFloor at 320 x 240, f = 400.
RangeGrid floorGrid(double (*noise)(double), double step, int seed = 3) {
  return test::noisyFloor(320, 240, 400, noise, step, seed);
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
  // A noisy floor's map, asked along 200 rays about points in front of the floor: a metre in
  // front, every one was looked through; 2.5 deviations in front (where the camera's own
  // depths scatter), few were, while a map without the noise model counts most of them.
  const RangeGrid grid = floorGrid(depthSquared, 0, 5);
  SightMap aware = SightMap::fromPinholeGrid(grid, 1);
  aware.setNoise(RangeNoise::measure(grid), 1);
  const SightMap fixed = SightMap::fromPinholeGrid(grid, 1);
  const double tilt = 30 * M_PI / 180, margin = 0.02;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> across(-0.3, 0.3), down(0, 0.25);
  int far = 0, near = 0, nearFixed = 0;
  const int rays = 200;
  for (int k = 0; k < rays; ++k) {
    const Eigen::Vector3d dir = Eigen::Vector3d(across(rng), down(rng), -1).normalized();
    const double t = -1.5 / (dir.y() * std::cos(tilt) + dir.z() * std::sin(tilt));
    const double z = -t * dir.z(), sigma = depthSquared(z);
    EXPECT_NEAR(aware.noiseAt(t * dir), sigma, 0.25 * sigma);
    const Eigen::Vector3d front = (t - (margin + 2.5 * sigma) / -dir.z()) * dir;
    far += aware.lookedThrough((t - 1) * dir, margin);
    near += aware.lookedThrough(front, margin);
    nearFixed += fixed.lookedThrough(front, margin);
  }
  std::printf("looked through: a metre in front %d, 2.5 deviations %d (%d without noise) of %d\n",
              far, near, nearFixed, rays);
  EXPECT_EQ(far, rays);
  EXPECT_LE(near, rays / 10);
  EXPECT_GE(nearFixed, rays / 2);
}

}  // namespace
}  // namespace rangefuse
