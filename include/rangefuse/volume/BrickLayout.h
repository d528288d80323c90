// Which bricks exist and which rank owns each (Morton order, contiguous equal-work runs).
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/volume/VoxelGrid.h"

namespace rangefuse {

using BrickCoord = Eigen::Vector3i;

namespace internal {

/// The low 21 bits of x, two zero bits after each.
inline uint64_t spreadBits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace internal

/// Morton code of a brick coordinate; coordinates must lie in [0, 2^21). Inline: asked at every
/// brick a prism or a control point reaches.
inline uint64_t mortonEncode(const BrickCoord& b) {
  using internal::spreadBits;
  return spreadBits(b.x()) | spreadBits(b.y()) << 1 | spreadBits(b.z()) << 2;
}
BrickCoord mortonDecode(uint64_t code);

/// Brick of voxel v (floor division by the brick size).
inline BrickCoord brickOf(const VoxelIndex& v, int brick) {
  return BrickCoord(floorDiv(v.x(), brick), floorDiv(v.y(), brick), floorDiv(v.z(), brick));
}

/// The bricks one rank knows and who owns every brick. Ranks own contiguous runs of Morton
/// codes. A rank's directory (what planning builds) holds its own bricks and the bricks
/// bordering them (their 26 neighbours that exist), so it grows with the rank's share, not the
/// job; a whole list (tests, one-process planning) holds every brick. Either way `rankStart`
/// splits the codes held by owner, and `firstCodes` answers the owner of any code.
struct BrickLayout {
  VoxelGrid grid;
  std::vector<uint64_t> codes;    ///< Morton-sorted
  std::vector<uint64_t> work;     ///< per brick: predicted cost (addPrismCost units)
  std::vector<size_t> rankStart;  ///< ranks + 1 entries: rank r owns [rankStart[r], rankStart[r+1])
  /// ranks + 1 entries, ascending: rank r owns every code in [firstCodes[r], firstCodes[r+1]).
  std::vector<uint64_t> firstCodes;
  /// ranks + 1 entries: rank r's bricks are [globalStart[r], globalStart[r+1]) of the whole
  /// Morton-sorted list (the checkpoint's rows).
  std::vector<uint64_t> globalStart;
  /// False when bricks may have joined other ranks beside this rank's since the directory was
  /// built (a growing field): then a neighbour it does not hold may still exist.
  bool borderKnown = true;

  /// Sets the runs of a whole list (`start` as partitionWork returns) and the ranges derived
  /// from them.
  void setRuns(std::vector<size_t> start);
  /// Position of a brick in `codes`, or -1 when this layout does not hold it.
  int64_t find(uint64_t code) const;
  /// Owner rank of the brick at position i.
  int ownerOf(size_t i) const;
  /// Owner rank of any code, held or not (the brick need not exist).
  int ownerOfCode(uint64_t code) const;
  /// The rank that would own brick `code`: its owner when held; -1 when this layout knows the
  /// brick does not exist (a whole list, or a code in `me`'s own range); otherwise the owner of
  /// its range, which may not hold it.
  int mayOwn(uint64_t code, int me) const;
  /// The owner of brick `code` bordering one of rank me's bricks, or -1 when it does not
  /// exist (or me owns it): exact while borderKnown, else mayOwn's answer.
  int neighbourOwner(uint64_t code, int me) const;
  int ranks() const { return static_cast<int>(rankStart.size()) - 1; }
  /// Bricks of the whole field, on every rank.
  uint64_t totalBricks() const { return globalStart.empty() ? codes.size() : globalStart.back(); }
  /// True when this layout holds every brick (not a rank's directory).
  bool whole() const { return totalBricks() == codes.size(); }
  /// Bytes its lists hold.
  uint64_t bytes() const;
};

/// Cuts the Morton-sorted bricks into `ranks` contiguous runs of near-equal work.
std::vector<size_t> partitionWork(const std::vector<uint64_t>& work, int ranks);

/// Positions in sorted `codes` where each rank's range (firstCodes) starts; ranks + 1 entries.
std::vector<size_t> runsOf(const std::vector<uint64_t>& codes,
                           const std::vector<uint64_t>& firstCodes);

/// Rank `me`'s directory taken from a whole list: its bricks and those bordering them.
BrickLayout directoryOf(const BrickLayout& whole, int me);

/// The codes of the 26 neighbours of brick `code` that lie in the lattice.
std::vector<uint64_t> neighbourCodes(uint64_t code);

}  // namespace rangefuse
