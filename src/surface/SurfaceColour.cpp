#include <cmath>
#include <cstdlib>

#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {
namespace {

/// Floor division: the block of an original cell (cells of a block at negative places too).
int blockOf(long cell, int k) {
  return static_cast<int>(cell >= 0 ? cell / k : -((-cell + k - 1) / k));
}

/// The texel of triangle t's original cell nearest the barycentric point, or null where it
/// has none (the triangle crosses a station's 0/360 seam, or the cell held no sample).
const Texel* nearestTexel(const ScanSurface& s, const Triangle& t, const Eigen::Vector3d& bary) {
  const int k = s.texelSide;
  double row = 0, col = 0;
  for (int i = 0; i < 3; ++i) {
    const auto& b = s.blocks[t[i]];
    // A block's centre is its original cells' centre: k b + (k - 1) / 2.
    row += bary[i] * (k * b[0] + 0.5 * (k - 1));
    col += bary[i] * (k * b[1] + 0.5 * (k - 1));
    for (int j = 0; j < i; ++j)
      if (std::abs(b[1] - s.blocks[t[j]][1]) > 1) return nullptr;  // across the seam
  }
  const long r = std::lround(row), c = std::lround(col);
  const std::array<int32_t, 2> block{blockOf(r, k), blockOf(c, k)};
  for (int i = 0; i < 3; ++i) {
    if (s.blocks[t[i]] != block) continue;
    const size_t at =
        size_t(t[i]) * k * k + size_t(r - long(k) * block[0]) * k + size_t(c - long(k) * block[1]);
    return s.texels[at][3] != 0 ? &s.texels[at] : nullptr;
  }
  return nullptr;  // rounding reached a block the triangle does not touch
}

}  // namespace

void dropColour(ScanSurface& s) {
  s.colours = {};
  s.texels = {};
  s.blocks = {};
  s.texelSide = 1;
}

Colour surfaceColour(const ScanSurface& s, const Triangle& t, const Eigen::Vector3d& bary) {
  if (!s.texels.empty())
    if (const Texel* texel = nearestTexel(s, t, bary)) return colourOf(*texel);
  const auto& c = s.colours;
  return static_cast<float>(bary[0]) * c[t[0]] + static_cast<float>(bary[1]) * c[t[1]] +
         static_cast<float>(bary[2]) * c[t[2]];
}

}  // namespace rangefuse
