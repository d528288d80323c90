#include "rangefuse/surface/GridMerging.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "GridSteps.h"

namespace rangefuse {
namespace {

constexpr int kLargestFactor = 64;  // past this a grid is not a range image at this voxel
constexpr int kLeastCellsAcross = 16;

/// The valid cell of block (r0, c0) nearest its centre (first in row order on ties), or -1.
int32_t centralCell(const RangeGrid& g, int r0, int c0, int k, int& rc, int& cc) {
  // Inside the grid a block's nearest cell to its centre is (k - 1) / 2 down and across (the
  // first of four for even k): when it holds a point, nothing nearer does.
  const int half = (k - 1) / 2;
  if (r0 + k <= g.rows && c0 + k <= g.cols)
    if (const int32_t i = g.at(r0 + half, c0 + half); i >= 0) {
      rc = r0 + half, cc = c0 + half;
      return i;
    }
  const double mid = 0.5 * (k - 1);
  double best = std::numeric_limits<double>::infinity();
  int32_t found = -1;
  for (int r = r0; r < std::min(r0 + k, g.rows); ++r)
    for (int c = c0; c < std::min(c0 + k, g.cols); ++c) {
      const int32_t i = g.at(r, c);
      const double d = std::pow(r - r0 - mid, 2) + std::pow(c - c0 - mid, 2);
      if (i < 0 || !(d < best)) continue;
      best = d, found = i, rc = r, cc = c;
    }
  return found;
}

/// The mean of block (r0, c0)'s points on the surface of its central cell, and that cell's colour
/// if the grid has any; false if none. The colour is sampled, not averaged: the merged cells
/// interpolate it between their corners, and a block mean on top of that would blur a texture
/// edge over two blocks instead of one. `texels` (if set) gets the cells' colours.
bool blockMean(const RangeGrid& g, int r0, int c0, int k, double step, Eigen::Vector3d& mean,
               Colour& colour, TexelImage* texels) {
  int rc = 0, cc = 0;
  const int32_t centre = centralCell(g, r0, c0, k, rc, cc);
  if (centre < 0) return false;
  const Eigen::Vector3d& ref = g.points[centre];
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (int r = r0; r < std::min(r0 + k, g.rows); ++r)
    for (int c = c0; c < std::min(c0 + k, g.cols); ++c) {
      const int32_t i = g.at(r, c);
      if (i < 0) continue;
      const int apart = std::max({std::abs(r - rc), std::abs(c - cc), 1});
      if ((g.points[i] - ref).norm() > step * apart) continue;
      sum += g.points[i];
      ++n;
      if (texels) texels->cell(r, c) = texelOf(g.colours[i]);
    }
  mean = sum / n;
  if (!g.colours.empty()) colour = g.colours[centre];
  return true;
}

}  // namespace

double lateralSpacing(const RangeGrid& grid, int downEvery) {
  // Squares keep the order, so the median step is the root of the median square: one root.
  return std::sqrt(internal::medianNeighbourStep(
      grid,
      [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
        return internal::squaredLateralStep(grid, a, b);
      },
      downEvery));
}

std::array<double, 2> lateralAndGridSpacing(const RangeGrid& grid) {
  const auto [lateral, step] = internal::medianNeighbourSteps(
      grid,
      [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
        return internal::squaredLateralStep(grid, a, b);
      },
      internal::squaredStep);
  return {std::sqrt(lateral), std::sqrt(step)};
}

double angularSpacing(const RangeGrid& grid, int downEvery) {
  // The chord between unit directions: the angle, to within a part in 10^6 at these steps.
  return std::sqrt(internal::medianNeighbourStep(
      grid,
      [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
        return (a.normalized() - b.normalized()).squaredNorm();
      },
      downEvery));
}

int mergeFactor(double spacing, double target, int shortSide) {
  if (!(spacing > 0) || !(target > spacing)) return 1;
  // A scan much smaller than a voxel keeps a grid of its own rather than vanish into a cell.
  const int largest = std::max(1, std::min(kLargestFactor, shortSide / kLeastCellsAcross));
  return static_cast<int>(std::min<double>(largest, std::floor(target / spacing)));
}

double mergedEdgeLimit(double mergedStep, double fineStep, int k, double maxEdgeFactor) {
  return maxEdgeFactor * std::max(mergedStep, k * fineStep);
}

TexelImage cellTexels(const RangeGrid& g) {
  if (g.colours.empty()) return {};
  TexelImage out = TexelImage::blank(0, 0, g.rows, g.cols);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c)
      if (const int32_t i = g.at(r, c); i >= 0) out.cell(r, c) = texelOf(g.colours[i]);
  return out;
}

RangeGrid mergeCells(const RangeGrid& g, int k, double spacing, double maxEdgeFactor,
                     TexelImage* texels) {
  if (k <= 1) return g;
  RangeGrid out;
  out.cols = (g.cols + k - 1) / k;
  out.rows = (g.rows + k - 1) / k;
  out.cell.assign(static_cast<size_t>(out.cols) * out.rows, -1);
  out.spherical = g.spherical;
  out.colourKind = g.colourKind;
  if (g.pinhole) {
    // Merged pixel (C, R) is centred on old pixel k C + (k - 1) / 2.
    Pinhole p = *g.pinhole;
    p.fx /= k, p.fy /= k;
    p.cx = (p.cx - 0.5 * (k - 1)) / k;
    p.cy = (p.cy - 0.5 * (k - 1)) / k;
    out.pinhole = p;
  }
  const double step = maxEdgeFactor * spacing;
  Eigen::Vector3d mean;
  Colour colour;
  if (g.colours.empty()) texels = nullptr;
  if (texels) *texels = TexelImage::blank(0, 0, g.rows, g.cols);
  // A merged grid lives while its frame is read: room for every block, not growth by doubling.
  out.points.reserve(out.cell.size());
  if (!g.colours.empty()) out.colours.reserve(out.cell.size());
  for (int R = 0; R < out.rows; ++R)
    for (int C = 0; C < out.cols; ++C) {
      if (!blockMean(g, R * k, C * k, k, step, mean, colour, texels)) continue;
      out.cell[static_cast<size_t>(R) * out.cols + C] = static_cast<int32_t>(out.points.size());
      out.points.push_back(mean);
      if (!g.colours.empty()) out.colours.push_back(colour);
    }
  return out;
}

}  // namespace rangefuse
