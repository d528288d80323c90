// The whole fused field on one rank, for pictures: bricks gathered from every rank.
#pragma once

#include <mpi.h>

#include <unordered_map>
#include <vector>

#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

class SparseField {
 public:
  SparseField(const VoxelGrid& grid, float minWeight) : grid_(grid), minWeight_(minWeight) {}

  /// Collective: every rank's bricks, on `root` (elsewhere the field is empty).
  static SparseField gather(const BrickStore& store, float minWeight, int root, MPI_Comm comm);

  void addBrick(uint64_t code, std::vector<VoxelSums> sums);
  const VoxelGrid& grid() const { return grid_; }
  /// Bounds of the existing bricks, world units.
  Eigen::AlignedBox3d bounds() const;
  bool hasBrick(const BrickCoord& b) const { return bricks_.count(mortonEncode(b)) > 0; }

  /// Voxel sums, or nullptr where unobserved (no brick, or weight not above minWeight).
  const VoxelSums* voxel(const VoxelIndex& v) const;
  /// Trilinear distance at p; false when a surrounding voxel is unobserved.
  bool distance(const Eigen::Vector3d& p, double& d) const;
  /// Unit gradient at the voxel nearest to p (Tubic §4.7); zero when unobserved.
  Eigen::Vector3d gradient(const Eigen::Vector3d& p) const;

 private:
  VoxelGrid grid_;
  float minWeight_;
  std::unordered_map<uint64_t, std::vector<VoxelSums>> bricks_;
};

}  // namespace rangefuse
