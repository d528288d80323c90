#include "KeyFrameFit.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace rangefuse::internal {
namespace {

/// Normals further apart than this (cosine) are not the same surface seen twice.
constexpr double kSameSide = 0.5;

/// One source point's pairing: its residual along the target's normal and the row of the
/// residual's derivative in the source's frame (translation, rotation). False when it has no
/// partner within `radius`.
bool pairPoint(const KeyFramePoints& target, const Pose& motion, const Eigen::Vector3d& p,
               const Eigen::Vector3d& n, double radius, double& residual, Vector6d& row) {
  const Eigen::Vector3d q = motion.apply(p);
  const long j = target.nearest(q, radius);
  if (j < 0) return false;
  const Eigen::Vector3d& m = target.normals()[static_cast<size_t>(j)];
  if (m.dot(motion.R * n) < kSameSide) return false;
  residual = m.dot(q - target.points()[static_cast<size_t>(j)]);
  const Eigen::Vector3d a = motion.R.transpose() * m;
  row << a, p.cross(a);
  return true;
}

double huberWeight(double r, double huber) {
  return std::abs(r) <= huber ? 1 : huber / std::abs(r);
}

}  // namespace

KeyFramePoints::KeyFramePoints(std::vector<Eigen::Vector3d> points,
                               std::vector<Eigen::Vector3d> normals)
    : normals_(std::move(normals)) {
  cloud_->pts = std::move(points);
  tree_ = buildKdTree(*cloud_);
  std::vector<double> ranges;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : cloud_->pts) ranges.push_back(p.norm()), sum += p;
  if (!ranges.empty()) {
    auto mid = ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2);
    std::nth_element(ranges.begin(), mid, ranges.end());
    medianRange_ = *mid;
  }
  if (sum.norm() > 0) view_ = sum.normalized();
}

long KeyFramePoints::nearest(const Eigen::Vector3d& p, double radius) const {
  if (cloud_->pts.empty()) return -1;
  size_t index = 0;
  double squared = 0;
  nanoflann::KNNResultSet<double> result(1);
  result.init(&index, &squared);
  tree_->findNeighbors(result, p.data(), nanoflann::SearchParams());
  return squared <= radius * radius ? static_cast<long>(index) : -1;
}

PairFit measurePair(const KeyFramePoints& target, const KeyFramePoints& source, const Pose& motion,
                    double radius, double huber) {
  PairFit fit;
  fit.motion = motion;
  size_t paired = 0;
  double squares = 0;
  for (size_t i = 0; i < source.points().size(); ++i) {
    double r;
    Vector6d row;
    if (!pairPoint(target, motion, source.points()[i], source.normals()[i], radius, r, row))
      continue;
    ++paired;
    squares += r * r;
    fit.information += huberWeight(r, huber) * row * row.transpose();
  }
  // Residuals of about `huber` are a point's own noise: the information is in those units.
  fit.information /= huber * huber;
  fit.inliers = source.points().empty() ? 0 : static_cast<double>(paired) / source.points().size();
  fit.rms = paired ? std::sqrt(squares / paired) : 0;
  return fit;
}

PairFit fitPair(const KeyFramePoints& target, const KeyFramePoints& source, const Pose& guess,
                const PairFitSettings& s) {
  Pose motion = guess;
  double radius = s.startRadius;
  for (int it = 0; it < s.iterations; ++it) {
    Matrix6d H = Matrix6d::Zero();
    Vector6d g = Vector6d::Zero();
    for (size_t i = 0; i < source.points().size(); ++i) {
      double r;
      Vector6d row;
      if (!pairPoint(target, motion, source.points()[i], source.normals()[i], radius, r, row))
        continue;
      const double w = huberWeight(r, s.huber);
      H += w * row * row.transpose();
      g += w * r * row;
    }
    const Eigen::LDLT<Matrix6d> solve(H);
    if (solve.info() != Eigen::Success) break;
    const Vector6d step = -solve.solve(g);
    if (!step.allFinite()) break;
    motion = motion * twistPose(step);
    const bool last = radius <= s.endRadius;
    radius = std::max(s.endRadius, 0.7 * radius);
    if (last && step.cwiseAbs().maxCoeff() < 1e-7) break;
  }
  return measurePair(target, source, motion, s.endRadius, s.huber);
}

double overlapShare(const KeyFramePoints& target, const KeyFramePoints& source, const Pose& motion,
                    double radius, int stride) {
  size_t tried = 0, near = 0;
  for (size_t i = 0; i < source.points().size(); i += static_cast<size_t>(stride)) {
    ++tried;
    near += target.nearest(motion.apply(source.points()[i]), radius) >= 0;
  }
  return tried ? static_cast<double>(near) / tried : 0;
}

}  // namespace rangefuse::internal
