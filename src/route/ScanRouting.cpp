#include "rangefuse/route/ScanRouting.h"

#include <malloc.h>

#include <algorithm>

#include "PartPacking.h"
#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse {
namespace {

using internal::packPart;
using internal::unpackPart;
using internal::usedVertices;

/// The part of `scan` made of the listed triangles (in order) and the vertices they use. Sized
/// before it is filled: a routed part grows no vector by doubling (each step would leave pages
/// behind that the rank then holds).
PrismScan subScan(const PrismScan& scan, const std::vector<uint32_t>& triangles,
                  std::vector<int32_t>& remap) {
  const ScanSurface& s = scan.surface;
  const std::vector<uint32_t> used = usedVertices(s, triangles, remap);
  PrismScan part;
  ScanSurface& p = part.surface;
  part.quantum = scan.quantum;
  part.origin = scan.origin;
  p.sensor = s.sensor;
  p.texelSide = s.texelSide;
  p.points.reserve(used.size());
  p.normals.reserve(used.size());
  p.confidence.reserve(used.size());
  if (!s.colours.empty()) p.colours.reserve(used.size());
  if (!s.texels.empty()) {
    p.blocks.reserve(used.size());
    p.texels = triangleTexels(s.texels, s.blocks, s.triangles, s.texelSide, &triangles);
  }
  for (const uint32_t v : used) {
    p.points.push_back(s.points[v]);
    p.normals.push_back(s.normals[v]);
    p.confidence.push_back(s.confidence[v]);
    if (!s.colours.empty()) p.colours.push_back(s.colours[v]);
    if (!s.texels.empty()) p.blocks.push_back(s.blocks[v]);
  }
  p.triangles.reserve(triangles.size());
  part.limits.reserve(triangles.size());
  for (uint32_t t : triangles) {
    const Triangle& tri = s.triangles[t];
    p.triangles.push_back({remap[tri[0]], remap[tri[1]], remap[tri[2]]});
    part.limits.push_back(scan.limits[t]);
  }
  for (uint32_t v : used) remap[v] = -1;
  return part;
}

}  // namespace

namespace {

Eigen::AlignedBox3d reachedBox(const PrismScan& world, size_t t, double reach) {
  const ScanSurface& s = world.surface;
  Eigen::AlignedBox3d box;
  if (reach == 0) {  // prismBounds(scanPrism(world, t)), without copying the prism out
    const auto& limits = world.limits[t];
    for (const int32_t v : s.triangles[t]) {
      box.extend(s.points[v] + limits[0] * s.normals[v]);
      box.extend(s.points[v] + limits[1] * s.normals[v]);
    }
    return box;
  }
  for (const int32_t v : s.triangles[t]) box.extend(s.points[v]);
  box.min().array() -= reach;
  box.max().array() += reach;
  return box;
}

/// The ranks each triangle of a scan goes to, remembered by the box of bricks it reaches:
/// neighbouring triangles (grid order) mostly reach the same bricks, and a brick's owner is
/// looked up in the layout once, not at every box that holds it.
class TriangleOwners {
 public:
  /// With `reached`, each owner's bricks are listed there too (some more than once).
  TriangleOwners(const BrickLayout& layout, int me, RouteTo to, ReachedBricks* reached)
      : layout_(layout),
        me_(me),
        to_(to),
        reached_(reached),
        codes_(kSlots, kNoCode),
        owners_(kSlots) {}

  /// The ranks that may own bricks of [lo, hi] (BrickLayout::mayOwn), or own their ranges of
  /// codes, ascending, each once.
  const std::vector<int>& of(const BrickCoord& lo, const BrickCoord& hi) {
    if (lo == lastLo_ && hi == lastHi_) return ranks_;
    lastLo_ = lo, lastHi_ = hi;
    ranks_.clear();
    BrickCoord b;
    for (b.z() = lo.z(); b.z() <= hi.z(); ++b.z())
      for (b.y() = lo.y(); b.y() <= hi.y(); ++b.y())
        for (b.x() = lo.x(); b.x() <= hi.x(); ++b.x()) {
          const int owner = ownerOf(mortonEncode(b));
          if (owner >= 0 && std::find(ranks_.begin(), ranks_.end(), owner) == ranks_.end())
            ranks_.push_back(owner);
        }
    std::sort(ranks_.begin(), ranks_.end());
    return ranks_;
  }

 private:
  /// A brick's owner as the layout answers it, through a cache indexed by the code's hash.
  int ownerOf(uint64_t code) {
    const size_t slot = (code * 0x9E3779B97F4A7C15ull) >> (64 - kSlotBits);
    if (codes_[slot] != code) {
      codes_[slot] = code;
      owners_[slot] =
          to_ == RouteTo::ranges ? layout_.ownerOfCode(code) : layout_.mayOwn(code, me_);
      // A brick is listed when it enters the cache: once, or again after an eviction.
      if (reached_ && owners_[slot] >= 0) (*reached_)[owners_[slot]].push_back(code);
    }
    return owners_[slot];
  }

  static constexpr int kSlotBits = 10;
  static constexpr size_t kSlots = size_t{1} << kSlotBits;
  static constexpr uint64_t kNoCode = ~uint64_t{0};  // above every code of 21-bit coordinates
  const BrickLayout& layout_;
  const int me_;
  const RouteTo to_;
  ReachedBricks* reached_;
  std::vector<uint64_t> codes_;
  std::vector<int> owners_;
  std::vector<int> ranks_;
  BrickCoord lastLo_{1, 1, 1}, lastHi_{0, 0, 0};  // an empty box: no triangle's
};

/// Each rank's triangles of `world`, ascending: those that reach a brick it owns or may own
/// (with `reached`, the bricks listed there too; see TriangleOwners).
std::vector<std::vector<uint32_t>> trianglesByRank(const PrismScan& world,
                                                   const BrickLayout& layout, double reach, int me,
                                                   RouteTo to, ReachedBricks* reached = nullptr) {
  std::vector<std::vector<uint32_t>> triangles(layout.ranks());
  TriangleOwners owners(layout, me, to, reached);
  for (size_t t = 0; t < world.surface.triangles.size(); ++t) {
    BrickCoord lo, hi;
    if (!bricksOfBox(layout.grid, reachedBox(world, t, reach), lo, hi)) continue;
    for (int r : owners.of(lo, hi)) triangles[r].push_back(static_cast<uint32_t>(t));
  }
  return triangles;
}

/// Packs the triangles of every rank but `me` into out[r], counting them in `stats`.
void packForOthers(uint64_t index, const PrismScan& world,
                   const std::vector<std::vector<uint32_t>>& triangles, int me,
                   std::vector<std::vector<char>>& out, std::vector<int32_t>& remap,
                   RoutingStats& stats) {
  stats.triangles += world.surface.triangles.size();
  for (size_t r = 0; r < triangles.size(); ++r) {
    if (triangles[r].empty() || static_cast<int>(r) == me) continue;
    const size_t before = out[r].size();
    packPart(out[r], index, world, triangles[r], remap);
    stats.copies += triangles[r].size();
    stats.bytes[r] += out[r].size() - before;
  }
}

}  // namespace

void routeScan(uint64_t index, PrismScan world, const BrickLayout& layout, double reach, int me,
               std::vector<std::vector<char>>& out, IndexedScans& mine, RoutingStats& stats,
               RouteTo to) {
  const auto triangles = trianglesByRank(world, layout, reach, me, to);
  std::vector<int32_t> remap(world.surface.points.size(), -1);
  packForOthers(index, world, triangles, me, out, remap, stats);
  // This rank's own part is kept as it is, not serialised: with one rank, the whole field.
  if (me < 0 || triangles[me].empty()) return;
  stats.copies += triangles[me].size();
  if (triangles[me].size() == world.surface.triangles.size())
    mine.emplace_back(index, std::move(world));
  else
    mine.emplace_back(index, subScan(world, triangles[me], remap));
}

std::vector<char> packedScan(const PrismScan& scan) {
  std::vector<char> bytes;
  internal::packWhole(bytes, 0, scan);
  bytes.shrink_to_fit();
  return bytes;
}

PrismScan unpackedScan(const std::vector<char>& bytes) {
  PrismScan scan;
  size_t pos = 0;
  unpackPart(bytes, pos, scan);
  return scan;
}

void unpackRoutedInto(std::vector<char>&& bytes, IndexedScans& into) {
  for (size_t pos = 0; pos < bytes.size();) {
    PrismScan s;
    const uint64_t i = unpackPart(bytes, pos, s);
    into.emplace_back(i, std::move(s));
  }
  std::vector<char>().swap(bytes);  // unpacked: the next rank's part may take its place
}

IndexedScans unpackRouted(std::vector<std::vector<char>>&& in) {
  IndexedScans scans;
  for (auto& part : in) unpackRoutedInto(std::move(part), scans);
  sortByEntry(scans);
  return scans;
}

void sortByEntry(IndexedScans& parts) {
  std::stable_sort(parts.begin(), parts.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
}

PrismScan joinScans(std::vector<PrismScan>&& parts) {
  PrismScan out = std::move(parts.front());
  ScanSurface& s = out.surface;
  for (size_t k = 1; k < parts.size(); ++k) {
    const ScanSurface& p = parts[k].surface;
    const auto base = static_cast<int32_t>(s.points.size());
    s.points.insert(s.points.end(), p.points.begin(), p.points.end());
    s.normals.insert(s.normals.end(), p.normals.begin(), p.normals.end());
    s.confidence.insert(s.confidence.end(), p.confidence.begin(), p.confidence.end());
    s.colours.insert(s.colours.end(), p.colours.begin(), p.colours.end());
    // Parts of one scan share its texel side; parts without texels (bands) have none at all.
    s.texels.include(p.texels);
    s.blocks.insert(s.blocks.end(), p.blocks.begin(), p.blocks.end());
    for (Triangle t : p.triangles) s.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    out.limits.insert(out.limits.end(), parts[k].limits.begin(), parts[k].limits.end());
  }
  if (s.blocks.size() != s.points.size()) s.texels = {}, s.blocks = {};  // not all parts had them
  return out;
}

size_t roundCount(const std::vector<std::vector<size_t>>& byReader,
                  const std::vector<uint64_t>& bytes, uint64_t roundBytes) {
  size_t rounds = 0;
  for (const std::vector<size_t>& entries : byReader) {
    uint64_t total = 0;
    for (size_t i : entries) total += bytes[i];
    const uint64_t need = (total + roundBytes - 1) / roundBytes;
    rounds = std::max(rounds, total > 0 ? std::min<size_t>(entries.size(), need) : entries.size());
  }
  return rounds;
}

std::vector<std::vector<size_t>> roundsOf(const std::vector<size_t>& mine, size_t rounds,
                                          const std::vector<uint64_t>& bytes) {
  uint64_t total = 0;
  for (size_t i : mine) total += bytes[i];
  std::vector<std::vector<size_t>> byRound(rounds);
  uint64_t before = 0;
  for (size_t j = 0; j < mine.size(); ++j) {
    const size_t k = total ? std::min<size_t>(rounds - 1, before * rounds / total) : j;
    byRound[k].push_back(mine[j]);
    before += bytes[mine[j]];
  }
  return byRound;
}

namespace {

/// Gives the pages of freed scans back to the system once enough have been freed: the parts a
/// rank receives are allocated apart from the scans it gave away, which would otherwise stay
/// resident beside them (48-view set on 4 ranks: 189 -> 179 MiB; a trim costs a few ms).
class Trimmer {
 public:
  void freed(uint64_t bytes) {
    pending_ += bytes;
    if (pending_ < kBytes) return;
    malloc_trim(0);
    pending_ = 0;
  }

 private:
  static constexpr uint64_t kBytes = 16 << 20;
  uint64_t pending_ = 0;
};

/// Routes one taken scan (see routeRounds), its parts for others appended to `out`; returns
/// the bytes it freed.
uint64_t routeTaken(size_t i, TakenScan&& s, const BrickLayout& layout, double reach, bool colour,
                    int me, RouteTo to, std::vector<std::vector<char>>& out, RoutedParts& parts,
                    RoutingStats& stats, ReachedBricks* reached) {
  const bool packed = !s.packed.empty();
  if (layout.ranks() == 1 && reach == 0) {
    if (!colour) dropColour(s.scan.surface);  // packed colours go unread: the store has none
    if (packed)
      parts.keepBytes(i, std::move(s.packed));
    else
      parts.keep(i, std::move(s.scan));
    return 0;
  }
  if (packed) s.scan = unpackedScan(s.packed);
  const uint64_t freed = s.packed.size() + scanBytes(s.scan);
  if (!colour) dropColour(s.scan.surface);  // nothing to send or keep
  const PrismScan& world = s.scan;
  const auto triangles = trianglesByRank(world, layout, reach, me, to, reached);
  std::vector<int32_t> remap(world.surface.points.size(), -1);
  packForOthers(i, world, triangles, me, out, remap, stats);
  const std::vector<uint32_t>& own = triangles[me];
  if (own.empty()) return freed;
  stats.copies += own.size();
  const bool whole = own.size() == world.surface.triangles.size();
  if (packed && whole) {
    parts.keepBytes(i, std::move(s.packed));  // all of it stays: packed already
  } else if (world.compact()) {  // packed straight from the scan: the bytes a copy would pack
    std::vector<char> bytes;
    packPart(bytes, i, world, own, remap);
    parts.keepBytes(i, std::move(bytes));
  } else if (whole) {
    parts.keep(i, std::move(s.scan));
  } else {
    parts.keep(i, subScan(world, own, remap));
  }
  return freed;
}

}  // namespace

bool routeRounds(const std::vector<std::vector<size_t>>& byRound,
                 const std::function<TakenScan(size_t)>& take, const BrickLayout& layout,
                 double reach, bool colour, MPI_Comm comm, RoutedParts& parts, RoutingStats& stats,
                 RouteTo to, ReachedBricks* reached) {
  const int ranks = mpi::size(comm), me = mpi::rank(comm);
  if (stats.bytes.size() != static_cast<size_t>(ranks)) stats.bytes.assign(ranks, 0);
  if (reached) reached->assign(ranks, {});
  Trimmer trim;
  for (const std::vector<size_t>& round : byRound) {
    std::vector<std::vector<char>> out(ranks);
    uint64_t given = 0;
    if (!mpi::collectively(comm, [&] {
          for (size_t i : round) {
            given +=
                routeTaken(i, take(i), layout, reach, colour, me, to, out, parts, stats, reached);
          }
        }))
      return false;
    mpi::exchangeBytes(std::move(out), comm,
                       [&](int, std::vector<char>&& bytes) { parts.receive(std::move(bytes)); });
    memoryLedger().set(Held::routedScans, parts.bytes());
    trim.freed(given);
  }
  if (reached)
    for (std::vector<uint64_t>& codes : *reached) {
      std::sort(codes.begin(), codes.end());
      codes.erase(std::unique(codes.begin(), codes.end()), codes.end());
    }
  return true;
}

}  // namespace rangefuse
