// Key frames' poses made to agree with the motions measured between them: the tracked motion
// from one key frame to the next, and the loops closed when the camera came back. Gauss-Newton
// on SE(3) over a sparse graph, the first node fixed (it holds the world frame).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "rangefuse/core/Pose.h"

namespace rangefuse::internal {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// A measured motion between two nodes: poses[to] should be poses[from] * measured. The
/// information weighs the error twist (translation, then rotation vector) of
/// measured^-1 * poses[from]^-1 * poses[to], in `to`'s frame.
struct PoseEdge {
  size_t from = 0, to = 0;
  Pose measured;
  Matrix6d information = Matrix6d::Identity();
};

/// The small rigid motion of a twist (translation, rotation vector).
Pose twistPose(const Vector6d& twist);

/// The error twist of an edge at `poses`: zero when they agree with its measurement.
Vector6d edgeError(const PoseEdge& edge, const std::vector<Pose>& poses);

/// The sum over the edges of e^T Omega e at `poses`.
double graphCost(const std::vector<Pose>& poses, const std::vector<PoseEdge>& edges);

/// Moves every pose but the first to minimise graphCost (Gauss-Newton, at most `iterations`
/// steps, until a step moves no pose by more than `tolerance` in translation or radians).
/// Returns the final cost. The same inputs give the same bits on every rank.
double optimisePoseGraph(std::vector<Pose>& poses, const std::vector<PoseEdge>& edges,
                         int iterations = 20, double tolerance = 1e-9);

}  // namespace rangefuse::internal
