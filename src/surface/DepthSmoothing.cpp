#include "rangefuse/surface/DepthSmoothing.h"

#include <algorithm>
#include <cmath>

namespace rangefuse {
namespace {

/// What a smoothing pass reads and writes per cell: the fitted value (inverse depth or depth),
/// the depth, its noise and the window's half-width; NaN where the grid has no point.
struct CellDepths {
  std::vector<double> value, depth, sigma;
  std::vector<int> half;
};

bool fitsInverse(const RangeGrid& grid) {
  return grid.pinhole.has_value() || grid.spherical;
}

CellDepths cellDepths(const RangeGrid& grid, const RangeNoise& noise, const DepthSmoothing& how) {
  const size_t n = grid.cell.size();
  CellDepths d{std::vector<double>(n, NAN), std::vector<double>(n, NAN),
               std::vector<double>(n, NAN), std::vector<int>(n, 0)};
  const bool inverse = fitsInverse(grid);
  for (size_t i = 0; i < grid.cell.size(); ++i) {
    if (grid.cell[i] < 0) continue;
    const double z = RangeNoise::depthOf(grid, grid.points[grid.cell[i]]);
    if (inverse && !(z > 0)) continue;
    d.depth[i] = z;
    d.value[i] = inverse ? 1 / z : z;
    d.sigma[i] = noise.at(std::abs(z)) * how.scale;
    d.half[i] = smoothingHalfWidth(d.sigma[i], how.target, how.maxHalfWidth);
  }
  return d;
}

/// Sums of a least-squares line v = a + b t through points (t, v), read at t = 0.
struct LineFit {
  double s0 = 0, s1 = 0, s2 = 0, sv = 0, stv = 0;
  void add(int t, double v) { s0 += 1, s1 += t, s2 += double(t) * t, sv += v, stv += t * v; }
  double atZero() const {
    const double det = s0 * s2 - s1 * s1;
    return det > 1e-9 ? (s2 * sv - s1 * stv) / det : sv / s0;  // one side only: the mean
  }
};

/// One line of cells (a row or a column) as a pass sees it.
struct CellLine {
  size_t first;    ///< index of its cell 0
  ptrdiff_t step;  ///< index step between neighbours
  int length;
};

/// Adds to `fit` the cells from `here` outward in direction `dir` (+1 or -1), up to `h` cells,
/// while they stay on the surface of cell `here`: two cells in a row further than `jump` in
/// depth from the last one taken end it, so a depth edge does and a lone outlier does not.
void addSide(const CellDepths& in, const CellLine& line, int here, int dir, int h, double jump,
             LineFit& fit) {
  double last = in.depth[line.first + here * line.step];
  int misses = 0;
  for (int t = dir; std::abs(t) <= h && here + t >= 0 && here + t < line.length && misses < 2;
       t += dir) {
    const size_t j = line.first + (here + t) * line.step;
    if (std::isnan(in.value[j]) || std::abs(in.depth[j] - last) > jump) {
      ++misses;
      continue;
    }
    misses = 0, last = in.depth[j];
    fit.add(t, in.value[j]);
  }
}

/// One pass along rows or down columns: each cell's value from a line fitted over its window.
std::vector<double> fitAlong(const RangeGrid& grid, const CellDepths& in, double edge,
                             bool alongRows) {
  std::vector<double> out = in.value;
  const bool inverse = fitsInverse(grid);
  const int lines = alongRows ? grid.rows : grid.cols;
  for (int l = 0; l < lines; ++l) {
    const CellLine line = alongRows ? CellLine{size_t(l) * grid.cols, 1, grid.cols}
                                    : CellLine{size_t(l), grid.cols, grid.rows};
    for (int here = 0; here < line.length; ++here) {
      const size_t i = line.first + here * line.step;
      if (in.half[i] == 0 || std::isnan(in.value[i])) continue;
      // Neighbours on the same surface differ by the edge limit plus the noise of two depths.
      const double jump = edge + 3 * std::sqrt(2.0) * in.sigma[i];
      LineFit fit;
      fit.add(0, in.value[i]);
      for (const int dir : {-1, 1}) addSide(in, line, here, dir, in.half[i], jump, fit);
      const double v = fit.atZero();
      if (!inverse || v > 0) out[i] = v;
    }
  }
  return out;
}

}  // namespace

int smoothingHalfWidth(double sigma, double target, int maxHalfWidth) {
  if (!(target > 0) || !(sigma > target)) return 0;
  return std::min(maxHalfWidth, static_cast<int>(std::ceil((sigma / target - 1) / 2)));
}

RangeGrid smoothDepths(const RangeGrid& grid, const RangeNoise& noise, const DepthSmoothing& how) {
  if (noise.empty() || !(how.target > 0)) return grid;
  CellDepths d = cellDepths(grid, noise, how);
  if (std::all_of(d.half.begin(), d.half.end(), [](int h) { return h == 0; })) return grid;
  d.value = fitAlong(grid, d, how.edge, true);
  d.value = fitAlong(grid, d, how.edge, false);
  RangeGrid out = grid;
  const bool inverse = fitsInverse(grid);
  for (size_t i = 0; i < grid.cell.size(); ++i) {
    if (d.half[i] == 0 || std::isnan(d.value[i])) continue;
    Eigen::Vector3d& p = out.points[grid.cell[i]];
    if (inverse)
      p *= (1 / d.value[i]) / d.depth[i];
    else
      p.z() = -d.value[i];
  }
  return out;
}

}  // namespace rangefuse
