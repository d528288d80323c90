// Exact point-to-mesh distances and mesh-to-mesh statistics.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "rangefuse/core/TriangleClosest.h"
#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse {

/// Where a point comes closest to a mesh: the triangle, the barycentric weights of its corners
/// there, and the distance.
struct ClosestPoint {
  size_t face = 0;
  Eigen::Vector3d weights = Eigen::Vector3d(1, 0, 0);
  double distance = INFINITY;
};

/// Exact distance from points to a triangle mesh. A k-d tree over triangle centroids finds
/// the candidates: every triangle whose centroid lies within (nearest centroid distance +
/// largest centroid-to-vertex radius) is tested, so no closer triangle can be missed.
class MeshDistance {
 public:
  explicit MeshDistance(const TriangleMesh& mesh);
  ~MeshDistance();
  double distance(const Eigen::Vector3d& p) const { return closest(p).distance; }
  /// The closest point itself (distance INFINITY on a mesh without triangles).
  ClosestPoint closest(const Eigen::Vector3d& p) const;

 private:
  struct Index;
  std::unique_ptr<Index> index_;
};

/// Area-weighted random samples on a mesh, deterministic for a seed.
std::vector<Eigen::Vector3d> sampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed);

struct DistanceStats {
  double mean = 0, median = 0, p90 = 0, p99 = 0, max = 0;
};

DistanceStats summarize(std::vector<double> distances);

/// Distances from `count` samples on `from` to the surface of `to`.
std::vector<double> sampledDistances(const TriangleMesh& from, const TriangleMesh& to, size_t count,
                                     uint64_t seed);

}  // namespace rangefuse
