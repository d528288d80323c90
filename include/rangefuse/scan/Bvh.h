// Bounding-volume hierarchy over a triangle mesh for exact first-hit ray casting.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse {

struct RayHit {
  double t = 0;       ///< distance along the (unit) direction
  int32_t face = -1;  ///< triangle index
};

/// Exact ray/triangle intersection (Moller-Trumbore); true with t in (tMin, tMax).
bool intersectTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, const Eigen::Vector3d& c, double tMin, double tMax,
                       double& t);

class Bvh {
 public:
  explicit Bvh(const TriangleMesh& mesh);

  /// Nearest hit of the ray o + t d with t in (tMin, tMax); false when none.
  bool firstHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tMin, double tMax,
                RayHit& hit) const;

  /// Reference for firstHit: every triangle tested.
  bool firstHitBruteForce(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tMin,
                          double tMax, RayHit& hit) const;

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int32_t left = -1, right = -1;  ///< children, or -1 for a leaf
    int32_t begin = 0, end = 0;     ///< leaf: range in order_
  };
  int32_t build(int32_t begin, int32_t end);

  const TriangleMesh mesh_;  // a copy: callers may pass temporaries
  std::vector<int32_t> order_;
  std::vector<Eigen::Vector3d> centroids_;
  std::vector<Node> nodes_;
};

}  // namespace rangefuse
