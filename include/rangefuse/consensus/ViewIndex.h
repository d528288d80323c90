// Exact closest-surface queries on one view's triangles (Wheeler et al. ClosestSurface).
#pragma once

#include <memory>
#include <vector>

#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// A surface observation: closest point, interpolated unit normal and confidence.
struct SurfaceObservation {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double confidence = 0;
  double distance = 0;  ///< from the query point
  int views = 1;        ///< observations averaged into it (consensus surfaces)
};

/// k-d trees over triangle centroids of one view, in two tiers by triangle size so that a
/// few long triangles do not widen every search. A query tests every triangle whose
/// centroid lies within (best distance so far + the tier's largest centroid-to-vertex
/// radius): the answer is exact, ties going to the lower triangle index.
class ViewIndex {
 public:
  /// Indexes the triangles of `scan` listed in `triangles` (all when empty).
  explicit ViewIndex(const ScanSurface& scan, const std::vector<int32_t>& triangles = {});
  ~ViewIndex();
  ViewIndex(ViewIndex&&) noexcept;

  /// The closest observation within maxDistance of x; false when there is none.
  bool closest(const Eigen::Vector3d& x, double maxDistance, SurfaceObservation& out) const;
  size_t size() const;

 private:
  struct Tier;
  const ScanSurface* scan_;
  std::vector<std::unique_ptr<Tier>> tiers_;
};

}  // namespace rangefuse
