// A nanoflann k-d tree over 3-D points (used for triangle centroids and scan points).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <nanoflann.hpp>
#include <vector>

namespace rangefuse {

/// The dataset adaptor nanoflann expects, over a vector of points.
struct PointCloud {
  std::vector<Eigen::Vector3d> pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(size_t i, size_t d) const { return pts[i][d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                   PointCloud, 3>;

/// Builds a tree over `cloud` (which must outlive it).
inline std::unique_ptr<KdTree> buildKdTree(const PointCloud& cloud, size_t leafSize = 10) {
  auto tree =
      std::make_unique<KdTree>(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(leafSize));
  tree->buildIndex();
  return tree;
}

}  // namespace rangefuse
