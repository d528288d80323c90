// The median of a measure over neighbouring grid cells: the grid spacing (triangulation) and
// the lateral spacing (cell merging) are both read this way.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "OrderStatistics.h"
#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::internal {

/// Grids with more neighbour pairs than this are sampled on diagonals a few cells apart.
constexpr size_t kMedianSample = size_t(1) << 16;

/// The first column of row r on the diagonals `every` cells apart that large grids are sampled
/// on (also RangeNoise::measure): every row and every column keeps its share of the sample.
inline int firstOnDiagonal(int r, int every) {
  return (every - r % every) % every;
}

/// Calls visit(a, b) for the points of each pair of valid cells next to each other that
/// medianNeighbourStep measures, in its order.
template <class Visit>
void forEachSampledPair(const RangeGrid& g, int downEvery, Visit&& visit) {
  const size_t pairs = 2 * g.cell.size();
  const int stride = static_cast<int>(std::max<size_t>(1, pairs / kMedianSample));
  for (const auto& [dr, dc] : {std::pair{0, 1}, std::pair{1, 0}})
    for (int r = 0; r + dr < g.rows; ++r)
      for (int c = firstOnDiagonal(r, stride); c + dc < g.cols; c += stride) {
        if (dr == 1 && c % downEvery != 0) continue;
        const int32_t a = g.at(r, c), b = g.at(r + dr, c + dc);
        if (a >= 0 && b >= 0) visit(g.points[a], g.points[b]);
      }
}

/// How many pairs forEachSampledPair visits at most.
inline size_t sampledPairsAtMost(const RangeGrid& g) {
  const size_t pairs = 2 * g.cell.size();
  return pairs / std::max<size_t>(1, pairs / kMedianSample) + 2 * static_cast<size_t>(g.cols);
}

/// The median of step(point a, point b) over pairs of valid cells next to each other along a
/// row or a column, or 0 if there is none. Large grids (a depth frame, a scanner station) are
/// sampled from the cells on diagonals a few cells apart, about kMedianSample pairs in all: the
/// median of so many steps moves far less than the decisions it feeds (a merge factor, an edge
/// limit four times as long). Diagonals give every row its share: a floor's depth, and so its
/// step, changes with the row. Grids up to that size use every pair.
/// Pairs down a column are taken in every `downEvery`-th column only: a sample of column pairs
/// side by side (ColumnBands) counts its first columns, so both directions weigh as in the grid.
template <class Step>
double medianNeighbourStep(const RangeGrid& g, Step&& step, int downEvery = 1) {
  std::vector<double> steps;
  steps.reserve(sampledPairsAtMost(g));
  forEachSampledPair(g, downEvery,
                     [&](const auto& a, const auto& b) { steps.push_back(step(a, b)); });
  return steps.empty() ? 0 : nthSmallest(steps, steps.size() / 2);
}

/// medianNeighbourStep of two measures, from one pass over the pairs.
template <class StepA, class StepB>
std::array<double, 2> medianNeighbourSteps(const RangeGrid& g, StepA&& stepA, StepB&& stepB) {
  std::vector<double> a, b;
  a.reserve(sampledPairsAtMost(g));
  b.reserve(sampledPairsAtMost(g));
  forEachSampledPair(g, 1, [&](const auto& p, const auto& q) {
    a.push_back(stepA(p, q));
    b.push_back(stepB(p, q));
  });
  if (a.empty()) return {0, 0};
  return {nthSmallest(a, a.size() / 2), nthSmallest(b, b.size() / 2)};
}

/// The squared distance between neighbours: gridSpacing's measure.
inline double squaredStep(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).squaredNorm();
}

/// The squared step from a to b across a's line of sight: lateralSpacing's measure.
inline double squaredLateralStep(const RangeGrid& g, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a, u = g.towardSensor(a);
  return (d - d.dot(u) * u).squaredNorm();
}

}  // namespace rangefuse::internal
