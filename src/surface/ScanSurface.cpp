#include "rangefuse/surface/ScanSurface.h"

#include <algorithm>

#include "rangefuse/surface/GridMerging.h"

namespace rangefuse {

ScanSurface buildScanSurface(const RangeGrid& grid, const Pose& pose,
                             const SurfaceOptions& options) {
  if (options.mergeTarget > 0) {
    const int k =
        mergeFactor(lateralSpacing(grid), options.mergeTarget, std::min(grid.cols, grid.rows));
    SurfaceOptions merged = options;
    merged.mergeTarget = 0;
    if (k > 1) {
      const RangeGrid coarse = mergeCells(grid, k, gridSpacing(grid), options.maxEdgeFactor);
      return buildScanSurface(coarse, pose, merged);
    }
  }
  TriangleMesh mesh = triangulateGrid(grid, options);
  const std::vector<Eigen::Vector3d> normals = filteredVertexNormals(mesh, options.normalPasses);
  return orientedSurface(std::move(mesh), normals, grid.sensor(), pose);
}

ScanSurface orientedSurface(TriangleMesh&& mesh, const std::vector<Eigen::Vector3d>& normals,
                            const Sensor& sensor, const Pose& pose) {
  ScanSurface s;
  s.triangles = std::move(mesh.faces);
  s.sensor = sensor.placed(pose);
  s.points.reserve(mesh.vertices.size());
  s.normals.reserve(mesh.vertices.size());
  s.confidence.reserve(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& p = mesh.vertices[i];
    s.confidence.push_back(std::max(0.0, normals[i].dot(sensor.toward(p))));
    s.points.push_back(pose.apply(p));
    s.normals.push_back(pose.rotate(normals[i]));
  }
  return s;
}

}  // namespace rangefuse
