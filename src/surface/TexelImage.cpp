#include "rangefuse/surface/TexelImage.h"

#include <algorithm>
#include <limits>

namespace rangefuse {

TexelImage TexelImage::blank(int32_t top, int32_t left, int32_t rows, int32_t cols) {
  TexelImage t;
  t.top = top, t.left = left, t.rows = std::max(rows, 0), t.cols = std::max(cols, 0);
  t.cells.assign(size_t(t.rows) * size_t(t.cols), Texel{0, 0, 0, 0});
  return t;
}

TexelImage TexelImage::cropped(long r0, long c0, long r1, long c1) const {
  r0 = std::max<long>(r0, top), c0 = std::max<long>(c0, left);
  r1 = std::min<long>(r1, long(top) + rows), c1 = std::min<long>(c1, long(left) + cols);
  if (r1 <= r0 || c1 <= c0) return {};
  TexelImage out;
  out.top = int32_t(r0), out.left = int32_t(c0);
  out.rows = int32_t(r1 - r0), out.cols = int32_t(c1 - c0);
  out.cells.reserve(size_t(out.rows) * size_t(out.cols));
  for (long r = r0; r < r1; ++r) {
    const auto from = cells.begin() + (r - top) * long(cols) + (c0 - left);
    out.cells.insert(out.cells.end(), from, from + (c1 - c0));
  }
  return out;
}

void TexelImage::include(const TexelImage& other) {
  if (other.empty()) return;
  if (empty()) {
    *this = other;
    return;
  }
  const long r0 = std::min(top, other.top), c0 = std::min(left, other.left);
  const long r1 = std::max(long(top) + rows, long(other.top) + other.rows);
  const long c1 = std::max(long(left) + cols, long(other.left) + other.cols);
  TexelImage both = blank(int32_t(r0), int32_t(c0), int32_t(r1 - r0), int32_t(c1 - c0));
  for (const TexelImage* part : {static_cast<const TexelImage*>(this), &other})
    for (long r = part->top; r < part->top + part->rows; ++r)
      for (long c = part->left; c < part->left + part->cols; ++c)
        if (const Texel* t = part->at(r, c)) both.cell(r, c) = *t;
  *this = std::move(both);
}

TexelImage blockTexels(const TexelImage& texels, const std::vector<std::array<int32_t, 2>>& blocks,
                       int k, const std::vector<uint32_t>* used) {
  constexpr long kNone = std::numeric_limits<long>::max();
  long r0 = kNone, c0 = kNone, r1 = 0, c1 = 0;
  const auto span = [&](const std::array<int32_t, 2>& b) {
    r0 = std::min<long>(r0, b[0]), r1 = std::max<long>(r1, b[0] + 1);
    c0 = std::min<long>(c0, b[1]), c1 = std::max<long>(c1, b[1] + 1);
  };
  if (used)
    for (uint32_t i : *used) span(blocks[i]);
  else
    for (const auto& b : blocks) span(b);
  return texels.cropped(k * r0, k * c0, k * r1, k * c1);
}

}  // namespace rangefuse
