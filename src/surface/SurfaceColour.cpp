#include <algorithm>
#include <cmath>

#include "rangefuse/core/Rounding.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

void dropColour(ScanSurface& s) {
  s.colours = {};
  s.texels = {};
  s.blocks = {};
  s.texelSide = 1;
}

ColourTriangle colourTriangle(const ScanSurface& s, const Triangle& t) {
  ColourTriangle c;
  c.surface = &s;
  c.corners = t;
  c.texels = !s.texels.empty();
  if (!c.texels) return c;
  const long k = s.texelSide;
  long r0 = s.blocks[t[0]][0], r1 = r0, c0 = s.blocks[t[0]][1], c1 = c0;
  for (int i = 0; i < 3; ++i) {
    const auto& b = s.blocks[t[i]];
    // A block's centre is its original cells' centre.
    c.row[i] = k * b[0] + 0.5 * (k - 1), c.col[i] = k * b[1] + 0.5 * (k - 1);
    r0 = std::min<long>(r0, b[0]), r1 = std::max<long>(r1, b[0]);
    c0 = std::min<long>(c0, b[1]), c1 = std::max<long>(c1, b[1]);
  }
  c.texels = takesTexels(int(k), r1 - r0, c1 - c0);
  c.top = k * r0, c.bottom = k * (r1 + 1), c.left = k * c0, c.right = k * (c1 + 1);
  return c;
}

namespace {

/// The texel of the original cell nearest the barycentric point, or null where it has none
/// (the cell held no sample, or rounding reached a block beyond the triangle's corners).
const Texel* nearestTexel(const ColourTriangle& c, const Eigen::Vector3d& bary) {
  const double row = bary[0] * c.row[0] + bary[1] * c.row[1] + bary[2] * c.row[2];
  const double col = bary[0] * c.col[0] + bary[1] * c.col[1] + bary[2] * c.col[2];
  const long r = floorToInt(row + 0.5), q = floorToInt(col + 0.5);  // once a voxel sample
  if (r < c.top || r >= c.bottom || q < c.left || q >= c.right) return nullptr;
  return c.surface->texels.at(r, q);
}

}  // namespace

Colour surfaceColour(const ColourTriangle& c, const Eigen::Vector3d& bary) {
  if (c.texels)
    if (const Texel* texel = nearestTexel(c, bary)) return colourOf(*texel);
  const auto& colours = c.surface->colours;
  const Triangle& t = c.corners;
  return static_cast<float>(bary[0]) * colours[t[0]] + static_cast<float>(bary[1]) * colours[t[1]] +
         static_cast<float>(bary[2]) * colours[t[2]];
}

Colour surfaceColour(const ScanSurface& s, const Triangle& t, const Eigen::Vector3d& bary) {
  return surfaceColour(colourTriangle(s, t), bary);
}

}  // namespace rangefuse
