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

PrismIntegrator::PrismIntegrator(BrickStore& store, int threads)
    : PrismIntegrator(store, threads, nullptr) {}

PrismIntegrator::PrismIntegrator(BrickStore& store, int threads, SurfaceHypotheses* hypotheses)
    : store_(store),
      hypotheses_(hypotheses),
      latest_(store.sums().size(), 0),
      slabs_(std::max(1, threads)) {
  // A slab's list holds at most the rank's voxels: its positions must fit latest_'s entries.
  if (store.sums().size() > std::numeric_limits<uint32_t>::max())
    throw InputError("a field of " + std::to_string(store.sums().size()) +
                     " voxels on one rank: more than 2^32 (use more ranks)");
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

void PrismIntegrator::findReach(const PrismScan& scan, size_t first, size_t end) {
  VoxelIndex lo, hi;
  // Neighbouring triangles (grid order) mostly reach the same bricks: the answer is known.
  const int B = store_.grid().brick;
  BrickCoord lastLo(1, 1, 1), lastHi(0, 0, 0);
  bool lastLocal = false;
  for (size_t t = first; t < end; ++t) {
    store_.grid().voxelRange(prismBounds(scanPrism(scan, t)), lo, hi);
    bool local = false;
    if (!(lo.array() > hi.array()).any()) {
      const BrickCoord bLo = brickOf(lo, B), bHi = brickOf(hi, B);
      if (bLo != lastLo || bHi != lastHi)
        lastLocal = touchesOwnedBrick(bLo, bHi), lastLo = bLo, lastHi = bHi;
      local = lastLocal;
    }
    reach_[t] = {lo.z(), hi.z(), local};
  }
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
  auto visit = [&](const VoxelIndex&, int64_t at, const PrismFoot& foot) {
    Sample* s = sampleOf(slab, static_cast<size_t>(at));
    // Ties keep the earlier triangle, so the result does not depend on the rank count.
    if (s && !(std::abs(foot.d) < std::abs(s->d))) return;
    if (!s) {
      latest_[at] = static_cast<uint32_t>(slab.samples.size());
      s = &slab.samples.emplace_back();
    }
    const Eigen::Vector3d g = footGradient(prism, foot.bary);
    *s = Sample{static_cast<size_t>(at),
                static_cast<float>(foot.d),
                static_cast<float>(footWeight(prism, foot.bary)),
                {static_cast<float>(g.x()), static_cast<float>(g.y()), static_cast<float>(g.z())}};
  };
  uint64_t counted = 0;
  for (size_t t = 0; t < scan.surface.triangles.size(); ++t) {
    const Reach& r = reach_[t];
    if (!r.local) continue;
    if (r.zLo >= slab.zLo && r.zLo <= slab.zHi) ++counted;
    if (r.zLo > slab.zHi || r.zHi < slab.zLo) continue;
    prism = scanPrism(scan, t);
    internal::PrismRows rows(prism, grid);
    rows.lo.z() = std::max(rows.lo.z(), slab.zLo);
    rows.hi.z() = std::min(rows.hi.z(), slab.zHi);
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
      hypotheses_->add(s.at, s.d, s.w, s.f);
      continue;
    }
    if (i + ahead < n) __builtin_prefetch(&sums[samples[i + ahead].at]);
    sums[s.at].add(s.d, s.w, s.f);
  }
}

void PrismIntegrator::cutSlabs() {
  // A view sees a part of the object: cut at the quantiles of this scan's own prisms.
  std::vector<int> mids;
  for (const Reach& r : reach_)
    if (r.local && r.zLo <= r.zHi) mids.push_back(r.zLo + (r.zHi - r.zLo) / 2);
  int from = std::numeric_limits<int>::min();
  for (size_t k = 0; k + 1 < slabs_.size(); ++k) {
    int cut = from;
    if (!mids.empty()) {
      auto at = mids.begin() + mids.size() * (k + 1) / slabs_.size();
      std::nth_element(mids.begin(), at, mids.end());
      cut = std::max(from, *at);
    }
    if (cut > from)
      slabs_[k].zLo = from, slabs_[k].zHi = cut - 1;
    else
      slabs_[k].zLo = 0, slabs_[k].zHi = -1;  // empty (no prisms here, or a repeated quantile)
    from = cut;
  }
  slabs_.back().zLo = from, slabs_.back().zHi = std::numeric_limits<int>::max();
}

IntegrationStats PrismIntegrator::addScan(const PrismScan& scan) {
  return addImage({&scan});
}

IntegrationStats PrismIntegrator::addImage(const std::vector<const PrismScan*>& parts) {
  const size_t threads = slabs_.size();
  std::vector<uint64_t> prisms(threads), updates(threads);
  // The slabs are cut at the first part's quantiles and kept for the others: a voxel's sample
  // must stay in one slab's list for the whole image (the parts of a station are bands of its
  // columns, alike along z). Every list is added once all parts are in, by its own thread
  // right after the last part (the slabs' voxels are disjoint in the sums too).
  for (const PrismScan* scan : parts) {
    const size_t n = scan->surface.triangles.size();
    reach_.resize(n);
    parallelFor(threads, static_cast<int>(threads),
                [&](size_t k) { findReach(*scan, n * k / threads, n * (k + 1) / threads); });
    if (scan == parts.front()) cutSlabs();
    // Slabs own disjoint voxels (of latest_ too): no two threads write the same one.
    parallelFor(threads, static_cast<int>(threads), [&](size_t k) {
      Slab& slab = slabs_[k];
      prisms[k] += rasterizeSlab(*scan, slab);
      if (scan != parts.back()) return;
      accumulate(slab);
      updates[k] = slab.samples.size();
      slab.samples.clear();
    });
  }
  IntegrationStats stats;
  for (size_t k = 0; k < threads; ++k) {
    stats.prisms += prisms[k];
    stats.voxelUpdates += updates[k];
  }
  return stats;
}

}  // namespace rangefuse
