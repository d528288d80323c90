// Rigid scan-to-world transform.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rangefuse {

/// p_world = R * p_scan + t.
struct Pose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return R * p + t; }
  Eigen::Vector3d rotate(const Eigen::Vector3d& v) const { return R * v; }
  /// The world-to-scan transform.
  Pose inverse() const {
    Pose inv;
    inv.R = R.transpose();
    inv.t = -(inv.R * t);
    return inv;
  }
};

}  // namespace rangefuse
