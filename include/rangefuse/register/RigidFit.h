// Closed-form weighted least-squares rigid fit from summed moments.
#pragma once

#include <Eigen/Core>

#include "rangefuse/core/Pose.h"

namespace rangefuse {

/// The sums a rigid fit of points p onto q needs: sum w, sum w p, sum w q, sum w p q^T, plus
/// sum w |q - p|^2 and the count, for the residual. Adding sums is how ranks combine them.
struct RigidSums {
  double w = 0;
  Eigen::Vector3d wp = Eigen::Vector3d::Zero();
  Eigen::Vector3d wq = Eigen::Vector3d::Zero();
  Eigen::Matrix3d wpq = Eigen::Matrix3d::Zero();
  double wr2 = 0;
  double count = 0;

  void add(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double weight);
  RigidSums& operator+=(const RigidSums& o);
  /// Weighted RMS of |q - p| before the fit.
  double rms() const { return w > 0 ? std::sqrt(wr2 / w) : 0; }
};

/// The rigid motion (R, t) minimising sum w |R p + t - q|^2 (SVD of the cross-covariance, with
/// the reflection case removed). Identity when the sums hold fewer than 3 points.
Pose fitRigid(const RigidSums& sums);

}  // namespace rangefuse
