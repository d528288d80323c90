// The median of a measure over neighbouring grid cells: the grid spacing (triangulation) and
// the lateral spacing (cell merging) are both read this way.
#pragma once

#include <algorithm>
#include <vector>

#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::internal {

/// The median of step(point a, point b) over every pair of valid cells next to each other along
/// a row or a column, or 0 if there is none.
template <class Step>
double medianNeighbourStep(const RangeGrid& g, Step&& step) {
  std::vector<double> steps;
  steps.reserve(2 * g.cell.size());
  for (const auto& [dr, dc] : {std::pair{0, 1}, std::pair{1, 0}})
    for (int r = 0; r + dr < g.rows; ++r)
      for (int c = 0; c + dc < g.cols; ++c) {
        const int32_t a = g.at(r, c), b = g.at(r + dr, c + dc);
        if (a >= 0 && b >= 0) steps.push_back(step(g.points[a], g.points[b]));
      }
  if (steps.empty()) return 0;
  auto mid = steps.begin() + steps.size() / 2;
  std::nth_element(steps.begin(), mid, steps.end());
  return *mid;
}

}  // namespace rangefuse::internal
