#include "rangefuse/prism/PrismField.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

constexpr float kEmpty = INFINITY;

Eigen::AlignedBox3d pointBounds(const std::vector<PrismScan>& scans) {
  Eigen::AlignedBox3d box;
  for (const auto& s : scans) box.extend(pointBounds(s));
  return box;
}

}  // namespace

PrismLimits computePrismLimits(const ScanSurface& s, double eps) {
  PrismLimits limits(s.triangles.size());
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const Triangle& tri = s.triangles[t];
    Prism p = makePrism({s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]},
                        {s.normals[tri[0]], s.normals[tri[1]], s.normals[tri[2]]}, {0, 0, 0}, eps);
    limits[t] = {p.dMin, p.dMax};
  }
  return limits;
}

Prism scanPrism(const PrismScan& scan, size_t t) {
  const ScanSurface& s = scan.surface;
  const Triangle& tri = s.triangles[t];
  return Prism{{s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]},
               {s.normals[tri[0]], s.normals[tri[1]], s.normals[tri[2]]},
               {s.confidence[tri[0]], s.confidence[tri[1]], s.confidence[tri[2]]},
               scan.limits[t][0],
               scan.limits[t][1]};
}

Eigen::AlignedBox3d pointBounds(const PrismScan& scan) {
  Eigen::AlignedBox3d box;
  for (const auto& p : scan.surface.points) box.extend(p);
  return box;
}

VoxelGrid fitGrid(const std::vector<PrismScan>& scans, double voxel, int brick, double eps,
                  int margin) {
  return gridAround(pointBounds(scans), voxel, brick, eps, margin);
}

bool gridHolds(const VoxelGrid& grid, const std::vector<PrismScan>& scans, double eps) {
  return gridHoldsBox(grid, pointBounds(scans), eps);
}

void addPrismWork(const PrismScan& scan, const VoxelGrid& grid, uint64_t maxVoxels,
                  BrickWork& work) {
  for (size_t t = 0; t < scan.surface.triangles.size(); ++t)
    addBoxWork(grid, prismBounds(scanPrism(scan, t)), maxVoxels, work);
}

BrickLayout planBricks(const std::vector<PrismScan>& scans, const VoxelGrid& grid, int ranks,
                       uint64_t maxVoxels) {
  BrickWork work;
  for (const auto& s : scans) addPrismWork(s, grid, maxVoxels, work);
  return layoutFromWork(work, grid, ranks);
}

PrismIntegrator::PrismIntegrator(BrickStore& store)
    : store_(store), scratch_(store.sums().size(), Sample{kEmpty, 0, {0, 0, 0}}) {}

bool PrismIntegrator::touchesOwnedBrick(const Eigen::AlignedBox3d& box) const {
  BrickCoord lo, hi, b;
  if (!bricksOfBox(store_.grid(), box, lo, hi)) return false;
  for (b.z() = lo.z(); b.z() <= hi.z(); ++b.z())
    for (b.y() = lo.y(); b.y() <= hi.y(); ++b.y())
      for (b.x() = lo.x(); b.x() <= hi.x(); ++b.x())
        if (store_.localBrick(mortonEncode(b)) >= 0) return true;
  return false;
}

IntegrationStats PrismIntegrator::addScan(const PrismScan& scan) {
  IntegrationStats stats;
  const VoxelGrid& grid = store_.grid();
  BrickCoord lastBrick(-1, -1, -1);
  int64_t lastLocal = -1;
  auto visit = [&](const VoxelIndex& v, const PrismHit& hit) {
    BrickCoord b = brickOf(v, grid.brick);
    if (b != lastBrick) {
      lastBrick = b;
      lastLocal = store_.localBrick(mortonEncode(b));
    }
    if (lastLocal < 0) return;
    Sample& s = scratch_[store_.offset(lastLocal, lastBrick, v)];
    // Ties keep the earlier triangle, so the result does not depend on the rank count.
    if (!(std::abs(hit.d) < std::abs(s.d))) return;
    if (s.d == kEmpty) touched_.push_back(store_.offset(lastLocal, lastBrick, v));
    s = Sample{static_cast<float>(hit.d),
               static_cast<float>(hit.weight),
               {static_cast<float>(hit.gradient.x()), static_cast<float>(hit.gradient.y()),
                static_cast<float>(hit.gradient.z())}};
  };
  for (size_t t = 0; t < scan.surface.triangles.size(); ++t) {
    Prism prism = scanPrism(scan, t);
    if (!touchesOwnedBrick(prismBounds(prism))) continue;
    ++stats.prisms;
    rasterizePrism(prism, grid, visit);
  }
  auto& sums = store_.sums();
  for (size_t off : touched_) {
    Sample& s = scratch_[off];
    VoxelSums& acc = sums[off];
    acc.wd += s.w * s.d;
    acc.w += s.w;
    for (int k = 0; k < 3; ++k) acc.wf[k] += s.w * s.f[k];
    acc.images += 1;
    s.d = kEmpty;
  }
  stats.voxelUpdates = touched_.size();
  touched_.clear();
  return stats;
}

}  // namespace rangefuse
