#include "rangefuse/surface/ColumnBands.h"

#include <algorithm>
#include <vector>

#include "GridShape.h"
#include "GridSteps.h"
#include "rangefuse/surface/GridMerging.h"

namespace rangefuse {
namespace {

int blockCount(const BandRules& rules) {
  return (rules.cols + rules.k - 1) / rules.k;
}

/// Merged columns [from, to) of the grid: their cells read, then merged in blocks of k.
RangeGrid blockColumns(const ColumnReader& read, const BandRules& rules, double maxEdgeFactor,
                       int from, int to) {
  const int first = from * rules.k, end = std::min(rules.cols, to * rules.k);
  RangeGrid fine = read(first, end - first);
  if (rules.k == 1) return fine;
  return mergeCells(fine, rules.k, rules.step, maxEdgeFactor);
}

/// Grids of the same rows side by side, left to right; the first one's sensor kept.
RangeGrid besideEachOther(const std::vector<RangeGrid>& parts) {
  RangeGrid out = parts.front();
  out.cols = 0;
  out.points.clear();
  out.colours.clear();
  for (const RangeGrid& p : parts) out.cols += p.cols;
  out.cell.assign(static_cast<size_t>(out.cols) * out.rows, -1);
  int left = 0;
  for (const RangeGrid& p : parts) {
    const auto base = static_cast<int32_t>(out.points.size());
    out.points.insert(out.points.end(), p.points.begin(), p.points.end());
    out.colours.insert(out.colours.end(), p.colours.begin(), p.colours.end());
    for (int r = 0; r < p.rows; ++r)
      for (int c = 0; c < p.cols; ++c)
        if (const int32_t k = p.at(r, c); k >= 0)
          out.cell[static_cast<size_t>(r) * out.cols + left + c] = base + k;
    left += p.cols;
  }
  return out;
}

/// A column with no cell: it keeps the pairs of a sample from becoming neighbours.
RangeGrid emptyColumn(const RangeGrid& like) {
  RangeGrid g = like;
  g.cols = 1;
  g.points.clear();
  g.colours.clear();
  g.cell.assign(static_cast<size_t>(g.rows), -1);
  return g;
}

/// Columns of a sample: a pair of neighbours and an empty column, so that the pairs never meet.
constexpr int kSamplePeriod = 3;

/// Pairs of neighbouring merged columns at `positions` places evenly from the first pair to
/// the last, an empty column between pairs: every neighbour step it holds is one of the grid's.
RangeGrid sampledPairs(const ColumnReader& read, const BandRules& rules, double maxEdgeFactor,
                       int positions) {
  const int blocks = blockCount(rules);
  if (blocks < 3) return blockColumns(read, rules, maxEdgeFactor, 0, blocks);  // one pair
  positions = std::clamp(positions, 2, blocks - 1);
  std::vector<RangeGrid> parts;
  for (int j = 0, last = -1; j < positions; ++j) {
    const int at = static_cast<int>(int64_t{j} * (blocks - 2) / (positions - 1));
    if (at == last) continue;
    last = at;
    if (!parts.empty()) parts.push_back(emptyColumn(parts.back()));
    parts.push_back(blockColumns(read, rules, maxEdgeFactor, at, at + 2));
  }
  return besideEachOther(parts);
}

/// Merged columns [first, end) of the band with `halo` more on each side where the grid has
/// them (round the seam of a full turn); `before` gets the number of halo columns on the left.
RangeGrid bandColumns(const ColumnReader& read, const BandRules& rules, double maxEdgeFactor,
                      int first, int end, int halo, int& before) {
  const int blocks = blockCount(rules);
  const bool wraps = rules.triangulation.wraps;
  std::vector<RangeGrid> parts;
  auto add = [&](int from, int to) {
    if (from < to) parts.push_back(blockColumns(read, rules, maxEdgeFactor, from, to));
  };
  before = wraps ? halo : std::min(halo, first);
  if (first - halo < 0 && wraps) add(blocks + first - halo, blocks);
  add(std::max(0, first - halo), first);
  add(first, end);
  add(end, std::min(blocks, end + halo));
  if (end + halo > blocks && wraps) add(0, end + halo - blocks);
  return besideEachOther(parts);
}

/// The triangles of cells in columns [first, end) and the vertices they use, with their normals.
TriangleMesh ownCells(const TriangleMesh& mesh, const std::vector<int>& cellColumns,
                      const std::vector<Eigen::Vector3d>& normals, int first, int end,
                      std::vector<Eigen::Vector3d>& ownNormals) {
  TriangleMesh own;
  std::vector<int32_t> remap(mesh.vertices.size(), -1);
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    if (cellColumns[f] < first || cellColumns[f] >= end) continue;
    Triangle t = mesh.faces[f];
    for (int32_t& v : t) {
      if (remap[v] < 0) {
        remap[v] = static_cast<int32_t>(own.vertices.size());
        own.vertices.push_back(mesh.vertices[v]);
        if (!mesh.colours.empty()) own.colours.push_back(mesh.colours[v]);
        ownNormals.push_back(normals[v]);
      }
      v = remap[v];
    }
    own.faces.push_back(t);
  }
  return own;
}

}  // namespace

BandRules bandRules(const ColumnReader& read, int cols, int rows, const SurfaceOptions& options) {
  BandRules rules;
  rules.cols = cols, rules.rows = rows;
  // About as many neighbour pairs as medianNeighbourStep samples of a large grid, from at
  // most an eighth of the columns (every band reads the sample).
  const int positions =
      std::clamp<int>(internal::kMedianSample / (3 * size_t(rows)), 2, std::max(16, cols / 16));
  const RangeGrid fine = sampledPairs(read, rules, options.maxEdgeFactor, positions);
  rules.step = gridSpacing(fine, kSamplePeriod);
  if (options.mergeTarget > 0)
    rules.k =
        mergeFactor(lateralSpacing(fine, kSamplePeriod), options.mergeTarget, std::min(cols, rows));
  rules.angular = rules.k * angularSpacing(fine, kSamplePeriod);
  const RangeGrid merged = rules.k > 1 ? sampledPairs(read, rules, options.maxEdgeFactor,
                                                      std::max(16, positions / rules.k))
                                       : fine;
  // gridTriangulation's rules, read from the sample of the merged grid.
  rules.triangulation = {mergedEdgeLimit(gridSpacing(merged, kSamplePeriod), rules.step, rules.k,
                                         options.maxEdgeFactor),
                         options.minCosine, internal::facesSensor(merged),
                         internal::wrapsAround(merged, blockCount(rules))};
  return rules;
}

ScanSurface buildBandSurface(const ColumnReader& read, const BandRules& rules, int band, int bands,
                             const SurfaceOptions& options) {
  const int blocks = blockCount(rules);
  const int first = static_cast<int>(int64_t{band} * blocks / bands);
  const int end = static_cast<int>(int64_t{band + 1} * blocks / bands);
  // A core triangle reaches one column past the core, whose normals see normalPasses + 1
  // columns further; the halo never reaches round to the band itself.
  const int halo = bands == 1 ? 0 : std::min(options.normalPasses + 2, (blocks - end + first) / 2);
  int before = 0;
  const RangeGrid grid = bandColumns(read, rules, options.maxEdgeFactor, first, end, halo, before);
  GridTriangulation triangulation = rules.triangulation;
  triangulation.wraps = bands == 1 && rules.triangulation.wraps;  // else the halo closes the seam
  std::vector<int> cellColumns;
  const TriangleMesh mesh = triangulateGrid(grid, triangulation, &cellColumns);
  const std::vector<Eigen::Vector3d> normals = filteredVertexNormals(mesh, options.normalPasses);
  std::vector<Eigen::Vector3d> ownNormals;
  TriangleMesh own = ownCells(mesh, cellColumns, normals, before, before + end - first, ownNormals);
  ScanSurface surface = orientedSurface(std::move(own), ownNormals, grid.sensor(), Pose{});
  surface.colourKind = grid.colourKind;
  return surface;
}

}  // namespace rangefuse
