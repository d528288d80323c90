// How noisy a scan's depths are, as a function of depth: measured from the scan itself, so
// that robust fusion's agreement and free-space tests widen where the sensor is noisy (a depth
// camera's far walls) and stay tight where it is not (docs/robust.md).
#pragma once

#include <vector>

#include "rangefuse/core/RangeGrid.h"

namespace rangefuse {

/// A scan's depth noise (one standard deviation, world units) against its depth: piecewise
/// linear between measured depths, constant beyond them; zero everywhere when nothing was
/// measured. Depth is -z for pinhole and near-orthographic grids, the range for stations.
class RangeNoise {
 public:
  RangeNoise() = default;

  /// Measures a grid's noise from the second differences of its depths along rows and
  /// columns (a smooth surface's are near zero; noise of deviation s gives sqrt(6) s), in
  /// bins of depth; steps between surfaces (neighbours' depths differing by more than 5 %)
  /// are left out, and each bin's figure is the larger of a median-based and a trimmed-RMS
  /// estimate, so that quantised depths, whose median step is zero, still count. A large grid
  /// is measured on cells of diagonals a few cells apart, about 2^17 second differences.
  static RangeNoise measure(const RangeGrid& grid);

  /// A point's depth as the curve counts it: the range for stations, -z for other grids.
  static double depthOf(const RangeGrid& grid, const Eigen::Vector3d& p) {
    return grid.spherical ? p.norm() : -p.z();
  }

  /// The noise at `depth`.
  double at(double depth) const;

  /// k of the curve k depth^2 nearest the measured one (least squares over the bins): a depth
  /// camera's noise, which grows with the square of the depth, from one number that a few
  /// noisy bins do not sway as they sway the curve itself. 0 when nothing was measured.
  double quadratic() const;

  /// The depth of a point of the measured grid (scan frame) as the curve counts it: -z, or the
  /// range for a station.
  double depthOfPoint(const Eigen::Vector3d& p) const { return spherical_ ? p.norm() : -p.z(); }

  bool empty() const { return depth_.empty(); }

  /// Depths and noise of the measured bins, for reports and messages.
  const std::vector<double>& depths() const { return depth_; }
  const std::vector<double>& sigmas() const { return sigma_; }

  /// Builds a curve from given points (depths ascending), as messages carry it.
  static RangeNoise fromPoints(std::vector<double> depths, std::vector<double> sigmas);

 private:
  std::vector<double> depth_, sigma_;
  bool spherical_ = false;  ///< measured on a station: depth is the range
};

}  // namespace rangefuse
