// Which bricks exist and which rank owns each (Morton order, contiguous equal-work runs).
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/volume/VoxelGrid.h"

namespace rangefuse {

using BrickCoord = Eigen::Vector3i;

/// Morton code of a brick coordinate; coordinates must lie in [0, 2^21).
uint64_t mortonEncode(const BrickCoord& b);
BrickCoord mortonDecode(uint64_t code);

/// Brick of voxel v (floor division by the brick size).
inline BrickCoord brickOf(const VoxelIndex& v, int brick) {
  return BrickCoord(floorDiv(v.x(), brick), floorDiv(v.y(), brick), floorDiv(v.z(), brick));
}

/// The global, rank-independent list of existing bricks and their owners.
struct BrickLayout {
  VoxelGrid grid;
  std::vector<uint64_t> codes;    ///< Morton-sorted
  std::vector<uint64_t> work;     ///< per brick: predicted cost (addPrismCost units)
  std::vector<size_t> rankStart;  ///< ranks + 1 entries: rank r owns [rankStart[r], rankStart[r+1])

  /// Position of a brick in `codes`, or -1 when it does not exist.
  int64_t find(uint64_t code) const;
  /// Owner rank of brick at position i.
  int ownerOf(size_t i) const;
  int ranks() const { return static_cast<int>(rankStart.size()) - 1; }
  /// Bytes its lists hold.
  uint64_t bytes() const;
};

/// Cuts the Morton-sorted bricks into `ranks` contiguous runs of near-equal work.
std::vector<size_t> partitionWork(const std::vector<uint64_t>& work, int ranks);

}  // namespace rangefuse
