#include "rangefuse/register/Registration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace rangefuse {
namespace {

/// A fit's motion as a twist about the control points' centroid: rotation vector scaled by
/// their RMS radius (so both halves are lengths) and translation of the centroid.
struct Twist {
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();  // axis * angle (radians)
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  double radius = 1;

  Eigen::Matrix<double, 6, 1> vector() const {
    Eigen::Matrix<double, 6, 1> v;
    v << radius * rotation, shift;
    return v;
  }
};

/// Successive fits of one scan, for acceleration: a linearly converging fit that keeps
/// stepping the same way is sped up by the rest of the geometric series (Besl & McKay).
struct FitHistory {
  bool have = false;
  Twist last;
};

Twist twistOf(const Pose& delta, const Eigen::Vector3d& centre, double radius) {
  const Eigen::AngleAxisd aa(delta.R);
  Twist t;
  t.rotation = aa.angle() * aa.axis();
  t.shift = delta.apply(centre) - centre;
  t.radius = radius;
  return t;
}

Pose poseOf(const Twist& t, const Eigen::Vector3d& centre, double scale) {
  Pose p;
  const double angle = t.rotation.norm() * scale;
  if (angle > 0) p.R = Eigen::AngleAxisd(angle, t.rotation.normalized()).toRotationMatrix();
  p.t = centre + scale * t.shift - p.R * centre;
  return p;
}

/// The extrapolation factor for this fit given the previous one (1: none).
double acceleration(const Twist& now, const FitHistory& h) {
  if (!h.have) return 1;
  const auto a = now.vector(), b = h.last.vector();
  if (!(a.norm() > 0 && b.norm() > 0) || a.dot(b) < 0.95 * a.norm() * b.norm()) return 1;
  const double r = a.norm() / b.norm();
  return r < 0.95 ? std::min(8.0, 1 / (1 - r)) : 1;
}

/// One fit of scan i against the field: correspondences, sums across ranks, rigid update.
RegistrationStep fitOnce(const PrismScan& scan, Pose& pose, const BrickStore& field,
                         const RegistrationOptions& o, MPI_Comm comm, FitHistory& history) {
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<double> weights;
  const ScanSurface& s = scan.surface;
  for (size_t v = 0; v < s.points.size(); v += o.controlStride) {
    points.push_back(pose.apply(s.points[v]));
    normals.push_back(pose.rotate(s.normals[v]));
    weights.push_back(s.confidence[v]);
  }
  const RigidSums sums =
      correspondenceSums(field, points, normals, weights, o.correspondences, comm);
  RegistrationStep step;
  step.correspondences = static_cast<uint64_t>(sums.count);
  step.rms = sums.rms();
  if (sums.count < o.minCorrespondences) return step;
  const Eigen::Vector3d centre = sums.wp / sums.w;
  const double radius =
      std::sqrt(std::max(1e-30, sums.wpq.trace() / sums.w - centre.squaredNorm()));
  const Twist twist = twistOf(fitRigid(sums), centre, radius);
  const Pose delta = poseOf(twist, centre, o.accelerate ? acceleration(twist, history) : 1.0);
  history = FitHistory{true, twist};
  pose.R = delta.R * pose.R;
  pose.t = delta.R * pose.t + delta.t;
  step.rotationDeg = rotationDegrees(delta.R);
  step.translation = delta.t.norm();
  step.applied = true;
  return step;
}

bool converged(const RegistrationStep& s, const RegistrationOptions& o) {
  return !s.applied || (s.rotationDeg < o.rotationTolDeg && s.translation < o.translationTol);
}

void incremental(const std::vector<PrismScan>& scans, std::vector<Pose>& poses,
                 const RegistrationOptions& o, const FieldFactory& build, MPI_Comm comm,
                 const std::function<void(const RegistrationStep&)>& onStep) {
  std::vector<size_t> fused = {o.anchor};
  for (size_t i = 0; i < scans.size(); ++i) {
    if (i == o.anchor) continue;
    const BrickStore& field = build(fused, poses);
    FitHistory history;
    for (int it = 1; it <= o.maxIterations; ++it) {
      RegistrationStep step = fitOnce(scans[i], poses[i], field, o, comm, history);
      step.algorithm = "incremental";
      step.iteration = it;
      step.scan = i;
      onStep(step);
      if (converged(step, o)) break;
    }
    fused.push_back(i);
  }
}

void simultaneous(const std::vector<PrismScan>& scans, std::vector<Pose>& poses,
                  RegistrationOptions o, const FieldFactory& build, MPI_Comm comm,
                  const std::function<void(const RegistrationStep&)>& onStep) {
  // The field holds each scan itself: only voxels another image also saw are overlap.
  o.correspondences.minImages = 2;
  std::vector<size_t> all;
  for (size_t i = 0; i < scans.size(); ++i) all.push_back(i);
  for (int round = 1; round <= o.maxRounds; ++round) {
    const BrickStore& field = build(all, poses);
    std::vector<FitHistory> history(scans.size());
    bool rebuiltFieldMovedScans = false;
    for (int it = 1; it <= o.maxIterations; ++it) {
      bool moved = false;
      for (size_t i = 0; i < scans.size(); ++i) {
        if (i == o.anchor) continue;
        RegistrationStep step = fitOnce(scans[i], poses[i], field, o, comm, history[i]);
        step.algorithm = "simultaneous";
        step.round = round;
        step.iteration = it;
        step.scan = i;
        onStep(step);
        moved |= !converged(step, o);
      }
      if (it == 1) rebuiltFieldMovedScans = moved;
      if (!moved) break;
    }
    if (!rebuiltFieldMovedScans) break;  // the poses stopped changing
  }
}

}  // namespace

double rotationDegrees(const Eigen::Matrix3d& R) {
  return std::abs(Eigen::AngleAxisd(R).angle()) * 180 / M_PI;
}

void registerScans(const std::vector<PrismScan>& scans, std::vector<Pose>& poses,
                   const RegistrationOptions& o, const FieldFactory& build, MPI_Comm comm,
                   const std::function<void(const RegistrationStep&)>& onStep) {
  if (o.mode == "incremental" || o.mode == "both")
    incremental(scans, poses, o, build, comm, onStep);
  if (o.mode == "simultaneous" || o.mode == "both")
    simultaneous(scans, poses, o, build, comm, onStep);
}

}  // namespace rangefuse
