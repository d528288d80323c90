// Two key frames fitted to each other, point to plane: how a loop is measured when the camera
// comes back to where an earlier key frame saw the scene.
#pragma once

#include <memory>
#include <vector>

#include "PoseGraph.h"
#include "rangefuse/core/KdTree.h"

namespace rangefuse::internal {

/// A key frame's points and unit normals in its own frame, with a tree over the points.
class KeyFramePoints {
 public:
  KeyFramePoints() = default;
  KeyFramePoints(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals);
  KeyFramePoints(KeyFramePoints&&) = default;
  KeyFramePoints& operator=(KeyFramePoints&&) = default;

  const std::vector<Eigen::Vector3d>& points() const { return cloud_->pts; }
  const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
  /// The index of the point nearest `p` within `radius`, or -1.
  long nearest(const Eigen::Vector3d& p, double radius) const;
  /// The median distance of the points from the frame's origin (the camera).
  double medianRange() const { return medianRange_; }
  /// The unit direction from the camera to the points' centroid.
  const Eigen::Vector3d& view() const { return view_; }

 private:
  std::unique_ptr<PointCloud> cloud_ = std::make_unique<PointCloud>();  ///< the tree's, fixed
  std::vector<Eigen::Vector3d> normals_;
  std::unique_ptr<KdTree> tree_;
  double medianRange_ = 0;
  Eigen::Vector3d view_ = Eigen::Vector3d::UnitZ();
};

/// How far a fit starts and ends: correspondences within `startRadius` at first, shrinking to
/// `endRadius`; residuals beyond `huber` weigh less.
struct PairFitSettings {
  double startRadius = 0.1, endRadius = 0.02, huber = 0.01;
  int iterations = 30;
};

/// The outcome: the motion from `source`'s frame into `target`'s, the information of its error
/// twist (PoseEdge's), the share of source points within endRadius of the target and their
/// RMS distance to its planes.
struct PairFit {
  Pose motion;
  Matrix6d information = Matrix6d::Zero();
  double inliers = 0, rms = 0;
};

/// The fit's figures at `motion` as it stands, correspondences within `radius`.
PairFit measurePair(const KeyFramePoints& target, const KeyFramePoints& source, const Pose& motion,
                    double radius, double huber);

/// Fits `source` to `target` from `guess` (target point ~ motion * source point), then
/// measurePair at the end radius.
PairFit fitPair(const KeyFramePoints& target, const KeyFramePoints& source, const Pose& guess,
                const PairFitSettings& settings);

/// The share of every `stride`-th source point, moved by `motion`, within `radius` of a target
/// point: how much two key frames overlap.
double overlapShare(const KeyFramePoints& target, const KeyFramePoints& source, const Pose& motion,
                    double radius, int stride = 8);

}  // namespace rangefuse::internal
