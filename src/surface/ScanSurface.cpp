#include "rangefuse/surface/ScanSurface.h"

#include <algorithm>

#include "rangefuse/surface/DepthSmoothing.h"
#include "rangefuse/surface/FlatBlocks.h"
#include "rangefuse/surface/GridMerging.h"

namespace rangefuse {
namespace {

/// Each merged point's block (row, column) in the merged grid.
std::vector<std::array<int32_t, 2>> blockPlaces(const RangeGrid& merged) {
  std::vector<std::array<int32_t, 2>> places(merged.points.size());
  for (int r = 0; r < merged.rows; ++r)
    for (int c = 0; c < merged.cols; ++c)
      if (const int32_t i = merged.at(r, c); i >= 0) places[i] = {r, c};
  return places;
}

/// Gives the surface its points' blocks and the texels its triangles need.
void attachTexels(ScanSurface& s, const RangeGrid& merged, int k, const TexelImage& texels,
                  const std::vector<int32_t>& sources) {
  const std::vector<std::array<int32_t, 2>> places = blockPlaces(merged);
  s.texelSide = k;
  s.blocks.reserve(sources.size());
  for (int32_t i : sources) s.blocks.push_back(places[i]);
  s.texels = triangleTexels(texels, s.blocks, s.triangles, k);
}

/// The grid triangulated by `rules`, with filtered normals and flat blocks joined within
/// `flatTolerance`, placed by `pose`; with `texels` (the grid's colours, cells merged k x k),
/// the surface keeps them, so that merged and joined triangles show the grid's own texture.
ScanSurface surfaceOf(const RangeGrid& grid, const GridTriangulation& rules, const Pose& pose,
                      const SurfaceOptions& options, int k = 1,
                      const TexelImage* texels = nullptr) {
  GridSurface s;
  const bool joins = options.flatTolerance > 0;
  const bool textured = texels && !texels->empty();
  // Both read which grid point each vertex came from; nothing else does.
  s.mesh = triangulateGrid(grid, rules, nullptr, joins || textured ? &s.sources : nullptr);
  s.normals = filteredVertexNormals(s.mesh, options.normalPasses);
  if (joins) joinFlatBlocks(grid, rules, options.flatTolerance, s);
  ScanSurface out = orientedSurface(std::move(s.mesh), s.normals, grid.sensor(), pose);
  out.colourKind = grid.colourKind;
  if (textured) attachTexels(out, grid, k, *texels, s.sources);
  return out;
}

}  // namespace

ScanSurface buildScanSurface(const RangeGrid& grid, const Pose& pose, const SurfaceOptions& options,
                             const RangeNoise* measured) {
  // Merging needs the lateral step, triangulation the grid's: one pass gives both.
  const auto [lateral, fineStep] = options.mergeTarget > 0
                                       ? lateralAndGridSpacing(grid)
                                       : std::array<double, 2>{0, gridSpacing(grid)};
  const int k = options.mergeTarget > 0
                    ? mergeFactor(lateral, options.mergeTarget, std::min(grid.cols, grid.rows))
                    : 1;
  // Noise is measured on the grid as read; a merged cell keeps 1 / k of it.
  const RangeNoise noise = measured                   ? *measured
                           : options.smoothTarget > 0 ? RangeNoise::measure(grid)
                                                      : RangeNoise{};
  DepthSmoothing smoothing{options.smoothTarget, 0, 1.0 / k};
  if (k > 1) {
    TexelImage texels;
    const RangeGrid coarse = mergeCells(grid, k, fineStep, options.maxEdgeFactor, &texels);
    const GridTriangulation rules = gridTriangulation(
        coarse, options, mergedEdgeLimit(gridSpacing(coarse), fineStep, k, options.maxEdgeFactor));
    smoothing.edge = rules.maxEdge;
    return surfaceOf(smoothDepths(coarse, noise, smoothing), rules, pose, options, k, &texels);
  }
  // The rules come from the grid as read: smoothing shortens its median step.
  const GridTriangulation rules =
      gridTriangulation(grid, options, options.maxEdgeFactor * fineStep);
  smoothing.edge = rules.maxEdge;
  // Joined blocks span two cells: their feet take the cells' own colours, not a blend.
  const TexelImage texels = options.flatTolerance > 0 ? cellTexels(grid) : TexelImage{};
  return surfaceOf(smoothDepths(grid, noise, smoothing), rules, pose, options, 1, &texels);
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
