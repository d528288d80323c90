#include "rangefuse/prism/PrismField.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

constexpr float kEmpty = INFINITY;
constexpr int kMaxVoxelsPerAxis = 1 << 20;  // vertex keys pack 20 bits per axis

void brickRange(const VoxelGrid& grid, const Eigen::AlignedBox3d& box, BrickCoord& lo,
                BrickCoord& hi, bool& empty) {
  VoxelIndex vlo, vhi;
  grid.voxelRange(box, vlo, vhi);
  empty = (vlo.array() > vhi.array()).any();
  lo = brickOf(vlo, grid.brick);
  hi = brickOf(vhi, grid.brick);
}

Eigen::AlignedBox3d pointBounds(const std::vector<PrismScan>& scans) {
  Eigen::AlignedBox3d box;
  for (const auto& s : scans)
    for (const auto& p : s.surface.points) box.extend(p);
  return box;
}

/// Voxels along the longest axis from the grid origin to the far side of `box`.
double extentVoxels(const VoxelGrid& g, const Eigen::AlignedBox3d& box, double eps) {
  return ((box.max() - g.origin).array() + eps).maxCoeff() / g.voxel + 2 * g.brick;
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

VoxelGrid fitGrid(const std::vector<PrismScan>& scans, double voxel, int brick, double eps,
                  int margin) {
  const Eigen::AlignedBox3d box = pointBounds(scans);
  if (box.isEmpty()) throw InputError("no triangles in any scan: nothing to fuse");
  VoxelGrid g;
  g.voxel = voxel;
  g.brick = brick;
  const double step = voxel * brick;
  for (int a = 0; a < 3; ++a)
    g.origin[a] = (std::floor((box.min()[a] - eps) / step) - margin) * step;
  const double extent = extentVoxels(g, box, eps) + (margin - 1) * brick;
  if (extent >= kMaxVoxelsPerAxis)
    throw InputError("--voxel " + std::to_string(voxel) + " needs " +
                     std::to_string(static_cast<long long>(extent)) +
                     " voxels along one axis (limit " + std::to_string(kMaxVoxelsPerAxis) +
                     "): use a larger voxel");
  return g;
}

bool gridHolds(const VoxelGrid& grid, const std::vector<PrismScan>& scans, double eps) {
  const Eigen::AlignedBox3d box = pointBounds(scans);
  if (box.isEmpty()) return true;
  const double step = grid.voxel * grid.brick;
  const bool above = ((box.min() - grid.origin).array() - eps >= step).all();
  return above && extentVoxels(grid, box, eps) < kMaxVoxelsPerAxis;
}

void dilateBricks(BrickLayout& layout, int ranks, uint64_t maxVoxels) {
  std::vector<uint64_t> codes;
  codes.reserve(layout.codes.size() * 27);
  for (uint64_t c : layout.codes) {
    const BrickCoord b = mortonDecode(c);
    BrickCoord d;
    for (d.z() = -1; d.z() <= 1; ++d.z())
      for (d.y() = -1; d.y() <= 1; ++d.y())
        for (d.x() = -1; d.x() <= 1; ++d.x())
          if (((b + d).array() >= 0).all()) codes.push_back(mortonEncode(b + d));
  }
  std::sort(codes.begin(), codes.end());
  codes.erase(std::unique(codes.begin(), codes.end()), codes.end());
  checkLimit("--voxel " + formatNumber(layout.grid.voxel),
             "voxels near the surface, registration room included:",
             static_cast<double>(codes.size()) * std::pow(layout.grid.brick, 3), maxVoxels,
             "max-voxels");
  std::vector<uint64_t> work(codes.size(), 0);
  for (size_t i = 0; i < codes.size(); ++i) {
    const int64_t at = layout.find(codes[i]);
    if (at >= 0) work[i] = layout.work[at];
  }
  layout.codes = std::move(codes);
  layout.work = std::move(work);
  layout.rankStart = partitionWork(layout.work, ranks);
}

BrickLayout planBricks(const std::vector<PrismScan>& scans, const VoxelGrid& grid, int ranks,
                       uint64_t maxVoxels) {
  const double perBrick = std::pow(grid.brick, 3);
  std::unordered_map<uint64_t, uint64_t> work;
  for (const auto& s : scans)
    for (size_t t = 0; t < s.surface.triangles.size(); ++t) {
      BrickCoord lo, hi, b;
      bool empty;
      brickRange(grid, prismBounds(scanPrism(s, t)), lo, hi, empty);
      if (empty) continue;
      // One huge prism or many small ones: either way refused before the map or store grows.
      const double voxels = (static_cast<double>(work.size()) +
                             (hi - lo + BrickCoord::Ones()).cast<double>().prod()) *
                            perBrick;
      if (voxels > static_cast<double>(maxVoxels))
        checkLimit("--voxel " + formatNumber(grid.voxel),
                   "voxels needed near the surface (estimate):", voxels, maxVoxels, "max-voxels");
      for (b.z() = lo.z(); b.z() <= hi.z(); ++b.z())
        for (b.y() = lo.y(); b.y() <= hi.y(); ++b.y())
          for (b.x() = lo.x(); b.x() <= hi.x(); ++b.x()) ++work[mortonEncode(b)];
    }
  BrickLayout layout;
  layout.grid = grid;
  for (const auto& kv : work) layout.codes.push_back(kv.first);
  std::sort(layout.codes.begin(), layout.codes.end());
  for (uint64_t c : layout.codes) layout.work.push_back(work[c]);
  layout.rankStart = partitionWork(layout.work, ranks);
  return layout;
}

PrismIntegrator::PrismIntegrator(BrickStore& store)
    : store_(store), scratch_(store.sums().size(), Sample{kEmpty, 0, {0, 0, 0}}) {}

bool PrismIntegrator::touchesOwnedBrick(const Eigen::AlignedBox3d& box) const {
  BrickCoord lo, hi, b;
  bool empty;
  brickRange(store_.grid(), box, lo, hi, empty);
  if (empty) return false;
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
