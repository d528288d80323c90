#include "rangefuse/prism/PrismRaster.h"

#include <algorithm>
#include <cmath>

#include "PrismRows.h"

namespace rangefuse {
namespace internal {

PrismRows::PrismRows(const Prism& prism, const VoxelGrid& grid) {
  const Eigen::AlignedBox3d box = prismBounds(prism);
  grid.voxelRange(box, lo, hi);
  Eigen::Vector3d::Index ax;
  box.sizes().maxCoeff(&ax);  // few, long rows
  along = static_cast<int>(ax), b = (along + 1) % 3, c = (along + 2) % 3;
  // Relative to p0, so that slab values are small and exact enough far from the origin.
  const Eigen::Vector3d& p0 = prism.p[0];
  std::array<Eigen::Vector3d, 6> corners;
  for (int i = 0; i < 3; ++i) {
    corners[2 * i] = prism.p[i] - p0 + prism.dMin * prism.n[i];
    corners[2 * i + 1] = prism.p[i] - p0 + prism.dMax * prism.n[i];
  }
  // Directions whose slabs fit the prism closely: the two end triangles' normals, and across
  // each side the edge crossed with its mean vertex normal (so a side tilted by its normals is
  // bounded by a tilted slab, not by the farthest corner for the whole height).
  const auto cornerAt = [&](int i, bool high) -> const Eigen::Vector3d& {
    return corners[2 * i + (high ? 1 : 0)];
  };
  Eigen::Vector3d dirs[kSlabs];
  for (int high = 0; high < 2; ++high)
    dirs[high] =
        (cornerAt(1, high) - cornerAt(0, high)).cross(cornerAt(2, high) - cornerAt(0, high));
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    dirs[2 + i] = (prism.p[j] - prism.p[i]).cross(prism.n[i] + prism.n[j]);
  }
  // The solve accepts points a hair outside (barycentric tolerance): keep them in the slabs.
  const double widen = 1e-6 * box.sizes().norm();
  const Eigen::Vector3d fromP0 = grid.origin - p0;
  for (const Eigen::Vector3d& dir : dirs) {
    if (!(dir.squaredNorm() > 0) || !dir.allFinite()) continue;  // degenerate: the box decides
    // Left unnormalised (no root): the margin scales with |m|, bounded above by its 1-norm.
    const Eigen::Vector3d& m = dir;
    const double margin = widen * m.lpNorm<1>();
    // A slab whose step along the rows has no finite inverse changes nothing along a row.
    const double perStepInv = 1 / (grid.voxel * m[along]);
    Slab& s = std::isfinite(perStepInv) ? slabs_[count_++] : flat_[flatCount_++];
    s.lo = s.hi = m.dot(corners[0]);
    for (const auto& k : corners) {
      s.lo = std::min(s.lo, m.dot(k));
      s.hi = std::max(s.hi, m.dot(k));
    }
    s.lo -= margin, s.hi += margin;
    s.atRow0 = m.dot(fromP0);
    s.perStepInv = perStepInv;
    s.perB = grid.voxel * m[b];
    s.perC = grid.voxel * m[c];
  }
}

}  // namespace internal

void rasterizePrismBruteForce(const Prism& prism, const VoxelGrid& grid,
                              const PrismVisitor& visit) {
  VoxelIndex lo, hi, v;
  grid.voxelRange(prismBounds(prism), lo, hi);
  const internal::PrismCubic cubic(prism);
  PrismHit hit;
  for (v.z() = lo.z(); v.z() <= hi.z(); ++v.z())
    for (v.y() = lo.y(); v.y() <= hi.y(); ++v.y())
      for (v.x() = lo.x(); v.x() <= hi.x(); ++v.x())
        if (internal::solvePrismDistance(prism, cubic, grid.centre(v), hit)) visit(v, hit);
}

void rasterizePrism(const Prism& prism, const VoxelGrid& grid, const PrismVisitor& visit) {
  PrismHit hit;
  internal::rasterizeRows(
      prism, grid, internal::PrismRows(prism, grid), [](const VoxelIndex&) -> int64_t { return 0; },
      [&](const VoxelIndex& v, int64_t, const PrismFoot& foot) {
        internal::completeHit(prism, foot, hit);
        visit(v, hit);
      });
}

}  // namespace rangefuse
