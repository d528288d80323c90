// One Gauss-Newton step of all poses at once (Algorithm 2's fits, solved jointly): every voxel
// that several scans' control points fall into is a small plane along the field's gradient
// whose offset is unknown. Eliminating that offset leaves, per voxel, point-to-plane terms
// between the scans that share it, so the scans are fitted to one another, not to a field that
// holds each of them, and the anchor fixes the gauge exactly (no drift of the group).
#pragma once

#include <mpi.h>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "rangefuse/core/Pose.h"

namespace rangefuse {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Where motions are linearised: a motion (ω, τ) moves p to centre + exp(ω/length)(p − centre)
/// + τ. Scaling ω by a length of the data (lengths at most `length` from the centre) gives
/// rotation and translation the same units, so every Jacobian entry is at most 1.
struct MotionFrame {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double length = 1;
};

/// One scan's control points in one voxel, summed (weights at most 1 each).
struct VoxelShare {
  uint32_t scan = 0;
  uint32_t points = 0;
  double weight = 0;                     ///< Σ w
  Vector6d jacobian = Vector6d::Zero();  ///< Σ w a, a = [(p − c) × f / length, f]
  double residual = 0;                   ///< Σ w r, r = the point's signed distance along f

  /// Adds a control point p (weight w, in (0, 1]) with unit gradient f and distance r.
  void add(const Eigen::Vector3d& p, const Eigen::Vector3d& f, double r, double w,
           const MotionFrame& frame);
};

/// The joint normal equations H δ = −g over every scan's motion, with per-scan residuals.
struct JointEquations {
  std::map<std::pair<uint32_t, uint32_t>, Matrix6d> blocks;  ///< H_st for s <= t, nonzero only
  std::vector<Vector6d> gradient;                            ///< g_s
  std::vector<double> weight, squares;  ///< per scan: Σ w and Σ w e² of its paired shares
  std::vector<uint64_t> points;         ///< per scan: control points in shared voxels
  /// Per pair of scans s < t: the control points of both in voxels both reached (their overlap).
  std::map<std::pair<uint32_t, uint32_t>, uint64_t> pairPoints;

  explicit JointEquations(size_t scans = 0)
      : gradient(scans, Vector6d::Zero()), weight(scans, 0), squares(scans, 0), points(scans, 0) {}
  /// Weighted RMS of scan s's residuals to the voxels' planes.
  double rms(size_t s) const;
};

/// The equations of voxels' shares summed here in double (tests, one rank).
JointEquations jointEquations(const std::vector<std::vector<VoxelShare>>& voxels, size_t scans);

/// Collective: the equations of every rank's voxels (a voxel's shares all on one rank), the same
/// bits on every rank whatever their number. `maxResidual` bounds every |r|.
JointEquations reduceJointEquations(const std::vector<std::vector<VoxelShare>>& voxels,
                                    size_t scans, double maxResidual, MPI_Comm comm);

/// Marquardt's damping of solveJoint, relative to the largest diagonal entry of a scan's block.
constexpr double kJointDamping = 1e-3;

/// Solves (H + damping · D) δ = −g for the scans marked free, D the largest diagonal entry of
/// each scan's block; the others (the anchor: the gauge) keep δ = 0. The damping keeps a
/// motion the surfaces do not constrain (turning about a sphere's centre, sliding along a
/// plane) near zero instead of following whatever the noise leaves in the gradient.
std::vector<Vector6d> solveJoint(const JointEquations& eq, const std::vector<char>& free,
                                 double damping = kJointDamping);

/// The pose change that applies motion δ in `frame` (left-multiplied onto a pose).
Pose motionPose(const Vector6d& delta, const MotionFrame& frame);

}  // namespace rangefuse
