// Consensus surfaces (Wheeler, Sato, Ikeuchi, ICCV 1998, §4.2) and the naive baseline.
#pragma once

#include <cmath>
#include <vector>

#include "rangefuse/consensus/ViewIndex.h"

namespace rangefuse {

struct ConsensusParams {
  double quorum = 1.5;         ///< theta_quorum: summed confidence a consensus needs
  int minViews = 1;            ///< ... and the views it needs (Wheeler: 1, the quorum alone)
  double sameDistance = 2.0;   ///< delta_d, world units
  double sameCosine = 0.7071;  ///< cos(theta_n)
  double reach = INFINITY;     ///< closest-surface queries look no farther, world units
  double edgeCosine = 0;       ///< x is unobserved where |n.(x-p)| < this |x-p| ...
  double edgeSlack = 0;        ///< ... and |x-p| > this (world units): beside an open edge
  double memberSlack = 0;      ///< the same test for an observation joining a consensus
};

/// The views, and which of them come near a region. Queries start with the near views and
/// consult the others only when the near ones cannot decide, so the answers are exactly
/// those of the full algorithms.
class RegionViews {
 public:
  /// `complete`: the views hold every triangle of every scan. When false they may hold only
  /// the triangles near the focused region (a rank's routed share), and a question the near
  /// triangles cannot settle exactly is answered "unobserved" instead of by all triangles.
  explicit RegionViews(const std::vector<ViewIndex>& views, bool complete = true);
  /// Restricts to a ball around box: near = views with a triangle within ball radius + margin.
  void focus(const Eigen::AlignedBox3d& box, double margin);

  const std::vector<ViewIndex>& all() const { return *views_; }
  const std::vector<int>& near() const { return near_; }
  /// True when every view with a triangle within `r` of p is a near view.
  bool coversBall(const Eigen::Vector3d& p, double r) const {
    return (p - centre_).norm() + r <= radius_ + margin_;
  }
  /// A closest-surface result farther than this from a point in the region cannot come from
  /// a view that is not near.
  double margin() const { return margin_; }
  bool complete() const { return complete_; }

 private:
  const std::vector<ViewIndex>* views_;
  std::vector<int> near_;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  double radius_ = INFINITY, margin_ = INFINITY;
  bool complete_ = true;
};

/// Eq. 1: two observations of the same surface.
bool sameSurface(const Eigen::Vector3d& p0, const Eigen::Vector3d& n0, const Eigen::Vector3d& p1,
                 const Eigen::Vector3d& n1, const ConsensusParams& params);

/// Algorithm ConsensusSurface: the confidence-weighted average of every view's closest
/// observation to p that passes SameSurface with (p, n); `confidence` is their sum.
SurfaceObservation consensusSurface(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                                    const RegionViews& views, const ConsensusParams& params);

/// Algorithm ClosestConsensusSurface for x inside the focused region; false when no view
/// has a surface within reach.
bool closestConsensusSurface(const Eigen::Vector3d& x, const RegionViews& views,
                             const ConsensusParams& params, SurfaceObservation& out);

/// A signed distance with the direction of its gradient and a weight.
struct SignedDistance {
  double d = 0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();  ///< unit, toward increasing d
  double weight = 0;
  int views = 1;  ///< views behind the surface point (those in its consensus)
};

/// Algorithm ConsensusSignedDistance: distance to the closest consensus point, signed by its
/// normal. The gradient is the unit direction from that point to x (the normal when x lies
/// on it). False when nothing is within reach.
bool consensusSignedDistance(const Eigen::Vector3d& x, const RegionViews& views,
                             const ConsensusParams& params, SignedDistance& out);

/// Algorithm ClosestSignedDistance (naive): the closest observation over all views.
bool naiveSignedDistance(const Eigen::Vector3d& x, const RegionViews& views,
                         const ConsensusParams& params, SignedDistance& out);

}  // namespace rangefuse
