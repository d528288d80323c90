// A pinhole camera above a floor, looking down it at 30 degrees: depths from about 2 to 6, a
// grid whose noise and smoothing have known answers (RangeNoise and DepthSmoothing tests).
#pragma once

#include <cmath>
#include <random>

#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::test {

/// A cols x rows pinhole grid (focal length f, centred; rows go with y, as the lens has it)
/// whose camera, tilted down by 30 degrees, sees a horizontal plane `heightAt(column)` below
/// it. Each ray's depth (-z) at that plane, t, is written as `depthOf(t)`.
template <class Height, class Depth>
RangeGrid floorGrid(int cols, int rows, double f, Height&& heightAt, Depth&& depthOf) {
  RangeGrid g;
  g.cols = cols, g.rows = rows;
  const double cx = (cols - 1) / 2.0, cy = (rows - 1) / 2.0;
  g.pinhole = Pinhole{f, f, cx, cy};
  g.cell.assign(size_t(cols) * rows, -1);
  const double tilt = 30 * M_PI / 180;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector3d ray((c - cx) / f, (r - cy) / f, -1);
      const double up = ray.y() * std::cos(tilt) + ray.z() * std::sin(tilt);
      if (!(up < -0.05)) continue;
      g.cell[size_t(r) * cols + c] = static_cast<int32_t>(g.points.size());
      g.points.push_back(depthOf(-heightAt(c) / up) * ray);
    }
  return g;
}

/// floorGrid's floor 1.5 below the camera, each range moved along its ray by `noise(depth)`
/// deviations of a normal variable (drawn with `seed`) and, when `step` > 0, rounded to a
/// multiple of step * depth^2 (a structured-light camera's steps).
inline RangeGrid noisyFloor(int cols, int rows, double f, double (*noise)(double), double step,
                            int seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0, 1);
  return floorGrid(
      cols, rows, f, [](int) { return 1.5; },
      [&](double t) {
        t += noise(t) * normal(rng);
        return step > 0 ? std::round(t / (step * t * t)) * step * t * t : t;
      });
}

/// Height above the plane floorGrid's camera saw of a point in the camera frame, less `height`.
inline double aboveFloor(const Eigen::Vector3d& p, double height) {
  const double tilt = 30 * M_PI / 180;
  return p.y() * std::cos(tilt) + p.z() * std::sin(tilt) + height;
}

}  // namespace rangefuse::test
