// A growing field split over the ranks against the same scans grown on one rank, voxel by
// voxel: routing each scan to the owners of the ranges it reaches, the owners joining its new
// bricks, and the splits by recent work that move bricks between ranks must leave every sum
// as adding the scans in order on one rank does.
#include <gtest/gtest.h>

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
  return g;
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
  if (mpi::size(MPI_COMM_WORLD) > 1) {
    // The walk moves the work from rank to rank: the bricks were split, and sums moved, more
    // than once, and every rank ends up holding some.
    EXPECT_GE(split.splits, 3u);
    EXPECT_GT(split.bricks, 0u);
  }
}

}  // namespace
}  // namespace rangefuse
