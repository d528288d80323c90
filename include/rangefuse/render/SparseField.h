// Fused-field bricks held by one rank for pictures: gathered, or its own and their neighbours.
#pragma once

#include <mpi.h>

#include <functional>
#include <optional>
#include <unordered_map>
#include <vector>

#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

/// Bounds, in world units, of the voxel centres of the given bricks.
Eigen::AlignedBox3d brickBounds(const VoxelGrid& grid, const std::vector<uint64_t>& codes);

class SparseField {
 public:
  SparseField(const VoxelGrid& grid, float minWeight) : grid_(grid), minWeight_(minWeight) {}

  /// Collective: every rank's bricks that `keep` accepts (null: all), on `root` (elsewhere the
  /// field is empty). Its bounds are those of all bricks, kept or not.
  static SparseField gather(const BrickStore& store, float minWeight, int root, MPI_Comm comm,
                            const std::function<bool(const BrickCoord&)>& keep = nullptr);

  /// Collective: this rank's bricks and every existing brick next to one of them (26
  /// neighbours), whoever owns it: what a ray needs to be followed through this rank's bricks.
  static SparseField withNeighbours(const BrickStore& store, float minWeight, MPI_Comm comm);

  /// A brick's sums and, when the field has colour, its voxels' colours (else empty).
  void addBrick(uint64_t code, std::vector<VoxelSums> sums, std::vector<VoxelColour> colours = {});
  const VoxelGrid& grid() const { return grid_; }
  /// Bounds of the existing bricks (of the whole layout when gathered), world units.
  Eigen::AlignedBox3d bounds() const;
  bool hasBrick(const BrickCoord& b) const { return bricks_.count(mortonEncode(b)) > 0; }

  /// Calls f(centre, sums) for every observed voxel (weight above minWeight), brick by brick.
  void forEachVoxel(const std::function<void(const Eigen::Vector3d&, const VoxelSums&)>& f) const;
  /// Voxel sums, or nullptr where unobserved (no brick, or weight not above minWeight).
  const VoxelSums* voxel(const VoxelIndex& v) const;
  /// Trilinear distance at p; false when a surrounding voxel is unobserved.
  bool distance(const Eigen::Vector3d& p, double& d) const;
  /// Unit gradient at the voxel nearest to p (Tubic §4.7); zero when unobserved.
  Eigen::Vector3d gradient(const Eigen::Vector3d& p) const;
  /// The fused colour at the voxel nearest to p; nullopt when the field has none there.
  std::optional<Colour> colour(const Eigen::Vector3d& p) const;

 private:
  VoxelGrid grid_;
  float minWeight_;
  std::unordered_map<uint64_t, std::vector<VoxelSums>> bricks_;
  std::unordered_map<uint64_t, std::vector<VoxelColour>> colours_;  ///< coloured fields only
  Eigen::AlignedBox3d frame_;  ///< bounds of the whole layout, when set
};

}  // namespace rangefuse
