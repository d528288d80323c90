#include "rangefuse/route/ScanRouting.h"

#include <malloc.h>

#include <algorithm>
#include <cstring>
#include <numeric>

#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse {
namespace {

template <class T>
void unpackVector(const std::vector<char>& buf, size_t& pos, std::vector<T>& v) {
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  v.resize(n);
  mpi::unpack(buf, pos, v.data(), n);
}

/// Reads one part as packSubScan wrote it; returns its scan index.
uint64_t unpackScan(const std::vector<char>& buf, size_t& pos, PrismScan& s) {
  uint64_t index;
  mpi::unpack(buf, pos, &index, 1);
  unpackVector(buf, pos, s.surface.points);
  unpackVector(buf, pos, s.surface.normals);
  unpackVector(buf, pos, s.surface.confidence);
  unpackVector(buf, pos, s.surface.triangles);
  unpackVector(buf, pos, s.surface.colours);
  mpi::unpack(buf, pos, &s.surface.texelSide, 1);
  unpackVector(buf, pos, s.surface.texels);
  unpackVector(buf, pos, s.surface.blocks);
  unpackVector(buf, pos, s.limits);
  mpi::unpack(buf, pos, &s.surface.sensor, 1);
  return index;
}

/// The vertices the listed triangles use, in order of first use; remap[v] is set to v's place
/// among them (the caller puts -1 back).
std::vector<uint32_t> usedVertices(const ScanSurface& s, const std::vector<uint32_t>& triangles,
                                   std::vector<int32_t>& remap) {
  std::vector<uint32_t> used;
  for (uint32_t t : triangles)
    for (const int32_t v : s.triangles[t])
      if (remap[v] < 0) {
        remap[v] = static_cast<int32_t>(used.size());
        used.push_back(v);
      }
  return used;
}

/// Appends the listed elements of v as packVector would append the vector made of them.
template <class T>
void packPicked(std::vector<char>& buf, const std::vector<T>& v, const std::vector<uint32_t>& pick,
                size_t per = 1) {
  const uint64_t n = v.empty() ? 0 : pick.size() * per;
  mpi::pack(buf, &n, 1);
  if (n == 0) return;
  // Grown once and written in place: an insert a value costs more than the copy.
  const size_t at = buf.size(), bytes = per * sizeof(T);
  buf.resize(at + n * sizeof(T));
  char* out = buf.data() + at;
  for (uint32_t i : pick) std::memcpy(out, v.data() + size_t(i) * per, bytes), out += bytes;
}

/// Appends the part of `scan` made of the listed triangles, as subScan would make it, to buf:
/// its index, then each vector with its length. Written straight from the scan and sized once
/// (no copy of the part in between, no doubling).
void packSubScan(std::vector<char>& buf, uint64_t index, const PrismScan& scan,
                 const std::vector<uint32_t>& triangles, std::vector<int32_t>& remap) {
  const ScanSurface& s = scan.surface;
  const std::vector<uint32_t> used = usedVertices(s, triangles, remap);
  const size_t perPoint = size_t(s.texelSide) * s.texelSide;
  const size_t v = used.size(), t = triangles.size();
  const size_t bytes =
      9 * sizeof(uint64_t) + sizeof(s.texelSide) + sizeof(s.sensor) +
      v * (2 * sizeof(Eigen::Vector3d) + sizeof(double)) +
      t * (sizeof(Triangle) + sizeof(scan.limits[0])) +
      (s.colours.empty() ? 0 : v * sizeof(Colour)) +
      (s.texels.empty() ? 0 : v * (perPoint * sizeof(Texel) + sizeof(s.blocks[0])));
  buf.reserve(buf.size() + bytes);
  mpi::pack(buf, &index, 1);
  packPicked(buf, s.points, used);
  packPicked(buf, s.normals, used);
  packPicked(buf, s.confidence, used);
  const uint64_t nt = t;
  mpi::pack(buf, &nt, 1);
  const size_t at = buf.size();
  buf.resize(at + t * sizeof(Triangle));
  char* out = buf.data() + at;
  for (uint32_t k : triangles) {
    const Triangle& tri = s.triangles[k];
    const Triangle local{remap[tri[0]], remap[tri[1]], remap[tri[2]]};
    std::memcpy(out, &local, sizeof(Triangle)), out += sizeof(Triangle);
  }
  packPicked(buf, s.colours, used);
  mpi::pack(buf, &s.texelSide, 1);
  packPicked(buf, s.texels, used, perPoint);
  packPicked(buf, s.blocks, used);
  packPicked(buf, scan.limits, triangles);
  mpi::pack(buf, &s.sensor, 1);
  for (uint32_t k : used) remap[k] = -1;
}

/// The part of `scan` made of the listed triangles (in order) and the vertices they use. Sized
/// before it is filled: a routed part grows no vector by doubling (each step would leave pages
/// behind that the rank then holds).
PrismScan subScan(const PrismScan& scan, const std::vector<uint32_t>& triangles,
                  std::vector<int32_t>& remap) {
  const ScanSurface& s = scan.surface;
  const std::vector<uint32_t> used = usedVertices(s, triangles, remap);
  PrismScan part;
  ScanSurface& p = part.surface;
  p.sensor = s.sensor;
  p.texelSide = s.texelSide;
  const size_t perPoint = size_t(s.texelSide) * s.texelSide;
  p.points.reserve(used.size());
  p.normals.reserve(used.size());
  p.confidence.reserve(used.size());
  if (!s.colours.empty()) p.colours.reserve(used.size());
  if (!s.texels.empty()) p.blocks.reserve(used.size()), p.texels.reserve(used.size() * perPoint);
  for (const uint32_t v : used) {
    p.points.push_back(s.points[v]);
    p.normals.push_back(s.normals[v]);
    p.confidence.push_back(s.confidence[v]);
    if (!s.colours.empty()) p.colours.push_back(s.colours[v]);
    if (!s.texels.empty()) {
      p.blocks.push_back(s.blocks[v]);
      const auto from = s.texels.begin() + v * perPoint;
      p.texels.insert(p.texels.end(), from, from + perPoint);
    }
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

/// The ranks that may own bricks of [lo, hi] (BrickLayout::mayOwn), ascending, each once.
std::vector<int> brickOwners(const BrickLayout& layout, const BrickCoord& lo, const BrickCoord& hi,
                             int me) {
  std::vector<int> owners;
  BrickCoord b;
  for (b.z() = lo.z(); b.z() <= hi.z(); ++b.z())
    for (b.y() = lo.y(); b.y() <= hi.y(); ++b.y())
      for (b.x() = lo.x(); b.x() <= hi.x(); ++b.x()) {
        const int owner = layout.mayOwn(mortonEncode(b), me);
        if (owner >= 0) owners.push_back(owner);
      }
  std::sort(owners.begin(), owners.end());
  owners.erase(std::unique(owners.begin(), owners.end()), owners.end());
  return owners;
}

}  // namespace

void routeScan(uint64_t index, PrismScan world, const BrickLayout& layout, double reach, int me,
               std::vector<std::vector<char>>& out, IndexedScans& mine, RoutingStats& stats) {
  const int ranks = layout.ranks();
  std::vector<std::vector<uint32_t>> triangles(ranks);
  std::vector<int> owners;
  // Neighbouring triangles (grid order) mostly reach the same bricks: their owners are known.
  BrickCoord lastLo(1, 1, 1), lastHi(0, 0, 0);
  for (size_t t = 0; t < world.surface.triangles.size(); ++t) {
    BrickCoord lo, hi;
    if (!bricksOfBox(layout.grid, reachedBox(world, t, reach), lo, hi)) continue;
    if (lo != lastLo || hi != lastHi) {
      owners = brickOwners(layout, lo, hi, me);
      lastLo = lo, lastHi = hi;
    }
    for (int r : owners) triangles[r].push_back(static_cast<uint32_t>(t));
  }
  std::vector<int32_t> remap(world.surface.points.size(), -1);
  stats.triangles += world.surface.triangles.size();
  for (int r = 0; r < ranks; ++r) {
    if (triangles[r].empty() || r == me) continue;
    const size_t before = out[r].size();
    packSubScan(out[r], index, world, triangles[r], remap);
    stats.copies += triangles[r].size();
    stats.bytes[r] += out[r].size() - before;
  }
  // This rank's own part is kept as it is, not serialised: with one rank, the whole field.
  if (me < 0 || triangles[me].empty()) return;
  stats.copies += triangles[me].size();
  if (triangles[me].size() == world.surface.triangles.size())
    mine.emplace_back(index, std::move(world));
  else
    mine.emplace_back(index, subScan(world, triangles[me], remap));
}

PrismScan usedPointsOnly(PrismScan scan) {
  std::vector<uint8_t> used(scan.surface.points.size(), 0);
  size_t count = 0;
  for (const Triangle& t : scan.surface.triangles)
    for (const int32_t v : t) count += !used[v], used[v] = 1;
  if (count == used.size()) return scan;
  std::vector<uint32_t> all(scan.surface.triangles.size());
  std::iota(all.begin(), all.end(), 0u);
  std::vector<int32_t> remap(used.size(), -1);
  PrismScan kept = subScan(scan, all, remap);
  kept.surface.colourKind = scan.surface.colourKind;
  kept.sight = std::move(scan.sight);
  kept.noise = std::move(scan.noise);
  return kept;
}

void unpackRoutedInto(std::vector<char>&& bytes, IndexedScans& into) {
  for (size_t pos = 0; pos < bytes.size();) {
    PrismScan s;
    const uint64_t i = unpackScan(bytes, pos, s);
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
    s.texels.insert(s.texels.end(), p.texels.begin(), p.texels.end());
    s.blocks.insert(s.blocks.end(), p.blocks.begin(), p.blocks.end());
    for (Triangle t : p.triangles) s.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    out.limits.insert(out.limits.end(), parts[k].limits.begin(), parts[k].limits.end());
  }
  if (s.blocks.size() != s.points.size()) s.texels = {}, s.blocks = {};  // not all parts had them
  return out;
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

uint64_t partsBytes(const IndexedScans& parts, size_t from) {
  uint64_t bytes = 0;
  for (size_t k = from; k < parts.size(); ++k) bytes += scanBytes(parts[k].second);
  return bytes;
}

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

}  // namespace

bool routeRounds(const std::vector<std::vector<size_t>>& byRound,
                 const std::function<PrismScan(size_t)>& take, const BrickLayout& layout,
                 double reach, MPI_Comm comm, IndexedScans& parts, RoutingStats& stats) {
  const int ranks = mpi::size(comm), me = mpi::rank(comm);
  if (stats.bytes.size() != static_cast<size_t>(ranks)) stats.bytes.assign(ranks, 0);
  Trimmer trim;
  uint64_t held = partsBytes(parts, 0);
  for (const std::vector<size_t>& round : byRound) {
    std::vector<std::vector<char>> out(ranks);
    uint64_t given = 0;
    const size_t counted = parts.size();  // parts whose bytes `held` has
    if (!mpi::collectively(comm, [&] {
          for (size_t i : round) {
            PrismScan s = take(i);
            given += scanBytes(s);
            routeScan(i, std::move(s), layout, reach, me, out, parts, stats);
          }
        }))
      return false;
    mpi::exchangeBytes(std::move(out), comm, [&](int, std::vector<char>&& bytes) {
      unpackRoutedInto(std::move(bytes), parts);
    });
    held += partsBytes(parts, counted);
    memoryLedger().set(Held::routedScans, held);
    trim.freed(given);
  }
  return true;
}

}  // namespace rangefuse
