#include "rangefuse/register/RigidFit.h"

#include <Eigen/SVD>

namespace rangefuse {

void RigidSums::add(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double weight) {
  w += weight;
  wp += weight * p;
  wq += weight * q;
  wpq += weight * p * q.transpose();
  wr2 += weight * (q - p).squaredNorm();
  count += 1;
}

RigidSums& RigidSums::operator+=(const RigidSums& o) {
  w += o.w;
  wp += o.wp;
  wq += o.wq;
  wpq += o.wpq;
  wr2 += o.wr2;
  count += o.count;
  return *this;
}

Pose fitRigid(const RigidSums& s) {
  Pose pose;
  if (s.count < 3 || !(s.w > 0)) return pose;
  const Eigen::Vector3d pm = s.wp / s.w, qm = s.wq / s.w;
  // Cross-covariance about the centroids: sum w (p - pm)(q - qm)^T.
  const Eigen::Matrix3d H = s.wpq - s.w * pm * qm.transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  pose.R = svd.matrixV() * D * svd.matrixU().transpose();
  pose.t = qm - pose.R * pm;
  return pose;
}

}  // namespace rangefuse
