// The voxel data of the bricks one rank owns: weighted sums of distance and gradient.
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/volume/BrickLayout.h"
#include "rangefuse/volume/CodeIndex.h"

namespace rangefuse {

/// Running sums of Tubic Eqs. 11-12 for one voxel.
struct VoxelSums {
  float wd = 0;
  float w = 0;
  float wf[3] = {0, 0, 0};
  float images = 0;  ///< images that contributed (registration asks for overlap)

  /// Adds one image's sample: distance d, weight c (its confidence), unit gradient f.
  void add(float d, float c, const float f[3]) {
    wd += c * d;
    w += c;
    for (int k = 0; k < 3; ++k) wf[k] += c * f[k];
    images += 1;
  }
  /// Adds the sums of other images.
  VoxelSums& operator+=(const VoxelSums& o) {
    wd += o.wd, w += o.w, images += o.images;
    for (int k = 0; k < 3; ++k) wf[k] += o.wf[k];
    return *this;
  }
};

class BrickStore {
 public:
  using Sums = std::vector<VoxelSums>;

  /// Keeps its own copy of the layout (a rank's directory: small next to the voxels).
  BrickStore(const BrickLayout& layout, int rank);

  const BrickLayout& layout() const { return layout_; }
  const VoxelGrid& grid() const { return layout_.grid; }
  size_t brickCount() const { return codes_.size(); }
  uint64_t code(size_t local) const { return codes_[local]; }
  /// Whether local bricks follow code order (always, until grow(); again after sortBricks()).
  bool ordered() const { return ordered_; }
  size_t voxelsPerBrick() const { return perBrick_; }

  /// Local brick index of a Morton code, or -1 when this rank does not own it.
  int64_t localBrick(uint64_t code) const { return index_.find(code); }
  /// Flat offset of voxel v (which must lie in local brick b) into sums().
  size_t offset(size_t b, const VoxelIndex& v) const;
  /// The same, when the caller knows v's brick coordinate already (saves decoding the code).
  size_t offset(size_t b, const BrickCoord& brick, const VoxelIndex& v) const {
    const int B = layout_.grid.brick;
    const VoxelIndex l = v - brick * B;
    return b * perBrick_ + (static_cast<size_t>(l.z()) * B + l.y()) * B + l.x();
  }

  /// Adds to the work of the brick at layout position `at`: work only steers how the next
  /// layout is split, never which bricks exist or what they hold.
  void addWork(size_t at, uint64_t work) { layout_.work[at] += work; }
  /// Takes 1/2^shift off every brick's work (rounded down), so that recent work outweighs old.
  void decayWork(int shift) {
    for (uint64_t& w : layout_.work) w -= w >> shift;
  }

  Sums& sums() { return sums_; }
  const Sums& sums() const { return sums_; }

  /// Gives every voxel a colour of `kind` beside its sums (6 bytes more a voxel; none until
  /// asked).
  void enableColour(ColourKind kind);
  bool hasColour() const { return colourKind_ != ColourKind::none; }
  ColourKind colourKind() const { return colourKind_; }
  /// One per voxel, in the sums' order, when hasColour().
  std::vector<VoxelColour>& colours() { return colours_; }
  const std::vector<VoxelColour>& colours() const { return colours_; }

  /// Takes `layout`, a superset of this one on the same lattice in which this rank's run holds
  /// its old bricks and `fresh` (new codes): their sums start at zero after the old ones, which
  /// stay where they are, so a field grows without moving (amortised over the vector's
  /// doubling). Local indices then no longer follow code order.
  void grow(const BrickLayout& layout, const std::vector<uint64_t>& fresh);
  /// Takes `layout`, a new split of the same lattice's bricks: the local bricks it gives other
  /// ranks leave (the last local bricks take their places) and `arriving` (codes this rank did
  /// not hold) join with zero sums after them. The bricks that stay keep their sums in place,
  /// so a split costs the bricks that move, not the whole field. Local order then no longer
  /// follows code order.
  void rehome(const BrickLayout& layout, const std::vector<uint64_t>& arriving);
  /// Puts the local bricks back in code order, in place (one brick of scratch).
  void sortBricks();
  /// Bytes of the local bricks: sums, colours, codes and their index (not the layout).
  uint64_t bytes() const;

 private:
  BrickLayout layout_;
  std::vector<uint64_t> codes_;
  internal::CodeIndex index_;
  int rank_;
  size_t perBrick_;
  bool ordered_ = true;
  ColourKind colourKind_ = ColourKind::none;
  Sums sums_;
  std::vector<VoxelColour> colours_;
};

}  // namespace rangefuse
