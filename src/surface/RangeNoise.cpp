#include "rangefuse/surface/RangeNoise.h"

#include <algorithm>
#include <cmath>

#include "OrderStatistics.h"

namespace rangefuse {
namespace {

constexpr int kBins = 16;
constexpr size_t kMinSamples = 64;  // a bin's figure needs this many second differences
constexpr double kStep = 0.05;      // neighbours this far apart (share of depth) are an edge

/// One bin's deviation from the absolute second differences `a`.
double binSigma(const std::vector<double>& a) {
  const size_t keep = a.size() * 9 / 10;
  const double median = internal::nthSmallest(a, a.size() / 2) / 0.6745;
  // A normal variable's RMS below its 90th percentile of |x| is 0.789 of its deviation.
  const double sum = internal::sumOfSmallestSquares(a, keep);
  const double trimmed = std::sqrt(sum / std::max<size_t>(1, keep)) / 0.789;
  return std::max(median, trimmed) / std::sqrt(6.0);
}

}  // namespace

RangeNoise RangeNoise::measure(const RangeGrid& grid) {
  std::vector<double> depth(grid.cell.size(), NAN);
  double lo = INFINITY, hi = 0;
  for (size_t i = 0; i < grid.cell.size(); ++i)
    if (grid.cell[i] >= 0) {
      const double z = RangeNoise::depthOf(grid, grid.points[grid.cell[i]]);
      if (!(z > 0)) continue;
      depth[i] = z, lo = std::min(lo, z), hi = std::max(hi, z);
    }
  RangeNoise out;
  out.spherical_ = grid.spherical;
  if (!(hi > lo)) return out;
  const double ratio = std::log(hi / lo) / kBins;
  std::vector<std::vector<double>> bins(kBins);
  auto smooth = [](double a, double b, double c) {
    return std::abs(a - c) <= kStep * b && std::abs(a - b) <= kStep * b;
  };
  const size_t cols = grid.cols;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const size_t i = r * cols + c;
      const double b = depth[i];
      if (std::isnan(b)) continue;
      const bool across = c > 0 && c + 1 < grid.cols && smooth(depth[i - 1], b, depth[i + 1]);
      const bool down = r > 0 && r + 1 < grid.rows && smooth(depth[i - cols], b, depth[i + cols]);
      if (!across && !down) continue;
      // One logarithm a cell: both of its second differences fall in its depth's bin.
      std::vector<double>& bin =
          bins[std::min(kBins - 1, static_cast<int>(std::log(b / lo) / ratio))];
      if (across) bin.push_back(std::abs(depth[i - 1] - 2 * b + depth[i + 1]));
      if (down) bin.push_back(std::abs(depth[i - cols] - 2 * b + depth[i + cols]));
    }
  for (int k = 0; k < kBins; ++k) {
    if (bins[k].size() < kMinSamples) continue;
    out.depth_.push_back(lo * std::exp((k + 0.5) * ratio));
    out.sigma_.push_back(binSigma(bins[k]));
  }
  return out;
}

RangeNoise RangeNoise::fromPoints(std::vector<double> depths, std::vector<double> sigmas) {
  RangeNoise out;
  out.depth_ = std::move(depths), out.sigma_ = std::move(sigmas);
  return out;
}

double RangeNoise::quadratic() const {
  double num = 0, den = 0;
  for (size_t k = 0; k < depth_.size(); ++k) {
    const double z2 = depth_[k] * depth_[k];
    num += sigma_[k] * z2, den += z2 * z2;
  }
  return den > 0 ? num / den : 0;
}

double RangeNoise::at(double depth) const {
  if (depth_.empty()) return 0;
  if (!(depth > depth_.front())) return sigma_.front();
  if (depth >= depth_.back()) return sigma_.back();
  const size_t k = std::upper_bound(depth_.begin(), depth_.end(), depth) - depth_.begin();
  const double t = (depth - depth_[k - 1]) / (depth_[k] - depth_[k - 1]);
  return sigma_[k - 1] + t * (sigma_[k] - sigma_[k - 1]);
}

}  // namespace rangefuse
