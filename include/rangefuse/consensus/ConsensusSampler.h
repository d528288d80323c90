// The consensus (or naive) signed distance as a brick-by-brick field sampler.
#pragma once

#include "rangefuse/consensus/NearSurface.h"

namespace rangefuse {

class ConsensusSampler : public FieldSampler {
 public:
  /// `margin` (world units): triangles farther than this from a brick are consulted only when
  /// the nearer ones cannot decide, and never when `complete` is false (the views hold only
  /// the triangles near this rank's bricks): there the voxel stays unobserved (RegionViews).
  ConsensusSampler(const std::vector<ViewIndex>& views, const ConsensusParams& params, bool naive,
                   double margin, bool complete)
      : region_(views, complete), params_(params), naive_(naive), margin_(margin) {}

  void enterBrick(const Eigen::AlignedBox3d& bounds) override { region_.focus(bounds, margin_); }

  bool sample(const Eigen::Vector3d& x, SignedDistance& out) override {
    return naive_ ? naiveSignedDistance(x, region_, params_, out)
                  : consensusSignedDistance(x, region_, params_, out);
  }

 private:
  RegionViews region_;
  ConsensusParams params_;
  bool naive_;
  double margin_;
};

}  // namespace rangefuse
