// Which bricks a field needs and who owns them: planned from boxes (one per prism), summed
// across ranks, split in Morton order into runs of equal work.
#pragma once

#include <mpi.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <unordered_map>

#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse {

/// Per brick (Morton code), its work: the predicted cost of the boxes touching it.
using BrickWork = std::unordered_map<uint64_t, uint64_t>;

/// The lattice around `box`: voxel `voxel`, bricks of `brick` voxels, origin a whole number of
/// bricks, `margin` bricks below the box grown by eps. Throws InputError when one axis would
/// need more voxels than vertex keys can name.
VoxelGrid gridAround(const Eigen::AlignedBox3d& box, double voxel, int brick, double eps,
                     int margin = 1);

/// True when `box` grown by eps lies a brick inside the lattice (gridAround's guarantee).
bool gridHoldsBox(const VoxelGrid& grid, const Eigen::AlignedBox3d& box, double eps);

/// Bricks [lo, hi] holding the voxel centres inside box; false when it holds none. Inline:
/// routing asks it for every triangle.
inline bool bricksOfBox(const VoxelGrid& grid, const Eigen::AlignedBox3d& box, BrickCoord& lo,
                        BrickCoord& hi) {
  VoxelIndex vlo, vhi;
  grid.voxelRange(box, vlo, vhi);
  if ((vlo.array() > vhi.array()).any()) return false;
  lo = brickOf(vlo, grid.brick);
  hi = brickOf(vhi, grid.brick);
  return true;
}

/// Adds the work of `part` (planned apart, e.g. on another thread) to `work`; refuses the sum
/// as addBrickWork does.
void addWork(const BrickWork& part, const VoxelGrid& grid, uint64_t maxVoxels, BrickWork& work);

/// Adds `count` to the work of every brick in [lo, hi]. Throws InputError, before the map
/// grows, when the bricks would hold more than maxVoxels voxels.
void addBrickWork(const VoxelGrid& grid, const BrickCoord& lo, const BrickCoord& hi, uint64_t count,
                  uint64_t maxVoxels, BrickWork& work);

/// The (code, work) pairs of `work`, sorted by code.
std::vector<std::pair<uint64_t, uint64_t>> sortedPairs(const BrickWork& work);

/// Collective: where each rank's rows start in the whole Morton-sorted brick list (ranks + 1
/// entries), from the number of bricks each rank owns.
std::vector<uint64_t> globalStartOf(uint64_t ownBricks, MPI_Comm comm);

/// The bricks of `work`, Morton-sorted and split over `ranks` runs of near-equal work.
BrickLayout layoutFromWork(const BrickWork& work, const VoxelGrid& grid, int ranks);

/// Collective: this rank's directory of every rank's work summed (a brick's work is an integer
/// sum, so the layout does not depend on how the boxes were spread over ranks). No rank sees
/// another's boxes nor every brick: the pairs are sorted across ranks by code (sample sort),
/// summed where they land, cut into runs by the work before them, and sent to their owners,
/// which then ask for the bricks bordering theirs. Throws InputError past maxVoxels on every
/// rank.
BrickLayout reduceBrickWork(const BrickWork& mine, const VoxelGrid& grid, uint64_t maxVoxels,
                            MPI_Comm comm);

/// Collective: this rank's directory of the (code, work) pairs every rank holds, given sorted
/// and in rank order (every code of rank r below every code of rank r + 1, none twice): cut as
/// partitionWork cuts the whole list, whatever the number of parts it came in. `brickCost` is
/// added to every brick's work for the cut only (the layout keeps the work as given).
BrickLayout spreadSorted(std::vector<std::pair<uint64_t, uint64_t>> mine, const VoxelGrid& grid,
                         MPI_Comm comm, uint64_t brickCost = 0);

/// Collective: rank me's directory from its own (code, work) pairs, sorted and inside its
/// range of `firstCodes`: the bricks bordering them asked of their owners, every rank's bricks
/// counted.
BrickLayout directoryFromOwn(std::vector<std::pair<uint64_t, uint64_t>> own,
                             const std::vector<uint64_t>& firstCodes, const VoxelGrid& grid,
                             MPI_Comm comm);

}  // namespace rangefuse
