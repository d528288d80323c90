#include "rangefuse/surface/TexelImage.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace rangefuse {
namespace {

/// Rows from `top` on holding columns [lo[r], hi[r]) each (none where hi <= lo), no texel
/// sampled yet.
TexelImage spanned(int32_t top, const std::vector<long>& lo, const std::vector<long>& hi) {
  TexelImage t;
  t.top = top;
  t.left.reserve(lo.size());
  t.from.reserve(lo.size() + 1);
  t.from.push_back(0);
  for (size_t r = 0; r < lo.size(); ++r) {
    const long width = std::max(0L, hi[r] - lo[r]);
    t.left.push_back(int32_t(width ? lo[r] : 0));
    t.from.push_back(t.from.back() + uint32_t(width));
  }
  t.cells.assign(t.from.back(), Texel{0, 0, 0, 0});
  return t;
}

/// Copies the cells `from` holds in row `row` into `to`, where `to` holds them too.
void copyRow(const TexelImage& from, long row, TexelImage& to) {
  const size_t a = size_t(row - from.top), b = size_t(row - to.top);
  const long c0 = std::max<long>(from.left[a], to.left[b]);
  const long c1 = std::min<long>(from.left[a] + long(from.from[a + 1] - from.from[a]),
                                 to.left[b] + long(to.from[b + 1] - to.from[b]));
  if (c1 <= c0) return;
  std::memcpy(&to.cells[to.from[b] + size_t(c0 - to.left[b])],
              &from.cells[from.from[a] + size_t(c0 - from.left[a])],
              size_t(c1 - c0) * sizeof(Texel));
}

/// Copies every row of `from` that `to` holds.
void copyRows(const TexelImage& from, TexelImage& to) {
  const long r0 = std::max<long>(from.top, to.top);
  const long r1 = std::min(from.top + from.rows(), to.top + to.rows());
  for (long r = r0; r < r1; ++r) copyRow(from, r, to);
}

}  // namespace

TexelImage TexelImage::blank(int32_t top, int32_t left, int32_t rows, int32_t cols) {
  const size_t n = size_t(std::max(rows, 0));
  return spanned(top, std::vector<long>(n, left), std::vector<long>(n, long(left) + cols));
}

void TexelImage::include(const TexelImage& other) {
  if (other.empty()) return;
  if (empty()) {
    *this = other;
    return;
  }
  const long r0 = std::min(top, other.top);
  const long r1 = std::max(top + rows(), other.top + other.rows());
  std::vector<long> lo(size_t(r1 - r0), std::numeric_limits<long>::max()), hi(lo.size(), 0);
  for (const TexelImage* part : {static_cast<const TexelImage*>(this), &other})
    for (long r = 0; r < part->rows(); ++r) {
      const long width = long(part->from[size_t(r) + 1] - part->from[size_t(r)]);
      if (width == 0) continue;
      const size_t at = size_t(part->top + r - r0);
      lo[at] = std::min<long>(lo[at], part->left[size_t(r)]);
      hi[at] = std::max<long>(hi[at], part->left[size_t(r)] + width);
    }
  TexelImage both = spanned(int32_t(r0), lo, hi);
  copyRows(*this, both);
  copyRows(other, both);
  *this = std::move(both);
}

TexelImage triangleTexels(const TexelImage& texels,
                          const std::vector<std::array<int32_t, 2>>& blocks,
                          const std::vector<Triangle>& triangles, int k,
                          const std::vector<uint32_t>* pick) {
  // Per row the image holds, the columns the blocks of its triangles span.
  std::vector<long> lo(size_t(texels.rows()), std::numeric_limits<long>::max()), hi(lo.size(), 0);
  const auto add = [&](uint32_t t) {
    long r0 = blocks[triangles[t][0]][0], r1 = r0, c0 = blocks[triangles[t][0]][1], c1 = c0;
    for (const int32_t v : triangles[t]) {
      r0 = std::min<long>(r0, blocks[v][0]), r1 = std::max<long>(r1, blocks[v][0]);
      c0 = std::min<long>(c0, blocks[v][1]), c1 = std::max<long>(c1, blocks[v][1]);
    }
    if (!takesTexels(k, r1 - r0, c1 - c0)) return;
    // A partial last block reaches beyond the image.
    const long first = std::max(k * r0 - texels.top, 0L);
    const long end = std::min(k * (r1 + 1) - texels.top, texels.rows());
    for (long r = first; r < end; ++r)
      lo[size_t(r)] = std::min(lo[size_t(r)], k * c0),
      hi[size_t(r)] = std::max(hi[size_t(r)], k * (c1 + 1));
  };
  if (pick)
    for (uint32_t t : *pick) add(t);
  else
    for (uint32_t t = 0; t < triangles.size(); ++t) add(t);
  // Held where the image holds them; rows without a span before the first or after the last
  // are left out.
  size_t first = lo.size(), end = 0;
  for (size_t r = 0; r < lo.size(); ++r) {
    lo[r] = std::max<long>(lo[r], texels.left[r]);
    hi[r] = std::min<long>(hi[r], texels.left[r] + long(texels.from[r + 1] - texels.from[r]));
    if (hi[r] > lo[r]) first = std::min(first, r), end = r + 1;
  }
  if (end <= first) return {};
  TexelImage out = spanned(int32_t(texels.top + long(first)),
                           std::vector<long>(lo.begin() + long(first), lo.begin() + long(end)),
                           std::vector<long>(hi.begin() + long(first), hi.begin() + long(end)));
  copyRows(texels, out);
  return out;
}

}  // namespace rangefuse
