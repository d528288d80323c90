// A scan too large for one rank, prepared in bands of whole columns that ranks read and build on
// their own. What must hold for the whole grid (the merge factor, the edge limit, the winding,
// whether the columns close a turn) is decided by every band alike from the same sample of the
// grid's columns, so a band is a function of the file and its number only: any rank, any rank
// count, the same triangles. Each band reads a halo of neighbouring columns so that its normals
// are filtered as in the whole grid, then keeps the triangles of its own cells only.
#pragma once

#include <cstdint>
#include <functional>

#include "rangefuse/core/RangeGrid.h"  // and bandCount
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// Columns [first, first + count) of a grid, as a grid of their own.
using ColumnReader = std::function<RangeGrid(int first, int count)>;

/// What every band of one grid agrees on.
struct BandRules {
  int cols = 0, rows = 0;           ///< the whole grid's
  int k = 1;                        ///< cells merged into blocks of k x k (GridMerging)
  double step = 0;                  ///< grid spacing at full resolution (merging's edge test)
  double angular = 0;               ///< angular step of the merged grid (a station's sight map)
  GridTriangulation triangulation;  ///< for the merged grid (the seam, if any, closed by halos)
};

/// The rules of a cols x rows grid from a sample of pairs of neighbouring (merged) columns
/// spread over the grid, its first and last included; the same for every band.
BandRules bandRules(const ColumnReader& read, int cols, int rows, const SurfaceOptions& options);

/// Band `band` of `bands` (merged columns split evenly) as a surface in the scan frame: the
/// triangles of its cells, whose normals are filtered with normalPasses + 2 merged columns of
/// neighbours on each side (across the seam of a full turn).
ScanSurface buildBandSurface(const ColumnReader& read, const BandRules& rules, int band, int bands,
                             const SurfaceOptions& options);

}  // namespace rangefuse
