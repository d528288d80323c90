#include "rangefuse/prism/PrismField.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "rangefuse/core/Error.h"
#include "rangefuse/parallel/Threads.h"

namespace rangefuse {
namespace {

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

void addPrismWork(const PrismScan& scan, const VoxelGrid& grid, uint64_t maxVoxels, BrickWork& work,
                  int threads) {
  const size_t n = scan.surface.triangles.size(), parts = std::max(1, threads);
  std::vector<BrickWork> part(parts);
  parallelFor(parts, threads, [&](size_t k) {
    BrickWork& mine = parts == 1 ? work : part[k];
    // Neighbouring triangles (grid order) mostly touch the same bricks: added once a run.
    BrickCoord runLo, runHi, lo, hi;
    uint64_t run = 0;
    for (size_t t = n * k / parts; t < n * (k + 1) / parts; ++t) {
      if (!bricksOfBox(grid, prismBounds(scanPrism(scan, t)), lo, hi)) continue;
      if (run > 0 && lo == runLo && hi == runHi) {
        ++run;
        continue;
      }
      if (run > 0) addBrickWork(grid, runLo, runHi, run, maxVoxels, mine);
      runLo = lo, runHi = hi, run = 1;
    }
    if (run > 0) addBrickWork(grid, runLo, runHi, run, maxVoxels, mine);
  });
  if (parts > 1)
    for (const BrickWork& p : part) addWork(p, grid, maxVoxels, work);
}

BrickLayout planBricks(const std::vector<PrismScan>& scans, const VoxelGrid& grid, int ranks,
                       uint64_t maxVoxels) {
  BrickWork work;
  for (const auto& s : scans) addPrismWork(s, grid, maxVoxels, work);
  return layoutFromWork(work, grid, ranks);
}

namespace {

/// The voxel layers along z of triangle t's prism: those of voxelRange(prismBounds(prism)),
/// with the same arithmetic, from its six corners' z alone (empty if zLo > zHi).
void prismLayers(const PrismScan& scan, size_t t, const VoxelGrid& grid, int& zLo, int& zHi) {
  const ScanSurface& s = scan.surface;
  const Triangle& tri = s.triangles[t];
  const double dMin = scan.limits[t][0], dMax = scan.limits[t][1];
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < 3; ++i) {
    const double z = s.points[tri[i]].z(), n = s.normals[tri[i]].z();
    const double a = z + dMin * n, b = z + dMax * n;
    lo = std::min(lo, std::min(a, b));
    hi = std::max(hi, std::max(a, b));
  }
  zLo = ceilToInt((lo - grid.origin.z()) / grid.voxel);
  zHi = floorToInt((hi - grid.origin.z()) / grid.voxel);
}

}  // namespace

PrismIntegrator::PrismIntegrator(BrickStore& store, int threads)
    : PrismIntegrator(store, threads, nullptr) {}

PrismIntegrator::PrismIntegrator(BrickStore& store, int threads, SurfaceHypotheses* hypotheses)
    : store_(store),
      hypotheses_(hypotheses),
      latest_(store.sums().size(), 0),
      slabs_(std::max(1, threads)) {
  measureStore();
}

void PrismIntegrator::storeGrew() {
  latest_.resize(store_.sums().size(), 0);
  measureStore();
}

uint64_t PrismIntegrator::bytes() const {
  uint64_t b = sizeof(uint32_t) * latest_.capacity();
  for (const Slab& s : slabs_)
    b += sizeof(Sample) * s.samples.capacity() + sizeof(Colour) * s.colours.capacity();
  return b;
}

void PrismIntegrator::measureStore() {
  // Voxel offsets and positions in a slab's list (at most the rank's voxels) take 32 bits.
  if (store_.sums().size() > std::numeric_limits<uint32_t>::max())
    throw InputError("a field of " + std::to_string(store_.sums().size()) +
                     " voxels on one rank: more than 2^32 (use more ranks)");
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (size_t b = 0; b < store_.brickCount(); ++b) {
    const int z = mortonDecode(store_.code(b)).z();
    lo = std::min(lo, z), hi = std::max(hi, z);
  }
  if (lo <= hi) zFirst_ = lo * store_.grid().brick, zLayers_ = (hi - lo + 1) * store_.grid().brick;
}

PrismIntegrator::Sample* PrismIntegrator::sampleOf(Slab& slab, size_t at) const {
  const uint32_t i = latest_[at];
  return i < slab.samples.size() && slab.samples[i].at == at ? &slab.samples[i] : nullptr;
}

bool PrismIntegrator::touchesOwnedBrick(const BrickCoord& lo, const BrickCoord& hi) const {
  BrickCoord b;
  for (b.z() = lo.z(); b.z() <= hi.z(); ++b.z())
    for (b.y() = lo.y(); b.y() <= hi.y(); ++b.y())
      for (b.x() = lo.x(); b.x() <= hi.x(); ++b.x())
        if (store_.localBrick(mortonEncode(b)) >= 0) return true;
  return false;
}

/// Rasterizes the scan's prisms within the slab; returns the prisms counted here (those that
/// reach a local brick and whose lowest layer is in the slab).
uint64_t PrismIntegrator::rasterizeSlab(const PrismScan& scan, Slab& slab) {
  const VoxelGrid& grid = store_.grid();
  BrickCoord lastBrick(-1, -1, -1);
  int64_t lastLocal = -1;
  Prism prism;
  // A voxel's sample is fetched while the batch it joins is solved (it is rarely cached: an
  // image's voxels are spread over the whole field); voxels of other ranks' bricks are skipped.
  auto slotOf = [&](const VoxelIndex& v) -> int64_t {
    const BrickCoord b = brickOf(v, grid.brick);
    if (b != lastBrick) {
      lastBrick = b;
      lastLocal = store_.localBrick(mortonEncode(b));
    }
    if (lastLocal < 0) return -1;
    const size_t at = store_.offset(lastLocal, lastBrick, v);
    __builtin_prefetch(&latest_[at]);
    return static_cast<int64_t>(at);
  };
  // The store takes colour only from coloured scans (a job is coloured throughout or not at all).
  const bool coloured = store_.hasColour() && !scan.surface.colours.empty();
  ColourTriangle footColours;  // the current triangle, prepared for its feet
  auto visit = [&](const VoxelIndex&, int64_t at, const PrismFoot& foot) {
    Sample* s = sampleOf(slab, static_cast<size_t>(at));
    // Ties keep the earlier triangle, so the result does not depend on the rank count.
    if (s && !(std::abs(foot.d) < std::abs(s->d))) return;
    if (!s) {
      latest_[at] = static_cast<uint32_t>(slab.samples.size());
      s = &slab.samples.emplace_back();
      if (coloured) slab.colours.emplace_back();
    }
    if (coloured)  // the colour at the foot, where the gradient is interpolated
      slab.colours[static_cast<size_t>(s - slab.samples.data())] =
          surfaceColour(footColours, foot.bary);
    const Eigen::Vector3d g = footGradient(prism, foot.bary);
    *s = Sample{static_cast<uint32_t>(at),
                static_cast<float>(foot.d),
                static_cast<float>(footWeight(prism, foot.bary)),
                {static_cast<float>(g.x()), static_cast<float>(g.y()), static_cast<float>(g.z())}};
  };
  // Neighbouring triangles (grid order) mostly reach the same bricks: the answer is known.
  BrickCoord reachLo(1, 1, 1), reachHi(0, 0, 0);
  bool reachLocal = false;
  uint64_t counted = 0;
  for (size_t t = 0; t < scan.surface.triangles.size(); ++t) {
    int zLo, zHi;
    prismLayers(scan, t, grid, zLo, zHi);
    if (zLo > slab.zHi || zHi < slab.zLo || zLo > zHi) continue;
    prism = scanPrism(scan, t);
    internal::PrismRows rows(prism, grid);
    if (rows.empty()) continue;
    const BrickCoord bLo = brickOf(rows.lo, grid.brick), bHi = brickOf(rows.hi, grid.brick);
    if (bLo != reachLo || bHi != reachHi)
      reachLocal = touchesOwnedBrick(bLo, bHi), reachLo = bLo, reachHi = bHi;
    if (!reachLocal) continue;
    if (zLo >= slab.zLo) ++counted;
    rows.lo.z() = std::max(rows.lo.z(), slab.zLo);
    rows.hi.z() = std::min(rows.hi.z(), slab.zHi);
    if (coloured) footColours = colourTriangle(scan.surface, scan.surface.triangles[t]);
    internal::rasterizeRows(prism, grid, rows, slotOf, visit);
  }
  return counted;
}

void PrismIntegrator::accumulate(Slab& slab) {
  auto& sums = store_.sums();
  const std::vector<Sample>& samples = slab.samples;
  const size_t n = samples.size(), ahead = 16;  // the sums are spread over the rank's field
  for (size_t i = 0; i < n; ++i) {
    const Sample& s = samples[i];
    if (hypotheses_) {
      hypotheses_->add(s.at, s.d, s.w, s.f, slab.colours.empty() ? nullptr : &slab.colours[i]);
      continue;
    }
    if (i + ahead < n) __builtin_prefetch(&sums[samples[i + ahead].at]);
    // The colour's mean takes the weight the sums held before this sample.
    if (!slab.colours.empty()) store_.colours()[s.at].add(slab.colours[i], s.w, sums[s.at].w);
    sums[s.at].add(s.d, s.w, s.f);
  }
}

void PrismIntegrator::cutSlabs(const std::vector<Image>& images) {
  const size_t threads = slabs_.size();
  slabs_.back().zLo = std::numeric_limits<int>::min();
  slabs_.back().zHi = std::numeric_limits<int>::max();
  if (threads == 1) return;
  // The images see parts of the object: cut at the quantiles of their points' layers (a
  // prism's work follows its vertices', and points are read in order where triangles would
  // gather them), counted per layer of the rank's bricks (beyond them: at the nearer end).
  const VoxelGrid& grid = store_.grid();
  std::vector<uint64_t> counts(zLayers_ + 1, 0);
  uint64_t total = 0;
  for (const Image& image : images)
    for (const PrismScan* part : image)
      for (const Eigen::Vector3d& p : part->surface.points) {
        const double z = grid.coord(p, 2) - zFirst_;
        ++counts[z >= 0 ? (z < zLayers_ ? static_cast<int>(z) : zLayers_) : 0];
        ++total;
      }
  // Slab k ends before the layer where the count first passes k+1 shares; an empty slab is
  // one whose cut repeats the last (no points there).
  int from = std::numeric_limits<int>::min(), z = 0;
  uint64_t below = 0;
  for (size_t k = 0; k + 1 < threads; ++k) {
    const uint64_t share = total * (k + 1) / threads;
    while (z <= zLayers_ && below + counts[z] <= share) below += counts[z++];
    const int cut = std::max(from, zFirst_ + z);
    if (total > 0 && cut > from)
      slabs_[k].zLo = from, slabs_[k].zHi = cut - 1;
    else
      slabs_[k].zLo = 0, slabs_[k].zHi = -1;
    if (total > 0) from = cut;
  }
  slabs_.back().zLo = from;
}

IntegrationStats PrismIntegrator::integrateSlab(const std::vector<Image>& images, Slab& slab) {
  IntegrationStats stats;
  for (const Image& image : images) {
    for (const PrismScan* part : image) stats.prisms += rasterizeSlab(*part, slab);
    accumulate(slab);
    stats.voxelUpdates += slab.samples.size();
    slab.samples.clear();
    slab.colours.clear();
  }
  return stats;
}

IntegrationStats PrismIntegrator::addScan(const PrismScan& scan) {
  return addImages({{&scan}});
}

IntegrationStats PrismIntegrator::addImage(const Image& parts) {
  return addImages({parts});
}

IntegrationStats PrismIntegrator::addImages(const std::vector<Image>& images) {
  const size_t threads = slabs_.size();
  cutSlabs(images);
  std::vector<IntegrationStats> part(threads);
  // Slabs own disjoint voxels (of latest_ and of the sums): no two threads write the same one.
  parallelFor(threads, static_cast<int>(threads),
              [&](size_t k) { part[k] = integrateSlab(images, slabs_[k]); });
  IntegrationStats stats;
  for (const IntegrationStats& p : part) {
    stats.prisms += p.prisms;
    stats.voxelUpdates += p.voxelUpdates;
  }
  return stats;
}

}  // namespace rangefuse
