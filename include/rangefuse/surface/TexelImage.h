// A scan's colour at its grid's own resolution, kept beside a surface whose triangles are
// coarser than the grid: merged cells and joined flat blocks would otherwise blur its texture.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse {

/// Whether the feet of a triangle whose corners' blocks (k x k cells each) span `rows` x `cols`
/// blocks (the largest place less the least) take texels: a merged cell's, or a joined flat
/// block's (two blocks across). Cells neither merged nor joined interpolate their corners'
/// colours, and a triangle wider than two blocks closes a station's 0/360 degree seam, across
/// which block places do not interpolate.
inline bool takesTexels(int k, long rows, long cols) {
  return cols <= 2 && (k > 1 || rows > 1 || cols > 1);
}

/// Some of a range grid's cells, one texel each: from row `top` on, a span of columns a row,
/// which holds a part of a scan as tightly as its outline allows. Alpha 0 where a cell holds no
/// sample of its block's surface. Places are the original grid's (row, column).
struct TexelImage {
  int32_t top = 0;             ///< the first row held
  std::vector<int32_t> left;   ///< per row held: its first column
  std::vector<uint32_t> from;  ///< per row held, and one more: its first cell in `cells`
  std::vector<Texel> cells;

  /// A rectangle of `rows` x `cols` cells from (top, left), every texel without a sample.
  static TexelImage blank(int32_t top, int32_t left, int32_t rows, int32_t cols);

  bool empty() const { return cells.empty(); }
  long rows() const { return long(left.size()); }

  /// The texel of cell (row, col), or null where none is held or it has no sample.
  const Texel* at(long row, long col) const {
    const long r = row - top;
    if (r < 0 || r >= rows()) return nullptr;
    const long c = col - left[size_t(r)];
    if (c < 0 || c >= long(from[size_t(r) + 1] - from[size_t(r)])) return nullptr;
    const Texel& t = cells[from[size_t(r)] + size_t(c)];
    return t[3] != 0 ? &t : nullptr;
  }

  /// Cell (row, col), which the image must hold.
  Texel& cell(long row, long col) {
    const size_t r = size_t(row - top);
    return cells[from[r] + size_t(col - left[r])];
  }

  /// Adds the sampled cells of `other`, a part of the same scan, each row's span grown to hold
  /// both (where they overlap both hold the same texels).
  void include(const TexelImage& other);

  bool operator==(const TexelImage& o) const {
    return top == o.top && left == o.left && from == o.from && cells == o.cells;
  }
};

/// The cells a part of a surface needs: those of the k x k blocks between the corners of each
/// of its triangles that takes texels (`blocks` gives each point's block row and column; with
/// `pick`, only the triangles listed). Each row of blocks holds the span from its first such
/// block to its last.
TexelImage triangleTexels(const TexelImage& texels,
                          const std::vector<std::array<int32_t, 2>>& blocks,
                          const std::vector<Triangle>& triangles, int k,
                          const std::vector<uint32_t>* pick = nullptr);

}  // namespace rangefuse
