// Scans made from a grid of points, as a scanner would give them: the routing and growing-field
// tests' scans, unit and MPI alike.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse::test {

/// A scan of cols x rows grid points, point (x, y) at pointAt(x, y), with its surface and its
/// prism limits for envelope eps.
template <class PointAt>
PrismScan gridScan(int cols, int rows, double eps, PointAt&& pointAt) {
  RangeGrid g;
  g.cols = cols;
  g.rows = rows;
  for (int y = 0; y < g.rows; ++y)
    for (int x = 0; x < g.cols; ++x) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      g.points.push_back(pointAt(x, y));
    }
  PrismScan s;
  s.surface = buildScanSurface(g, Pose{}, SurfaceOptions{});
  s.limits = computePrismLimits(s.surface, eps);
  return s;
}

/// A wavy patch of 40 x 30 points half a unit apart at z = 20 + sin(0.3 x), eps 1.5.
inline PrismScan wavyScan() {
  return gridScan(40, 30, 1.5, [](int x, int y) {
    return Eigen::Vector3d(x * 0.5, y * 0.5, std::sin(x * 0.3) + 20);
  });
}

}  // namespace rangefuse::test
