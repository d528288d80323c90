#include "rangefuse/volume/BrickPlanning.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Limits.h"
#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

using Pair = std::pair<uint64_t, uint64_t>;

constexpr int kMaxVoxelsPerAxis = 1 << 20;  // vertex keys pack 20 bits per axis

/// Voxels along the longest axis from the grid origin to the far side of `box`.
double extentVoxels(const VoxelGrid& g, const Eigen::AlignedBox3d& box, double eps) {
  return ((box.max() - g.origin).array() + eps).maxCoeff() / g.voxel + 2 * g.brick;
}

void checkVoxels(const VoxelGrid& grid, const char* what, double voxels, uint64_t maxVoxels) {
  checkLimit("--voxel " + formatNumber(grid.voxel), what, voxels, maxVoxels, "max-voxels");
}

/// Pairs sorted by code with the work of equal codes summed.
std::vector<Pair> summedPairs(const std::vector<Pair>& sorted) {
  std::vector<Pair> out;
  for (const Pair& p : sorted) {
    if (!out.empty() && out.back().first == p.first)
      out.back().second += p.second;
    else
      out.push_back(p);
  }
  return out;
}

/// Collective: sends out[r] (packed pairs) to each rank r; returns the pairs received, in the
/// senders' rank order, each part freed as it is copied.
std::vector<Pair> exchangePairs(std::vector<std::vector<char>> out, MPI_Comm comm) {
  std::vector<Pair> in;
  for (auto& part : mpi::exchangeBytes(std::move(out), comm)) {
    if (part.empty()) continue;  // memcpy may not be given an empty vector's null data
    const size_t at = in.size();
    in.resize(at + part.size() / sizeof(Pair));
    std::memcpy(static_cast<void*>(in.data() + at), part.data(), part.size());
    std::vector<char>().swap(part);
  }
  return in;
}

/// Sum over ranks.
uint64_t totalOf(uint64_t mine, MPI_Comm comm) {
  uint64_t total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UINT64_T, MPI_SUM, comm);
  return total;
}

/// Collective: ranks - 1 codes that cut every rank's sorted codes into ranges of about equal
/// size (regular sampling: a few evenly spaced codes of each rank, gathered and sorted).
std::vector<uint64_t> splittersOf(const std::vector<Pair>& sorted, MPI_Comm comm) {
  const int ranks = mpi::size(comm);
  constexpr size_t kSamples = 64;
  std::vector<uint64_t> samples;
  const size_t n = sorted.size(), take = std::min(n, kSamples);
  for (size_t k = 0; k < take; ++k) samples.push_back(sorted[k * n / take].first);
  std::vector<char> bytes;
  mpi::pack(bytes, samples.data(), samples.size());
  std::vector<uint64_t> all;
  for (const auto& part : mpi::allgatherBytes(bytes, comm))
    for (size_t pos = 0; pos < part.size();) {
      uint64_t c;
      mpi::unpack(part, pos, &c, 1);
      all.push_back(c);
    }
  std::sort(all.begin(), all.end());
  std::vector<uint64_t> splitters;
  for (int r = 1; r < ranks; ++r)
    splitters.push_back(all.empty() ? ~uint64_t{0} : all[all.size() * r / ranks]);
  return splitters;
}

/// Collective: where each rank's run starts in the whole sorted list (ranks + 1 entries), the
/// cuts partitionWork would make on the whole list (each brick's work plus brickCost), found
/// from each rank's part of it. `first` is set to the position of mine[0] in the whole list.
std::vector<uint64_t> cutsOf(const std::vector<Pair>& mine, uint64_t brickCost, MPI_Comm comm,
                             uint64_t& first) {
  const int ranks = mpi::size(comm);
  uint64_t local[2] = {mine.size(), 0}, before[2] = {0, 0}, total[2] = {0, 0};
  for (const Pair& p : mine) local[1] += p.second + brickCost;
  MPI_Exscan(local, before, 2, MPI_UINT64_T, MPI_SUM, comm);
  if (mpi::rank(comm) == 0) before[0] = before[1] = 0;  // MPI leaves rank 0's undefined
  MPI_Allreduce(local, total, 2, MPI_UINT64_T, MPI_SUM, comm);
  // Brick i opens rank r's run once the work before it reaches r/ranks of the total; a cut
  // met on an earlier rank is met here too, so the smallest candidate wins.
  std::vector<uint64_t> start(ranks + 1, total[0]);
  uint64_t prefix = before[1];
  int r = 1;
  for (size_t i = 0; i < mine.size() && r < ranks; ++i) {
    while (r < ranks && prefix * ranks >= total[1] * r) start[r++] = before[0] + i;
    prefix += mine[i].second + brickCost;
  }
  start[0] = 0;
  MPI_Allreduce(MPI_IN_PLACE, start.data(), ranks + 1, MPI_UINT64_T, MPI_MIN, comm);
  first = before[0];
  return start;
}

/// Collective: the code at each cut (the first code of each rank's range); past every code
/// for ranks with nothing after them. mine[0] is at `first` in the whole list.
std::vector<uint64_t> firstCodesOf(const std::vector<Pair>& mine,
                                   const std::vector<uint64_t>& start, uint64_t first,
                                   MPI_Comm comm) {
  const uint64_t n = mine.size();
  std::vector<uint64_t> codes(start.size(), ~uint64_t{0});
  for (size_t r = 0; r + 1 < start.size(); ++r)
    if (start[r] >= first && start[r] < first + n) codes[r] = mine[start[r] - first].first;
  MPI_Allreduce(MPI_IN_PLACE, codes.data(), static_cast<int>(codes.size()), MPI_UINT64_T, MPI_MIN,
                comm);
  codes[0] = 0;
  return codes;
}

/// Collective: each rank's part of the whole sorted list sent to the ranks owning it by the
/// cuts (mine[0] at `first` in it); returns this rank's run, sorted.
std::vector<Pair> sendToOwners(std::vector<Pair> mine, const std::vector<uint64_t>& start,
                               uint64_t first, MPI_Comm comm) {
  std::vector<std::vector<char>> out(mpi::size(comm));
  for (size_t i = 0; i < mine.size(); ++i) {
    const auto at = std::upper_bound(start.begin(), start.end() - 1, first + i);
    mpi::pack(out[at - start.begin() - 1], &mine[i], 1);
  }
  std::vector<Pair>().swap(mine);
  return exchangePairs(std::move(out), comm);  // senders' parts in rank order, each sorted
}

/// Collective: this rank's run and the bricks of other ranks bordering it (asked of their
/// owners), sorted.
std::vector<Pair> withBorder(std::vector<Pair> own, const std::vector<uint64_t>& firstCodes, int me,
                             MPI_Comm comm) {
  const uint64_t lo = firstCodes[me], hi = firstCodes[me + 1];
  std::vector<uint64_t> asked;
  for (const Pair& p : own)
    for (uint64_t n : neighbourCodes(p.first))
      if (n < lo || n >= hi) asked.push_back(n);
  std::sort(asked.begin(), asked.end());
  asked.erase(std::unique(asked.begin(), asked.end()), asked.end());
  const int ranks = mpi::size(comm);
  std::vector<std::vector<char>> out(ranks);
  for (uint64_t c : asked) {
    const int owner = static_cast<int>(
        std::upper_bound(firstCodes.begin(), firstCodes.end() - 1, c) - firstCodes.begin() - 1);
    mpi::pack(out[owner], &c, 1);
  }
  std::vector<uint64_t>().swap(asked);
  std::vector<std::vector<char>> answers(ranks);
  const std::vector<std::vector<char>> questions = mpi::exchangeBytes(std::move(out), comm);
  for (int r = 0; r < ranks; ++r)
    for (size_t pos = 0; pos < questions[r].size();) {
      uint64_t c;
      mpi::unpack(questions[r], pos, &c, 1);
      const auto it = std::lower_bound(own.begin(), own.end(), Pair(c, 0));
      if (it != own.end() && it->first == c) mpi::pack(answers[r], &*it, 1);
    }
  for (const auto& part : mpi::exchangeBytes(std::move(answers), comm))
    for (size_t pos = 0; pos < part.size();) {
      Pair p;
      mpi::unpack(part, pos, &p, 1);
      own.push_back(p);
    }
  std::sort(own.begin(), own.end());
  return own;
}
}  // namespace

std::vector<Pair> sortedPairs(const BrickWork& work) {
  std::vector<Pair> pairs(work.begin(), work.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<uint64_t> globalStartOf(uint64_t ownBricks, MPI_Comm comm) {
  const int ranks = mpi::size(comm);
  std::vector<uint64_t> counts(ranks), start(ranks + 1, 0);
  MPI_Allgather(&ownBricks, 1, MPI_UINT64_T, counts.data(), 1, MPI_UINT64_T, comm);
  for (int r = 0; r < ranks; ++r) start[r + 1] = start[r] + counts[r];
  return start;
}

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
  for (const auto& [code, w] : sortedPairs(work))
    layout.codes.push_back(code), layout.work.push_back(w);
  layout.setRuns(partitionWork(layout.work, ranks));
  return layout;
}

BrickLayout reduceBrickWork(const BrickWork& mine, const VoxelGrid& grid, uint64_t maxVoxels,
                            MPI_Comm comm) {
  // Sample sort: each brick's pairs go to the rank whose range of codes holds it, so that the
  // summed bricks come out sorted across ranks and no rank holds every brick.
  std::vector<Pair> pairs = sortedPairs(mine);
  const std::vector<uint64_t> splitters = splittersOf(pairs, comm);
  std::vector<std::vector<char>> out(mpi::size(comm));
  for (const Pair& p : pairs) {
    const size_t to =
        std::upper_bound(splitters.begin(), splitters.end(), p.first) - splitters.begin();
    mpi::pack(out[to], &p, 1);
  }
  std::vector<Pair>().swap(pairs);
  pairs = exchangePairs(std::move(out), comm);
  std::sort(pairs.begin(), pairs.end());
  pairs = summedPairs(pairs);
  checkVoxels(grid, "voxels needed near the surface:",
              static_cast<double>(totalOf(pairs.size(), comm)) * std::pow(grid.brick, 3),
              maxVoxels);
  return spreadSorted(std::move(pairs), grid, comm);
}

BrickLayout spreadSorted(std::vector<std::pair<uint64_t, uint64_t>> mine, const VoxelGrid& grid,
                         MPI_Comm comm, uint64_t brickCost) {
  uint64_t first = 0;
  const std::vector<uint64_t> start = cutsOf(mine, brickCost, comm, first);
  const std::vector<uint64_t> firstCodes = firstCodesOf(mine, start, first, comm);
  return directoryFromOwn(sendToOwners(std::move(mine), start, first, comm), firstCodes, grid,
                          comm);
}

BrickLayout directoryFromOwn(std::vector<std::pair<uint64_t, uint64_t>> own,
                             const std::vector<uint64_t>& firstCodes, const VoxelGrid& grid,
                             MPI_Comm comm) {
  std::vector<uint64_t> globalStart = globalStartOf(own.size(), comm);
  const std::vector<Pair> held = withBorder(std::move(own), firstCodes, mpi::rank(comm), comm);
  BrickLayout layout;
  layout.grid = grid;
  layout.codes.reserve(held.size());
  layout.work.reserve(held.size());
  for (const auto& [code, w] : held) layout.codes.push_back(code), layout.work.push_back(w);
  layout.firstCodes = firstCodes;
  layout.globalStart = std::move(globalStart);
  layout.rankStart = runsOf(layout.codes, firstCodes);
  memoryLedger().set(Held::brickList, layout.bytes());
  return layout;
}

}  // namespace rangefuse
