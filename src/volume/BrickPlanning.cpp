#include "rangefuse/volume/BrickPlanning.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Limits.h"
#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

constexpr int kMaxVoxelsPerAxis = 1 << 20;  // vertex keys pack 20 bits per axis

/// Voxels along the longest axis from the grid origin to the far side of `box`.
double extentVoxels(const VoxelGrid& g, const Eigen::AlignedBox3d& box, double eps) {
  return ((box.max() - g.origin).array() + eps).maxCoeff() / g.voxel + 2 * g.brick;
}

void checkVoxels(const VoxelGrid& grid, const char* what, double voxels, uint64_t maxVoxels) {
  checkLimit("--voxel " + formatNumber(grid.voxel), what, voxels, maxVoxels, "max-voxels");
}

/// Sorted (code, work) pairs of a work map, flattened.
std::vector<uint64_t> sortedPairs(const BrickWork& work) {
  std::vector<std::pair<uint64_t, uint64_t>> pairs(work.begin(), work.end());
  std::sort(pairs.begin(), pairs.end());
  std::vector<uint64_t> flat;
  flat.reserve(2 * pairs.size());
  for (const auto& [code, w] : pairs) flat.push_back(code), flat.push_back(w);
  return flat;
}

/// The rank that sums brick `code`'s work while planning: spread by a hash, so that each rank
/// sums about as many bricks wherever they lie.
int summerOf(uint64_t code, int ranks) {
  return static_cast<int>(((code * 0x9E3779B97F4A7C15ull) >> 32) % static_cast<uint64_t>(ranks));
}

}  // namespace

VoxelGrid gridAround(const Eigen::AlignedBox3d& box, double voxel, int brick, double eps,
                     int margin) {
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

bool gridHoldsBox(const VoxelGrid& grid, const Eigen::AlignedBox3d& box, double eps) {
  if (box.isEmpty()) return true;
  const double step = grid.voxel * grid.brick;
  const bool above = ((box.min() - grid.origin).array() - eps >= step).all();
  return above && extentVoxels(grid, box, eps) < kMaxVoxelsPerAxis;
}

bool bricksOfBox(const VoxelGrid& grid, const Eigen::AlignedBox3d& box, BrickCoord& lo,
                 BrickCoord& hi) {
  VoxelIndex vlo, vhi;
  grid.voxelRange(box, vlo, vhi);
  if ((vlo.array() > vhi.array()).any()) return false;
  lo = brickOf(vlo, grid.brick);
  hi = brickOf(vhi, grid.brick);
  return true;
}

void addBrickWork(const VoxelGrid& grid, const BrickCoord& lo, const BrickCoord& hi, uint64_t count,
                  uint64_t maxVoxels, BrickWork& work) {
  // One huge box or many small ones: either way refused before the map grows.
  const double perBrick = static_cast<double>(grid.brick) * grid.brick * grid.brick;
  const double voxels =
      (static_cast<double>(work.size()) + (hi - lo + BrickCoord::Ones()).cast<double>().prod()) *
      perBrick;
  if (voxels > static_cast<double>(maxVoxels))
    checkVoxels(grid, "voxels needed near the surface (estimate):", voxels, maxVoxels);
  BrickCoord b;
  for (b.z() = lo.z(); b.z() <= hi.z(); ++b.z())
    for (b.y() = lo.y(); b.y() <= hi.y(); ++b.y())
      for (b.x() = lo.x(); b.x() <= hi.x(); ++b.x()) work[mortonEncode(b)] += count;
}

void addWork(const BrickWork& part, const VoxelGrid& grid, uint64_t maxVoxels, BrickWork& work) {
  for (const auto& [code, w] : part) work[code] += w;
  const double voxels = static_cast<double>(work.size()) * std::pow(grid.brick, 3);
  if (voxels > static_cast<double>(maxVoxels))
    checkVoxels(grid, "voxels needed near the surface (estimate):", voxels, maxVoxels);
}

BrickLayout layoutFromWork(const BrickWork& work, const VoxelGrid& grid, int ranks) {
  BrickLayout layout;
  layout.grid = grid;
  const std::vector<uint64_t> flat = sortedPairs(work);
  for (size_t i = 0; i < flat.size(); i += 2) {
    layout.codes.push_back(flat[i]);
    layout.work.push_back(flat[i + 1]);
  }
  layout.rankStart = partitionWork(layout.work, ranks);
  return layout;
}

BrickLayout reduceBrickWork(const BrickWork& mine, const VoxelGrid& grid, uint64_t maxVoxels,
                            MPI_Comm comm) {
  const int ranks = mpi::size(comm);
  // Each brick's pairs go to the one rank that sums them, so that no rank holds every rank's
  // pairs of every brick (nor a map of them all) at once.
  std::vector<std::vector<char>> out(ranks);
  for (const auto& [code, w] : mine) {
    const uint64_t pair[2] = {code, w};
    mpi::pack(out[summerOf(code, ranks)], pair, 2);
  }
  BrickWork summed;
  for (auto& part : mpi::exchangeBytes(std::move(out), comm)) {
    for (size_t pos = 0; pos < part.size();) {
      uint64_t pair[2];
      mpi::unpack(part, pos, pair, 2);
      summed[pair[0]] += pair[1];
    }
    std::vector<char>().swap(part);
  }
  // Then every rank's sums to every rank, each brick once: the list, sorted.
  std::vector<char> bytes;
  const std::vector<uint64_t> flat = sortedPairs(summed);
  summed = {};
  mpi::pack(bytes, flat.data(), flat.size());
  std::vector<std::pair<uint64_t, uint64_t>> all;
  uint64_t gathered = 0;
  for (auto& part : mpi::allgatherBytes(bytes, comm)) {
    gathered += part.size();
    for (size_t pos = 0; pos < part.size();) {
      uint64_t pair[2];
      mpi::unpack(part, pos, pair, 2);
      all.emplace_back(pair[0], pair[1]);
    }
    std::vector<char>().swap(part);
  }
  memoryLedger().set(Held::brickList, gathered + sizeof(all[0]) * all.capacity());
  checkVoxels(grid, "voxels needed near the surface:",
              static_cast<double>(all.size()) * std::pow(grid.brick, 3), maxVoxels);
  std::sort(all.begin(), all.end());
  BrickLayout layout;
  layout.grid = grid;
  layout.codes.reserve(all.size());
  layout.work.reserve(all.size());
  for (const auto& [code, w] : all) layout.codes.push_back(code), layout.work.push_back(w);
  layout.rankStart = partitionWork(layout.work, ranks);
  return layout;
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
  checkVoxels(layout.grid, "voxels near the surface, registration room included:",
              static_cast<double>(codes.size()) * std::pow(layout.grid.brick, 3), maxVoxels);
  std::vector<uint64_t> work(codes.size(), 0);
  for (size_t i = 0; i < codes.size(); ++i) {
    const int64_t at = layout.find(codes[i]);
    if (at >= 0) work[i] = layout.work[at];
  }
  layout.codes = std::move(codes);
  layout.work = std::move(work);
  layout.rankStart = partitionWork(layout.work, ranks);
}

}  // namespace rangefuse
