#include "HoleFilling.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"

namespace rangefuse::internal {
namespace {

/// Voxel centres of the lattice [first, first + side)^3 (x fastest) and their box.
std::vector<Eigen::Vector3d> latticeCentres(const VoxelGrid& grid, const VoxelIndex& first,
                                            int side, Eigen::AlignedBox3d& box) {
  std::vector<Eigen::Vector3d> p;
  p.reserve(static_cast<size_t>(side) * side * side);
  for (int z = 0; z < side; ++z)
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) p.push_back(grid.centre(first + VoxelIndex(x, y, z)));
  box =
      Eigen::AlignedBox3d(grid.centre(first), grid.centre(first + VoxelIndex::Constant(side - 1)));
  return p;
}

}  // namespace

void fillRegion(const BrickLayout& layout, MPI_Comm comm, BrickCoord& lo, BrickCoord& hi) {
  const int me = mpi::rank(comm);
  int box[6] = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};  // lo, -hi
  for (size_t b = layout.rankStart[me]; b < layout.rankStart[me + 1]; ++b) {
    const BrickCoord c = mortonDecode(layout.codes[b]);
    for (int a = 0; a < 3; ++a)
      box[a] = std::min(box[a], c[a]), box[3 + a] = std::min(box[3 + a], -c[a]);
  }
  MPI_Allreduce(MPI_IN_PLACE, box, 6, MPI_INT, MPI_MIN, comm);
  for (int a = 0; a < 3; ++a) {
    lo[a] = box[a] == INT32_MAX ? 1 : std::max(0, box[a] - 1);
    hi[a] = box[a] == INT32_MAX ? 0 : -box[3 + a] + 1;
  }
}

std::vector<uint8_t> carveBrick(uint64_t code, const VoxelGrid& grid, const HoleFill& fill,
                                std::vector<float>& values) {
  std::vector<uint8_t> carved(values.size(), 0);
  if (std::none_of(values.begin(), values.end(), [](float v) { return std::isnan(v); }))
    return carved;
  Eigen::AlignedBox3d box;
  const std::vector<Eigen::Vector3d> centres =
      latticeCentres(grid, mortonDecode(code) * grid.brick, grid.brick, box);
  const std::vector<uint8_t> in = fill.inside(box, centres);
  for (size_t i = 0; i < values.size(); ++i)
    if (std::isnan(values[i])) values[i] = in[i] ? -fill.value : fill.value, carved[i] = 1;
  return carved;
}

std::map<uint64_t, std::vector<float>> fillBricks(const BrickLayout& layout, const BrickCoord& lo,
                                                  const BrickCoord& hi, const HoleFill& fill,
                                                  int me, int threads) {
  std::vector<uint64_t> codes;
  BrickCoord c;
  for (c.z() = lo.z(); c.z() <= hi.z(); ++c.z())
    for (c.y() = lo.y(); c.y() <= hi.y(); ++c.y())
      for (c.x() = lo.x(); c.x() <= hi.x(); ++c.x()) {
        const uint64_t code = mortonEncode(c);
        if (layout.ownerOfCode(code) == me && layout.find(code) < 0) codes.push_back(code);
      }
  std::sort(codes.begin(), codes.end());
  const int B = layout.grid.brick;
  std::vector<std::vector<float>> values(codes.size());
  parallelFor(codes.size(), threads, [&](size_t k) {
    // The brick's cubes read the first layer of its upper neighbours: (B + 1)^3 centres.
    Eigen::AlignedBox3d box;
    const std::vector<Eigen::Vector3d> centres =
        latticeCentres(layout.grid, mortonDecode(codes[k]) * B, B + 1, box);
    const std::vector<uint8_t> in = fill.inside(box, centres);
    if (std::none_of(in.begin(), in.end(), [](uint8_t v) { return v != 0; })) return;
    std::vector<float>& v = values[k];
    v.reserve(static_cast<size_t>(B) * B * B);
    for (int z = 0; z < B; ++z)
      for (int y = 0; y < B; ++y)
        for (int x = 0; x < B; ++x)
          v.push_back(in[(static_cast<size_t>(z) * (B + 1) + y) * (B + 1) + x] ? -fill.value
                                                                               : fill.value);
  });
  std::map<uint64_t, std::vector<float>> out;
  for (size_t k = 0; k < codes.size(); ++k)
    if (!values[k].empty()) out[codes[k]] = std::move(values[k]);
  return out;
}

BrickLayout withFillBricks(const BrickLayout& layout,
                           const std::map<uint64_t, std::vector<float>>& fill) {
  BrickLayout out = layout;
  for (const auto& entry : fill) out.codes.push_back(entry.first);
  std::sort(out.codes.begin(), out.codes.end());
  out.work.assign(out.codes.size(), 0);
  out.rankStart = runsOf(out.codes, out.firstCodes);
  out.borderKnown = false;
  return out;
}

}  // namespace rangefuse::internal
