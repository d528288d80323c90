#include "rangefuse/register/LooseMotion.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

namespace rangefuse {

LooseMotion loosestMotion(const Matrix6d& block, const MotionFrame& frame) {
  LooseMotion out;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> solver(block);
  const Vector6d values = solver.eigenvalues().cwiseMax(0.0);  // ascending
  if (!(values[5] > 0)) {
    out.hold = 0;
    out.looseWays = 6;
    return out;
  }
  out.hold = std::sqrt(values[0] / values[5]);
  for (int k = 0; k < 6; ++k) out.looseWays += std::sqrt(values[k] / values[5]) < kLooseHold;
  // The eigenvector moves points by ω × (p − c) + τ with ω = v.head / length (both parts in
  // the same units at the frame's length): a turn when its rotation part dominates.
  const Vector6d v = solver.eigenvectors().col(0);
  const Eigen::Vector3d omega = v.head<3>() / frame.length, tau = v.tail<3>();
  out.turn = v.head<3>().norm() >= tau.norm();
  if (!out.turn) {
    out.axis = tau.normalized();
    return out;
  }
  out.axis = omega.normalized();
  // The axis point nearest the centre: there ω × (p − c) cancels τ's part across the axis.
  out.through = frame.centre + omega.cross(tau) / omega.squaredNorm();
  return out;
}

}  // namespace rangefuse
