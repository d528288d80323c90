#include <cmath>
#include <cstdlib>

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
  const int k = s.texelSide;
  for (int i = 0; c.texels && i < 3; ++i) {
    const auto& b = s.blocks[t[i]];
    c.top[i] = long(k) * b[0], c.left[i] = long(k) * b[1];
    // A block's centre is its original cells' centre.
    c.row[i] = c.top[i] + 0.5 * (k - 1), c.col[i] = c.left[i] + 0.5 * (k - 1);
    for (int j = 0; j < i; ++j)  // across a station's 0/360 seam the places do not interpolate
      if (std::abs(b[1] - s.blocks[t[j]][1]) > 1) c.texels = false;
  }
  return c;
}

namespace {

/// The texel of the original cell nearest the barycentric point, or null where it has none
/// (the cell held no sample, or rounding reached a block the triangle does not touch).
const Texel* nearestTexel(const ColourTriangle& c, const Eigen::Vector3d& bary) {
  const double row = bary[0] * c.row[0] + bary[1] * c.row[1] + bary[2] * c.row[2];
  const double col = bary[0] * c.col[0] + bary[1] * c.col[1] + bary[2] * c.col[2];
  // floor, not lround: this runs once a voxel sample, and lround is a library call.
  const long r = static_cast<long>(std::floor(row + 0.5));
  const long q = static_cast<long>(std::floor(col + 0.5));
  const ScanSurface& s = *c.surface;
  const long k = s.texelSide;
  for (int i = 0; i < 3; ++i) {
    const long dr = r - c.top[i], dc = q - c.left[i];
    if (dr < 0 || dr >= k || dc < 0 || dc >= k) continue;
    const Texel& texel = s.texels[size_t(c.corners[i]) * size_t(k * k) + size_t(dr * k + dc)];
    return texel[3] != 0 ? &texel : nullptr;
  }
  return nullptr;
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
