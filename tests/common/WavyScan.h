// A wavy patch of 40 x 30 points half a unit apart, as a scan would give: the routing tests'
// scan, unit and MPI alike.
#pragma once

#include <cmath>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse::test {

/// The patch's surface and prism limits (eps 1.5), at z = 20 + sin(0.3 x).
inline PrismScan wavyScan() {
  RangeGrid g;
  g.cols = 40;
  g.rows = 30;
  for (int y = 0; y < g.rows; ++y)
    for (int x = 0; x < g.cols; ++x) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      g.points.emplace_back(x * 0.5, y * 0.5, std::sin(x * 0.3) + 20);
    }
  PrismScan s;
  s.surface = buildScanSurface(g, Pose{}, SurfaceOptions{});
  s.limits = computePrismLimits(s.surface, 1.5);
  return s;
}

}  // namespace rangefuse::test
