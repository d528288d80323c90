// Large grids are measured on a sample of their cells (medians of neighbour steps, the noise
// curve). A floor seen at an angle is the hard case: its depth, and so its steps and noise,
// change with the row, so a sample that takes whole rows leaves each depth to a few of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "FloorGrid.h"
#include "rangefuse/surface/RangeNoise.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {
namespace {

double depthSquared(double z) {
  return 0.002 * z * z;
}

/// A 640 x 480 floor (a depth camera's frame: more cells than either measure takes), each range
/// moved along its ray by depthSquared deviations and rounded to steps of `step` z^2.
RangeGrid largeFloor(double step) {
  return test::noisyFloor(640, 480, 800, depthSquared, step, 5);
}

/// The median of |a - b| over every pair of valid neighbours along rows and columns.
double bruteForceGridSpacing(const RangeGrid& g) {
  std::vector<double> steps;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const int32_t a = g.at(r, c);
      if (a < 0) continue;
      if (c + 1 < g.cols && g.at(r, c + 1) >= 0)
        steps.push_back((g.points[a] - g.points[g.at(r, c + 1)]).norm());
      if (r + 1 < g.rows && g.at(r + 1, c) >= 0)
        steps.push_back((g.points[a] - g.points[g.at(r + 1, c)]).norm());
    }
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return steps[steps.size() / 2];
}

TEST(GridSampling, ASampledMedianStepMatchesEveryPairsOnAFloor) {
  for (double step : {0.0, 0.001}) {
    const RangeGrid g = largeFloor(step);
    const double all = bruteForceGridSpacing(g);
    EXPECT_NEAR(gridSpacing(g), all, 0.01 * all) << "step " << step;
  }
}

TEST(GridSampling, ASampledNoiseCurveFollowsTheFloorsNoiseAtEveryDepth) {
  // Rounding to a quarter of the noise adds about 1 % to it.
  const RangeNoise n = RangeNoise::measure(largeFloor(0.0005));
  ASSERT_GE(n.depths().size(), 12u);
  for (size_t k = 0; k < n.depths().size(); ++k)
    EXPECT_NEAR(n.sigmas()[k], depthSquared(n.depths()[k]), 0.1 * depthSquared(n.depths()[k]))
        << "bin at depth " << n.depths()[k];
}

}  // namespace
}  // namespace rangefuse
