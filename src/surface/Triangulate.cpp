#include <algorithm>
#include <cmath>

#include "rangefuse/surface/GridSteps.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {
namespace {

bool keepTriangle(const RangeGrid& g, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, double maxEdge, double minCos) {
  if ((a - b).norm() > maxEdge || (b - c).norm() > maxEdge || (c - a).norm() > maxEdge)
    return false;
  Eigen::Vector3d n = (b - a).cross(c - a);
  double len = n.norm();
  if (len == 0) return false;
  Eigen::Vector3d centre = (a + b + c) / 3.0;
  return n.dot(g.towardSensor(centre)) / len >= minCos;
}

}  // namespace

double gridSpacing(const RangeGrid& grid) {
  // Squares keep the order, so the median step is the root of the median square: one root.
  return std::sqrt(internal::medianNeighbourStep(
      grid,
      [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).squaredNorm(); }));
}

TriangleMesh triangulateGrid(const RangeGrid& grid, const SurfaceOptions& options) {
  const double maxEdge = options.maxEdgeFactor * gridSpacing(grid);
  std::vector<int32_t> remap(grid.points.size(), -1);
  TriangleMesh mesh;
  auto use = [&](int32_t i) {
    if (remap[i] < 0) {
      remap[i] = static_cast<int32_t>(mesh.vertices.size());
      mesh.vertices.push_back(grid.points[i]);
    }
    return remap[i];
  };
  auto emit = [&](int32_t a, int32_t b, int32_t c) {
    if (a < 0 || b < 0 || c < 0) return;
    if (!keepTriangle(grid, grid.points[a], grid.points[b], grid.points[c], maxEdge,
                      options.minCosine))
      return;
    mesh.faces.push_back({use(a), use(b), use(c)});
  };
  // (r,c),(r,c+1),(r+1,c) has its normal toward +z, the sensor side (NOTES.md).
  for (int r = 0; r + 1 < grid.rows; ++r)
    for (int c = 0; c + 1 < grid.cols; ++c) {
      emit(grid.at(r, c), grid.at(r, c + 1), grid.at(r + 1, c));
      emit(grid.at(r, c + 1), grid.at(r + 1, c + 1), grid.at(r + 1, c));
    }
  return mesh;
}

}  // namespace rangefuse
