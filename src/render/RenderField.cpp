#include <algorithm>
#include <cmath>

#include "rangefuse/render/Render.h"

namespace rangefuse {
namespace {

/// Where the ray leaves the lattice cell block of brick b (cells whose low corner is in b).
double brickExit(const SparseField& f, const BrickCoord& b, const Eigen::Vector3d& o,
                 const Eigen::Vector3d& d) {
  const VoxelGrid& g = f.grid();
  double exit = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) continue;
    const double lo = g.origin[a] + g.voxel * b[a] * g.brick;
    const double hi = lo + g.voxel * g.brick;
    exit = std::min(exit, ((d[a] > 0 ? hi : lo) - o[a]) / d[a]);
  }
  return exit;
}

/// First outside-to-inside crossing along o + t d, t in [0, tMax], whose later sample lies in
/// a brick `counts` accepts; NaN when none. Samples sit at multiples of half a voxel whatever
/// bricks were skipped, so that a rank holding part of the field samples its bricks at the
/// same points as a rank holding all of it.
double firstCrossing(const SparseField& f, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                     double tMax, const BrickFilter& counts) {
  const double step = 0.5 * f.grid().voxel;
  bool havePrev = false;
  double prev = 0;
  for (int64_t k = 0; k * step <= tMax; ++k) {
    const double t = k * step;
    const Eigen::Vector3d p = o + t * d;
    VoxelIndex cell;
    for (int a = 0; a < 3; ++a) cell[a] = static_cast<int>(std::floor(f.grid().coord(p, a)));
    const BrickCoord b = brickOf(cell, f.grid().brick);
    if ((cell.array() < 0).any() || !f.hasBrick(b)) {
      havePrev = false;
      k = std::max(k, static_cast<int64_t>(std::ceil(brickExit(f, b, o, d) / step)) - 1);
      continue;
    }
    double cur;
    if (!f.distance(p, cur)) {
      havePrev = false;
      continue;
    }
    if (havePrev && prev > 0 && cur <= 0 && (!counts || counts(b)))
      return t - step + step * prev / (prev - cur);
    prev = cur;
    havePrev = true;
  }
  return NAN;
}

/// The hit at depth t along o + t d, shaded by the gradient facing back along the ray: the
/// field's colour there when it has one, else a warm grey.
PixelHit shadedHit(const SparseField& field, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                   double t) {
  const Eigen::Vector3d p = o + t * d, n = field.gradient(p);
  const float shade = static_cast<float>(0.15 + 0.85 * std::max(0.0, -n.dot(d)));
  const Colour base = field.colour(p).value_or(Colour(235, 225, 205) / 255);
  const Colour c = shade * base;
  return PixelHit{t, {colourByte(c[0]), colourByte(c[1]), colourByte(c[2])}};
}

/// One ray per pixel through a pinhole camera (the tracker's current view).
std::vector<PixelHit> castFromCamera(const SparseField& field, const ViewSettings& view,
                                     const BrickFilter& counts) {
  std::vector<PixelHit> hits(static_cast<size_t>(view.width) * view.height);
  const Pose& cam = *view.camera;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const Eigen::Vector3d d =
          cam.R * Eigen::Vector3d((x + 0.5 - 0.5 * view.width) / view.focal,
                                  (y + 0.5 - 0.5 * view.height) / view.focal, 1)
                      .normalized();
      const double t = firstCrossing(field, cam.t, d, view.farthest, counts);
      if (!std::isnan(t))
        hits[static_cast<size_t>(y) * view.width + x] = shadedHit(field, cam.t, d, t);
    }
  return hits;
}

}  // namespace

std::vector<PixelHit> castRays(const SparseField& field, const Eigen::AlignedBox3d& extent,
                               const ViewSettings& view, const BrickFilter& counts) {
  std::vector<PixelHit> hits(static_cast<size_t>(view.width) * view.height);
  if (view.camera) return castFromCamera(field, view, counts);
  if (extent.isEmpty()) return hits;
  const ViewFrame frame(view, extent);
  // Rays start two voxels in front of the surface and end two voxels behind it.
  const double ahead = 2 * field.grid().voxel;
  const Eigen::Vector3d d = -frame.axes.row(2).transpose();
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const Eigen::Vector3d o = frame.rayOrigin(x + 0.5, y + 0.5, ahead);
      const double t = firstCrossing(field, o, d, extent.sizes().z() + 2 * ahead, counts);
      if (!std::isnan(t)) hits[static_cast<size_t>(y) * view.width + x] = shadedHit(field, o, d, t);
    }
  return hits;
}

Eigen::AlignedBox3d surfaceExtent(const SparseField& field, const Eigen::Matrix3d& axes) {
  Eigen::AlignedBox3d box;
  const double near = field.grid().voxel;
  field.forEachVoxel([&](const Eigen::Vector3d& centre, const VoxelSums& s) {
    if (std::abs(s.wd / s.w) <= near) box.extend(axes * centre);
  });
  return box;
}

Image renderField(const SparseField& field, const ViewSettings& view) {
  const std::vector<PixelHit> hits =
      castRays(field, surfaceExtent(field, viewAxes(view)), view, nullptr);
  Image img(view.width, view.height, 0);
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const PixelHit& h = hits[static_cast<size_t>(y) * view.width + x];
      const std::array<uint8_t, 3>& c = std::isnan(h.t) ? kBackground : h.rgb;
      img.set(x, y, c[0], c[1], c[2]);
    }
  return img;
}

}  // namespace rangefuse
