#include "rangefuse/eval/TrajectoryError.h"

#include <Eigen/SVD>
#include <cmath>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/DepthSequence.h"

namespace rangefuse {
namespace {

double angleDeg(const Eigen::Matrix3d& R) {
  const double c = std::clamp((R.trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / M_PI;
}

/// The relative pose error of the pairs (i, j), t_j - t_i >= delta, j the first such.
void relativeError(const std::vector<io::TimedPose>& est, const std::vector<Pose>& ref,
                   double delta, TrajectoryError& e) {
  double t2 = 0, r2 = 0;
  size_t j = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    j = std::max(j, i + 1);
    while (j < est.size() && est[j].time - est[i].time < delta) ++j;
    if (j >= est.size()) break;
    const Pose& a = est[i].cameraToWorld;
    const Pose& b = est[j].cameraToWorld;
    const Pose error = relative(relative(ref[i], ref[j]), relative(a, b));
    t2 += error.t.squaredNorm();
    const double a2 = angleDeg(error.R);
    r2 += a2 * a2;
    ++e.rpePairs;
  }
  if (e.rpePairs == 0) return;
  e.rpeTranslationRmse = std::sqrt(t2 / e.rpePairs);
  e.rpeRotationRmseDeg = std::sqrt(r2 / e.rpePairs);
}

}  // namespace

Pose alignPoints(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to) {
  Eigen::Vector3d cf = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < from.size(); ++k) cf += from[k], ct += to[k];
  cf /= static_cast<double>(from.size());
  ct /= static_cast<double>(to.size());
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < from.size(); ++k) H += (from[k] - cf) * (to[k] - ct).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) D(2, 2) = -1;
  Pose p;
  p.R = svd.matrixV() * D * svd.matrixU().transpose();
  p.t = ct - p.R * cf;
  return p;
}

TrajectoryError compareTrajectories(const std::vector<io::TimedPose>& estimate,
                                    const std::vector<io::TimedPose>& reference,
                                    double maxDifference, double rpeDelta, PoseMatching matching) {
  std::vector<double> et, rt;
  for (const auto& p : estimate) et.push_back(p.time);
  for (const auto& p : reference) rt.push_back(p.time);
  std::vector<long> match = io::nearestTimes(et, rt, maxDifference);
  if (matching == PoseMatching::byIndex)
    for (size_t k = 0; k < match.size(); ++k)
      match[k] = k < reference.size() ? static_cast<long>(k) : -1;
  std::vector<io::TimedPose> est;
  std::vector<Pose> ref;
  std::vector<Eigen::Vector3d> from, to;
  for (size_t k = 0; k < estimate.size(); ++k) {
    if (match[k] < 0) continue;
    est.push_back(estimate[k]);
    ref.push_back(reference[match[k]].cameraToWorld);
    from.push_back(estimate[k].cameraToWorld.t);
    to.push_back(ref.back().t);
  }
  TrajectoryError e;
  e.matching = matching;
  e.estimated = estimate.size();
  e.matched = est.size();
  if (e.matched < 3 || 2 * e.matched < estimate.size())
    throw InputError(
        "only " + std::to_string(e.matched) + " of the " + std::to_string(estimate.size()) +
        " estimated poses " +
        (matching == PoseMatching::byIndex
             ? "have a reference pose of the same index"
             : "have a reference pose within " + std::to_string(maxDifference) + " s") +
        ": the trajectories do not match (at least half must)");
  e.alignment = alignPoints(from, to);
  double sum2 = 0, sum = 0;
  for (size_t k = 0; k < from.size(); ++k) {
    const double d = (e.alignment.apply(from[k]) - to[k]).norm();
    sum2 += d * d, sum += d, e.ateMax = std::max(e.ateMax, d);
  }
  e.ateRmse = std::sqrt(sum2 / e.matched);
  e.ateMean = sum / e.matched;
  relativeError(est, ref, rpeDelta, e);
  return e;
}

}  // namespace rangefuse
