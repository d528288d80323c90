// A growing field split over the ranks against the same scans grown on one rank, voxel by
// voxel: routing each scan to the owners of the ranges it reaches, the owners joining its new
// bricks, and the splits by recent work that move bricks between ranks must leave every sum
// as adding the scans in order on one rank does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../common/GridScan.h"
#include "ObservedVoxels.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/GrowingBricks.h"
#include "rangefuse/surface/ScanSurface.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse {
namespace {

constexpr double kVoxel = 0.25;

/// A wavy patch of 24 x 18 points a voxel apart, its corner at `corner`: one frame of a
/// camera sliding along the surface, so that each frame brings new bricks and moves the work.
PrismScan patch(const Eigen::Vector3d& corner) {
  return test::gridScan(24, 18, 1.5 * kVoxel, [&](int x, int y) {
    const Eigen::Vector3d p(x * 0.25, y * 0.25, std::sin((corner.x() + x * 0.25) * 0.7));
    return Eigen::Vector3d(corner + p);
  });
}

std::vector<PrismScan> walk() {
  std::vector<PrismScan> frames;
  for (int k = 0; k < 40; ++k)
    frames.push_back(patch(Eigen::Vector3d(0.6 * k, 1.5 * std::sin(k * 0.3), 20)));
  return frames;
}

/// The frames grown into a field over `comm`, frame k read by rank k mod ranks.
struct Grown {
  test::VoxelValues voxels;
  uint64_t splits = 0, bricks = 0;
  std::vector<uint64_t> codes;  ///< every rank's bricks, sorted
};

Grown grow(const std::vector<PrismScan>& frames, const VoxelGrid& grid, MPI_Comm comm) {
  const int ranks = mpi::size(comm), me = mpi::rank(comm);
  internal::GrowingBricks field(grid, uint64_t{1} << 40, 1, comm);
  field.startEmpty(ColourKind::none);
  for (size_t k = 0; k < frames.size(); ++k) {
    PrismScan placed = frames[k];
    field.add(static_cast<int>(k % ranks) == me ? &placed : nullptr);
  }
  Grown g;
  g.splits = field.splits();
  g.bricks = field.store().brickCount();
  g.voxels = test::observedVoxels(field.store(), comm);
  std::vector<char> mine;
  for (size_t b = 0; b < field.store().brickCount(); ++b) {
    const uint64_t code = field.store().code(b);
    mpi::pack(mine, &code, 1);
  }
  for (const std::vector<char>& bytes : mpi::allgatherBytes(mine, comm)) {
    const size_t at = g.codes.size(), n = bytes.size() / sizeof(uint64_t);
    g.codes.resize(at + n);
    size_t pos = 0;
    mpi::unpack(bytes, pos, g.codes.data() + at, n);
  }
  std::sort(g.codes.begin(), g.codes.end());
  return g;
}

/// The bricks the frames' prisms reach, found prism by prism.
std::vector<uint64_t> bricksReached(const std::vector<PrismScan>& frames, const VoxelGrid& grid) {
  std::vector<uint64_t> codes;
  for (const PrismScan& f : frames)
    for (size_t t = 0; t < f.surface.triangles.size(); ++t) {
      BrickCoord lo, hi, b;
      if (!bricksOfBox(grid, prismBounds(scanPrism(f, t)), lo, hi)) continue;
      for (b.z() = lo.z(); b.z() <= hi.z(); ++b.z())
        for (b.y() = lo.y(); b.y() <= hi.y(); ++b.y())
          for (b.x() = lo.x(); b.x() <= hi.x(); ++b.x()) codes.push_back(mortonEncode(b));
    }
  std::sort(codes.begin(), codes.end());
  codes.erase(std::unique(codes.begin(), codes.end()), codes.end());
  return codes;
}

TEST(GrowingBricks, SplitOverTheRanksGivesTheOneRankSumsBitForBit) {
  const std::vector<PrismScan> frames = walk();
  Eigen::AlignedBox3d box;
  for (const PrismScan& f : frames)
    for (const Eigen::Vector3d& p : f.surface.points) box.extend(p);
  const VoxelGrid grid = gridAround(box, kVoxel, 4, 1.5 * kVoxel);
  const Grown alone = grow(frames, grid, MPI_COMM_SELF);
  const Grown split = grow(frames, grid, MPI_COMM_WORLD);
  EXPECT_GT(alone.voxels.size(), 5000u);
  test::expectIdentical(alone.voxels, split.voxels);
  // The bricks joined are those the prisms reach: found by routing on several ranks (decision
  // 57), from the parts' prisms on one.
  const std::vector<uint64_t> reached = bricksReached(frames, grid);
  EXPECT_EQ(alone.codes, reached);
  EXPECT_EQ(split.codes, reached);
  if (mpi::size(MPI_COMM_WORLD) > 1) {
    // The walk moves the work from rank to rank: the bricks were split, and sums moved, more
    // than once, and every rank ends up holding some.
    EXPECT_GE(split.splits, 3u);
    EXPECT_GT(split.bricks, 0u);
  }
}

}  // namespace
}  // namespace rangefuse
