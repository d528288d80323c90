#include "rangefuse/surface/RangeNoise.h"

#include <algorithm>
#include <cmath>

#include "GridSteps.h"
#include "OrderStatistics.h"

namespace rangefuse {
namespace {

constexpr int kBins = 16;
constexpr size_t kMinSamples = 64;  // a bin's figure needs this many second differences
constexpr double kStep = 0.05;      // neighbours this far apart (share of depth) are an edge
/// About this many second differences are taken, from cells spread evenly over the grid. The
/// bins then hold thousands each; every cell of a real Kinect frame made measuring a fifth of
/// the time its frames took to read (issue 60).
constexpr size_t kSample = size_t(1) << 17;

/// One bin's deviation from the absolute second differences `a`.
double binSigma(const std::vector<double>& a) {
  const size_t keep = a.size() * 9 / 10;
  const auto [half, last] = internal::nthSmallestTwo(a, a.size() / 2, keep > 0 ? keep - 1 : 0);
  const double median = half / 0.6745;
  // A normal variable's RMS below its 90th percentile of |x| is 0.789 of its deviation.
  const double sum = internal::sumOfSmallestSquares(a, keep, last);
  const double trimmed = std::sqrt(sum / std::max<size_t>(1, keep)) / 0.789;
  return std::max(median, trimmed) / std::sqrt(6.0);
}

}  // namespace

RangeNoise RangeNoise::measure(const RangeGrid& grid) {
  const int rows = grid.rows, cols = grid.cols;
  auto depthAt = [&](int r, int c) {
    const int32_t i = grid.at(r, c);
    const double z = i >= 0 ? RangeNoise::depthOf(grid, grid.points[i]) : NAN;
    return z > 0 ? z : NAN;
  };
  auto smooth = [](double a, double b, double c) {
    return std::abs(a - c) <= kStep * b && std::abs(a - b) <= kStep * b;
  };
  // Cells on diagonals `every` apart: whole rows would leave a floor's narrow band of depths
  // to one row and its quantisation.
  const int every = static_cast<int>(std::max<size_t>(1, 2 * grid.cell.size() / kSample));
  struct Cell {
    double depth, across, down;  // second differences, NaN where not taken
  };
  std::vector<Cell> taken;
  double lo = INFINITY, hi = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = internal::firstOnDiagonal(r, every); c < cols; c += every) {
      const double b = depthAt(r, c);
      if (std::isnan(b)) continue;
      lo = std::min(lo, b), hi = std::max(hi, b);
      Cell cell{b, NAN, NAN};
      if (c > 0 && c + 1 < cols)
        if (const double a = depthAt(r, c - 1), d = depthAt(r, c + 1); smooth(a, b, d))
          cell.across = std::abs(a - 2 * b + d);
      if (r > 0 && r + 1 < rows)
        if (const double a = depthAt(r - 1, c), d = depthAt(r + 1, c); smooth(a, b, d))
          cell.down = std::abs(a - 2 * b + d);
      if (!std::isnan(cell.across) || !std::isnan(cell.down)) taken.push_back(cell);
    }
  RangeNoise out;
  out.spherical_ = grid.spherical;
  if (!(hi > lo)) return out;
  const double ratio = std::log(hi / lo) / kBins;
  std::vector<std::vector<double>> bins(kBins);
  for (const Cell& cell : taken) {
    // One logarithm a cell: both of its second differences fall in its depth's bin.
    std::vector<double>& bin =
        bins[std::min(kBins - 1, static_cast<int>(std::log(cell.depth / lo) / ratio))];
    if (!std::isnan(cell.across)) bin.push_back(cell.across);
    if (!std::isnan(cell.down)) bin.push_back(cell.down);
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
