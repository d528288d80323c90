#include "rangefuse/prism/PrismField.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "PrismRows.h"
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

double expectedUpdates(const Prism& p, double voxel) {
  const double area = 0.5 * (p.p[1] - p.p[0]).cross(p.p[2] - p.p[0]).norm();
  return area * (p.dMax - p.dMin) / (voxel * voxel * voxel);
}

namespace {

/// A prism's voxel range and predicted cost (work units); false when it holds no voxel.
bool prismCost(const Prism& prism, const VoxelGrid& grid, double setupUpdates, VoxelIndex& lo,
               VoxelIndex& hi, double& units) {
  const Eigen::AlignedBox3d bounds = prismBounds(prism);
  grid.voxelRange(bounds, lo, hi);
  if ((lo.array() > hi.array()).any()) return false;
  // A prism thinner than a voxel along some axis holds a voxel centre only by chance; given
  // that it holds one (it is planned), it holds 1/chance times the mean: a dense scan's small
  // prisms would otherwise be counted short by the share of them that hold none.
  const Eigen::Array3d extent = bounds.sizes().array() / grid.voxel;
  const double chance = extent.min(1.0).prod();
  const double box = (hi - lo + VoxelIndex::Ones()).cast<double>().prod();
  const double updates = std::min(box, expectedUpdates(prism, grid.voxel) / chance);
  units = kWorkPerUpdate * (setupUpdates + updates);
  return true;
}

/// Voxels of [lo, hi] (per axis) that also lie in brick b.
double overlapVoxels(const VoxelIndex& lo, const VoxelIndex& hi, const BrickCoord& b, int brick) {
  double n = 1;
  for (int a = 0; a < 3; ++a)
    n *= std::min(hi[a], (b[a] + 1) * brick - 1) - std::max(lo[a], b[a] * brick) + 1;
  return n;
}

/// The predicted cost of a run of prisms whose boxes touch the same bricks [lo, hi], per brick
/// (x fastest): neighbouring triangles (grid order) mostly do, and the run is added to the
/// work map once.
class CostRun {
 public:
  /// Adds the cost `units` of a prism on voxels [vLo, vHi], shared among its bricks as the
  /// voxels of its box are (each share rounded on its own: the same integers whoever adds
  /// them); a prism on other bricks than the run's first adds the run to `work`.
  void add(const VoxelIndex& vLo, const VoxelIndex& vHi, double units, const VoxelGrid& grid,
           uint64_t maxVoxels, BrickWork& work) {
    const BrickCoord bLo = brickOf(vLo, grid.brick), bHi = brickOf(vHi, grid.brick);
    if (shares_.empty() || bLo != lo_ || bHi != hi_) {
      flush(grid, maxVoxels, work);
      lo_ = bLo, hi_ = bHi;
      shares_.assign((hi_ - lo_ + BrickCoord::Ones()).prod(), 0);
    }
    if (shares_.size() == 1) {
      shares_[0] += std::llround(units);
      return;
    }
    const double box = (vHi - vLo + VoxelIndex::Ones()).cast<double>().prod();
    size_t i = 0;
    BrickCoord b;
    for (b.z() = lo_.z(); b.z() <= hi_.z(); ++b.z())
      for (b.y() = lo_.y(); b.y() <= hi_.y(); ++b.y())
        for (b.x() = lo_.x(); b.x() <= hi_.x(); ++b.x())
          shares_[i++] += std::llround(units * overlapVoxels(vLo, vHi, b, grid.brick) / box);
  }

  /// Adds the run to `work` (refused as addBrickWork refuses) and empties it.
  void flush(const VoxelGrid& grid, uint64_t maxVoxels, BrickWork& work) {
    if (shares_.empty()) return;
    if (shares_.size() == 1) {
      addBrickWork(grid, lo_, hi_, shares_[0], maxVoxels, work);
    } else {
      addBrickWork(grid, lo_, hi_, 0, maxVoxels, work);  // refused here if too many bricks
      size_t i = 0;
      BrickCoord b;
      for (b.z() = lo_.z(); b.z() <= hi_.z(); ++b.z())
        for (b.y() = lo_.y(); b.y() <= hi_.y(); ++b.y())
          for (b.x() = lo_.x(); b.x() <= hi_.x(); ++b.x()) work[mortonEncode(b)] += shares_[i++];
    }
    shares_.clear();
  }

 private:
  BrickCoord lo_, hi_;
  std::vector<uint64_t> shares_;
};

}  // namespace

void addPrismCost(const Prism& prism, const VoxelGrid& grid, uint64_t maxVoxels, BrickWork& work,
                  double setupUpdates) {
  VoxelIndex lo, hi;
  double units;
  if (!prismCost(prism, grid, setupUpdates, lo, hi, units)) return;
  CostRun run;
  run.add(lo, hi, units, grid, maxVoxels, work);
  run.flush(grid, maxVoxels, work);
}

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
                  int threads, double setupUpdates) {
  const size_t n = scan.surface.triangles.size(), parts = std::max(1, threads);
  std::vector<BrickWork> part(parts);
  parallelFor(parts, threads, [&](size_t k) {
    BrickWork& mine = parts == 1 ? work : part[k];
    CostRun run;
    for (size_t t = n * k / parts; t < n * (k + 1) / parts; ++t) {
      VoxelIndex lo, hi;
      double units;
      if (prismCost(scanPrism(scan, t), grid, setupUpdates, lo, hi, units))
        run.add(lo, hi, units, grid, maxVoxels, mine);
    }
    run.flush(grid, maxVoxels, mine);
  });
  if (parts > 1)
    for (const BrickWork& p : part) addWork(p, grid, maxVoxels, work);
}

BrickLayout planBricks(const std::vector<PrismScan>& scans, const VoxelGrid& grid, int ranks,
                       uint64_t maxVoxels, double setupUpdates) {
  BrickWork work;
  for (const auto& s : scans) addPrismWork(s, grid, maxVoxels, work, 1, setupUpdates);
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

/// The noise of the distances triangle t gives, at its centre's depth.
float triangleNoise(const PrismScan& scan, size_t t) {
  const Triangle& f = scan.surface.triangles[t];
  const auto& p = scan.surface.points;
  return static_cast<float>(scan.sight->sampleNoiseAt((p[f[0]] + p[f[1]] + p[f[2]]) / 3));
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
  for (Slab& s : slabs_)
    if (!s.brickUpdates.empty()) s.brickUpdates.resize(store_.brickCount(), 0);
  measureStore();
}

uint64_t PrismIntegrator::bytes() const {
  uint64_t b = sizeof(uint32_t) * latest_.capacity();
  for (const Slab& s : slabs_)
    b += sizeof(Sample) * s.samples.capacity() + sizeof(Colour) * s.colours.capacity() +
         sizeof(float) * s.sigmas.capacity();
  return b;
}

void PrismIntegrator::countUpdatesPerBrick() {
  for (Slab& s : slabs_) s.brickUpdates.assign(store_.brickCount(), 0);
}

std::vector<uint64_t> PrismIntegrator::updatesPerBrick() const {
  std::vector<uint64_t> n(store_.brickCount(), 0);
  for (const Slab& s : slabs_)
    for (size_t b = 0; b < s.brickUpdates.size(); ++b) n[b] += s.brickUpdates[b];
  return n;
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
  // The brick size is kept in a local: read through `grid`, which the loop's stores might change
  // as far as the compiler knows, it has brickOf's power-of-two test and shift redone per voxel.
  const int brick = grid.brick;
  auto slotOf = [&](const VoxelIndex& v) -> int64_t {
    const BrickCoord b = brickOf(v, brick);
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
  float sigma = 0;             // the current triangle's depth noise (robust fusion)
  auto visit = [&](const VoxelIndex&, int64_t at, const PrismFoot& foot) {
    Sample* s = sampleOf(slab, static_cast<size_t>(at));
    // Ties keep the earlier triangle, so the result does not depend on the rank count.
    if (s && !(std::abs(foot.d) < std::abs(s->d))) return;
    if (!s) {
      latest_[at] = static_cast<uint32_t>(slab.samples.size());
      s = &slab.samples.emplace_back();
      if (coloured) slab.colours.emplace_back();
      if (hypotheses_) slab.sigmas.emplace_back();
    }
    if (hypotheses_) slab.sigmas[static_cast<size_t>(s - slab.samples.data())] = sigma;
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
    if (hypotheses_ && scan.sight) sigma = triangleNoise(scan, t);
    internal::rasterizeRows(prism, grid, rows, slotOf, visit);
  }
  return counted;
}

void PrismIntegrator::accumulate(Slab& slab) {
  auto& sums = store_.sums();
  auto& colours = store_.colours();
  const std::vector<Sample>& samples = slab.samples;
  const bool coloured = !slab.colours.empty();
  const size_t n = samples.size(), ahead = 16;  // the sums are spread over the rank's field
  for (size_t i = 0; i < n; ++i) {
    const Sample& s = samples[i];
    // The sums, and a coloured field's colour sums beside them, are read for robust fusion's
    // first hypothesis as for a plain sample.
    if (i + ahead < n) {
      __builtin_prefetch(&sums[samples[i + ahead].at]);
      if (coloured) __builtin_prefetch(&colours[samples[i + ahead].at]);
    }
    if (hypotheses_) {
      hypotheses_->add(s.at, s.d, s.w, s.f, slab.sigmas[i], coloured ? &slab.colours[i] : nullptr);
      continue;
    }
    // The colour's mean takes the weight the sums held before this sample.
    if (coloured) colours[s.at].add(slab.colours[i], s.w, sums[s.at].w);
    sums[s.at].add(s.d, s.w, s.f);
  }
}

void PrismIntegrator::countBrickUpdates(Slab& slab) const {
  const size_t per = store_.voxelsPerBrick();
  // Bricks of 8 (the default) or any power of two: a shift, not a division, a sample (a
  // growing field counts every scan's updates).
  if ((per & (per - 1)) == 0) {
    const int shift = __builtin_ctzll(per);
    for (const Sample& s : slab.samples) ++slab.brickUpdates[s.at >> shift];
  } else {
    for (const Sample& s : slab.samples) ++slab.brickUpdates[s.at / per];
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
    if (!slab.brickUpdates.empty()) countBrickUpdates(slab);
    slab.samples.clear();
    slab.colours.clear();
    slab.sigmas.clear();
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
