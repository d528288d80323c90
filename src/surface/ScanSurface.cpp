#include "rangefuse/surface/ScanSurface.h"

#include <algorithm>

#include "rangefuse/surface/GridMerging.h"

namespace rangefuse {
namespace {

/// The grid triangulated by `rules`, with filtered normals, placed by `pose`.
ScanSurface surfaceOf(const RangeGrid& grid, const GridTriangulation& rules, const Pose& pose,
                      int normalPasses) {
  TriangleMesh mesh = triangulateGrid(grid, rules);
  const std::vector<Eigen::Vector3d> normals = filteredVertexNormals(mesh, normalPasses);
  ScanSurface s = orientedSurface(std::move(mesh), normals, grid.sensor(), pose);
  s.colourKind = grid.colourKind;
  return s;
}

}  // namespace

ScanSurface buildScanSurface(const RangeGrid& grid, const Pose& pose,
                             const SurfaceOptions& options) {
  const int k = options.mergeTarget > 0 ? mergeFactor(lateralSpacing(grid), options.mergeTarget,
                                                      std::min(grid.cols, grid.rows))
                                        : 1;
  if (k > 1) {
    const double fineStep = gridSpacing(grid);
    const RangeGrid coarse = mergeCells(grid, k, fineStep, options.maxEdgeFactor);
    GridTriangulation rules = gridTriangulation(coarse, options);
    rules.maxEdge = mergedEdgeLimit(gridSpacing(coarse), fineStep, k, options.maxEdgeFactor);
    return surfaceOf(coarse, rules, pose, options.normalPasses);
  }
  return surfaceOf(grid, gridTriangulation(grid, options), pose, options.normalPasses);
}

ScanSurface orientedSurface(TriangleMesh&& mesh, const std::vector<Eigen::Vector3d>& normals,
                            const Sensor& sensor, const Pose& pose) {
  ScanSurface s;
  s.triangles = std::move(mesh.faces);
  s.colours = std::move(mesh.colours);
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
