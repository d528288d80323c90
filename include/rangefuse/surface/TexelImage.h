// A scan's colour at its grid's own resolution, kept beside a surface whose triangles are
// coarser than the grid: merged cells and joined flat blocks would otherwise blur its texture.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "rangefuse/core/Colour.h"

namespace rangefuse {

/// A rectangle of a range grid's cells, one texel each, row-major; alpha 0 where a cell holds no
/// sample of its block's surface. Places are the original grid's (row, column).
struct TexelImage {
  int32_t top = 0, left = 0;   ///< the first cell held
  int32_t rows = 0, cols = 0;  ///< how many
  std::vector<Texel> cells;    ///< rows x cols

  /// A rectangle of `rows` x `cols` cells from (top, left), every texel without a sample.
  static TexelImage blank(int32_t top, int32_t left, int32_t rows, int32_t cols);

  bool empty() const { return cells.empty(); }

  /// The texel of cell (row, col), or null outside the rectangle or where it has no sample.
  const Texel* at(long row, long col) const {
    const long r = row - top, c = col - left;
    if (r < 0 || r >= rows || c < 0 || c >= cols) return nullptr;
    const Texel& t = cells[size_t(r) * size_t(cols) + size_t(c)];
    return t[3] != 0 ? &t : nullptr;
  }
  Texel& cell(long row, long col) {
    return cells[size_t(row - top) * size_t(cols) + size_t(col - left)];
  }

  /// The cells of rows [r0, r1) and columns [c0, c1), clipped to this rectangle.
  TexelImage cropped(long r0, long c0, long r1, long c1) const;

  /// Adds the sampled cells of `other`, a part of the same scan, growing the rectangle to hold
  /// both (where they overlap both hold the same texels).
  void include(const TexelImage& other);

  bool operator==(const TexelImage& o) const {
    return top == o.top && left == o.left && rows == o.rows && cols == o.cols && cells == o.cells;
  }
};

/// The cells of the k x k blocks spanned by `blocks` (each a block's row and column; with
/// `used`, only those listed), as a part of `texels` needs them.
TexelImage blockTexels(const TexelImage& texels, const std::vector<std::array<int32_t, 2>>& blocks,
                       int k, const std::vector<uint32_t>* used = nullptr);

}  // namespace rangefuse
