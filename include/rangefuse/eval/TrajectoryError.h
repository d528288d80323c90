// Trajectory accuracy as the TUM RGB-D benchmark defines it: the absolute trajectory error
// (ATE: RMSE of camera positions after the rigid motion that best aligns the estimate to the
// reference, Horn's method) and the relative pose error over one second (RPE: the drift of the
// motion between frames a second apart).
#pragma once

#include <vector>

#include "rangefuse/io/Trajectory.h"

namespace rangefuse {

/// How estimated poses find their reference poses: the nearest in time, or the same index
/// (for a trajectory without times, as a .log is, beside one with real timestamps).
enum class PoseMatching { byTime, byIndex };

struct TrajectoryError {
  PoseMatching matching = PoseMatching::byTime;
  size_t estimated = 0;  ///< poses of the estimate
  size_t matched = 0;    ///< estimated poses with a reference pose
  double ateRmse = 0;    ///< world units
  double ateMean = 0, ateMax = 0;
  size_t rpePairs = 0;            ///< pairs of matched poses about `rpeDelta` apart
  double rpeTranslationRmse = 0;  ///< world units per rpeDelta
  double rpeRotationRmseDeg = 0;  ///< degrees per rpeDelta
  Pose alignment;                 ///< reference = alignment * estimate (best rigid motion)
};

/// The rigid motion (no scale) that best maps points `from` onto `to` in least squares.
Pose alignPoints(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to);

/// Compares an estimated trajectory with a reference: each estimated pose is matched to the
/// reference pose nearest in time within `maxDifference` seconds (or of the same index); the
/// RPE takes, for every matched pose, the first matched pose at least `rpeDelta` seconds
/// later. Throws InputError when fewer than 3 poses, or fewer than half the estimate's, match.
TrajectoryError compareTrajectories(const std::vector<io::TimedPose>& estimate,
                                    const std::vector<io::TimedPose>& reference,
                                    double maxDifference = 0.02, double rpeDelta = 1.0,
                                    PoseMatching matching = PoseMatching::byTime);

}  // namespace rangefuse
