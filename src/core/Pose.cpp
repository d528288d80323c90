#include "rangefuse/core/Pose.h"

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

}  // namespace

std::string rotationProblem(const Eigen::Matrix3d& R) {
  if (!R.allFinite()) return "not finite";
  const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (!(off <= kRotationTolerance)) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R);
    return "not rigid: R^T R is off the identity by " + number(off) + " (it scales lengths by " +
           number(svd.singularValues().minCoeff()) + " to " +
           number(svd.singularValues().maxCoeff()) + ")";
  }
  if (R.determinant() < 0) return "a reflection (determinant " + number(R.determinant()) + ")";
  return "";
}

Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) d(2, 2) = -1;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

Pose rigidPose(const Pose& pose, const std::string& where) {
  if (!pose.t.allFinite() || !pose.R.allFinite())
    throw InputError(where + ": the pose is not finite");
  const std::string problem = rotationProblem(pose.R);
  if (!problem.empty()) throw InputError(where + ": the pose's rotation is " + problem);
  if ((pose.R.transpose() * pose.R).isIdentity(1e-9)) return pose;
  return Pose{nearestRotation(pose.R), pose.t};
}

}  // namespace rangefuse
