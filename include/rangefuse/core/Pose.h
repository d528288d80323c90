// Rigid scan-to-world transform: composition, inverse, relative motion, and the one check of
// "is this a rotation" every reader of poses applies.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

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
  /// This pose after `first`: (a * b).apply(p) is a.apply(b.apply(p)).
  Pose operator*(const Pose& first) const { return Pose{R * first.R, R * first.t + t}; }
};

/// The motion from `a` to `b` in a's frame: a * relative(a, b) is b.
inline Pose relative(const Pose& a, const Pose& b) {
  return Pose{a.R.transpose() * b.R, a.R.transpose() * (b.t - a.t)};
}

/// How far R^T R may be from the identity (Frobenius norm) for R to be read as a rotation:
/// matrices printed to 8 digits, as the 7-Scenes poses are, are off by up to 3.8e-4; a
/// transform that scales an axis by 1 % is off by 2e-2.
inline constexpr double kRotationTolerance = 1e-3;

/// Empty when R is a rotation to within kRotationTolerance; else what it is instead, in words
/// ("not finite", "a reflection (determinant -1)", "not rigid: R^T R is off the identity by
/// 3 (it scales lengths by up to 2)").
std::string rotationProblem(const Eigen::Matrix3d& R);

/// The rotation nearest `m` (least squares, never a reflection).
Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& m);

/// A pose as read from a file or a caller: throws InputError("<where>: the pose is <problem>")
/// when its translation is not finite or its matrix is not a rotation; a rotation given to a
/// few digits (off by more than 1e-9) is returned as the nearest exact rotation, so that poses
/// compose and compare as rotations; an exact one is returned as it is.
Pose rigidPose(const Pose& pose, const std::string& where);

}  // namespace rangefuse
