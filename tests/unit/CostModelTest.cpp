// The planner's cost model against the voxel updates the integrator counts: on a scene whose
// triangles differ 64-fold in size from one part to the other, the work it predicts splits
// the bricks into runs of equal updates, where counting prisms did not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/surface/ScanSurface.h"

using namespace rangefuse;

namespace {

constexpr double kVoxel = 0.25, kEps = 0.75;

/// A wavy patch of cols x rows cells `step` apart, its corner at x0, as a scan would give.
PrismScan patch(int cols, int rows, double step, double x0) {
  RangeGrid g;
  g.cols = cols;
  g.rows = rows;
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      const double px = x0 + x * step, py = y * step;
      g.points.emplace_back(px, py, std::sin(px * 0.4) + 0.3 * std::cos(py * 0.7) + 20);
    }
  PrismScan s;
  s.surface = buildScanSurface(g, Pose{}, SurfaceOptions{});
  s.limits = computePrismLimits(s.surface, kEps);
  return s;
}

/// Near (small triangles) and far (large ones) parts of one view, as a depth camera sees a
/// desk before a wall: the same area, 64 times fewer triangles in the far part.
std::vector<PrismScan> mixedScene() {
  return {patch(121, 61, 0.1, 0), patch(16, 8, 0.8, 14)};
}

/// Per brick (the layout's order), the voxel updates the integrator counts on one rank.
std::vector<uint64_t> countedUpdates(const std::vector<PrismScan>& scans,
                                     const BrickLayout& layout) {
  BrickStore store(layout, 0);
  PrismIntegrator integrator(store, 2);
  integrator.countUpdatesPerBrick();
  for (const PrismScan& s : scans) integrator.addScan(s);
  return integrator.updatesPerBrick();
}

/// max/mean of the counted updates over the runs of `cut` (rank starts over the same bricks).
double imbalance(const std::vector<uint64_t>& counted, const std::vector<size_t>& cut) {
  std::vector<double> runs;
  for (size_t r = 0; r + 1 < cut.size(); ++r)
    runs.push_back(std::accumulate(counted.begin() + cut[r], counted.begin() + cut[r + 1], 0.0));
  const double mean = std::accumulate(runs.begin(), runs.end(), 0.0) / runs.size();
  return *std::max_element(runs.begin(), runs.end()) / mean;
}

}  // namespace

TEST(CostModel, PredictsTheUpdatesEachPrismMakes) {
  for (const PrismScan& part : mixedScene()) {  // small triangles, then large ones
    const std::vector<PrismScan> scans{part};
    const BrickLayout layout = planBricks(scans, fitGrid(scans, kVoxel, 4, kEps), 1);
    const std::vector<uint64_t> counted = countedUpdates(scans, layout);
    double predicted = 0;
    for (const PrismScan& s : scans)
      for (size_t t = 0; t < s.surface.triangles.size(); ++t) {
        const Prism p = scanPrism(s, t);
        predicted += expectedUpdates(p, kVoxel);
      }
    const double total = std::accumulate(counted.begin(), counted.end(), 0.0);
    EXPECT_NEAR(predicted / total, 1.0, 0.05) << predicted << " predicted, " << total << " counted";
  }
}

TEST(CostModel, PredictedWorkFollowsTheCountedUpdatesAlongTheMortonOrder) {
  // The voxel updates alone (no set-up cost): what the integrator counts.
  const std::vector<PrismScan> scans = mixedScene();
  const BrickLayout layout = planBricks(scans, fitGrid(scans, kVoxel, 4, kEps), 1, UINT64_MAX, 0.0);
  const std::vector<uint64_t> counted = countedUpdates(scans, layout);
  ASSERT_EQ(counted.size(), layout.work.size());
  // Pearson correlation of predicted work and counted updates over groups of 8 bricks in
  // Morton order (a rank owns a run of them: single bricks may trade samples at their faces).
  std::vector<double> x, y;
  for (size_t b = 0; b < counted.size(); ++b) {
    if (b % 8 == 0) x.push_back(0), y.push_back(0);
    x.back() += layout.work[b], y.back() += counted[b];
  }
  const size_t n = x.size();
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n;
  const double my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t g = 0; g < n; ++g) {
    const double dx = x[g] - mx, dy = y[g] - my;
    sxy += dx * dy, sxx += dx * dx, syy += dy * dy;
  }
  EXPECT_GT(sxy / std::sqrt(sxx * syy), 0.98);
}

TEST(CostModel, CutsRunsOfEqualUpdatesWhereCountingPrismsDidNot) {
  const std::vector<PrismScan> scans = mixedScene();
  const VoxelGrid grid = fitGrid(scans, kVoxel, 4, kEps);
  const BrickLayout layout = planBricks(scans, grid, 1, UINT64_MAX, 0.0);
  const std::vector<uint64_t> counted = countedUpdates(scans, layout);
  // The count of prism boxes touching each brick: the planner's work before the cost model.
  BrickWork boxes;
  for (const PrismScan& s : scans)
    for (size_t t = 0; t < s.surface.triangles.size(); ++t) {
      BrickCoord lo, hi;
      if (bricksOfBox(grid, prismBounds(scanPrism(s, t)), lo, hi))
        addBrickWork(grid, lo, hi, 1, UINT64_MAX, boxes);
    }
  const BrickLayout byCount = layoutFromWork(boxes, grid, 1);
  ASSERT_EQ(byCount.codes, layout.codes);
  for (int ranks : {2, 3, 4}) {
    EXPECT_LE(imbalance(counted, partitionWork(layout.work, ranks)), 1.05) << ranks << " ranks";
    EXPECT_GT(imbalance(counted, partitionWork(byCount.work, ranks)), 1.3) << ranks << " ranks";
  }
}
