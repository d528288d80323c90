// Robust fusion at prism cost: per voxel, a few surface hypotheses built from the images'
// prism samples in scan order; a hypothesis stays if enough images agree on it, or if no other
// image looked through it (docs/robust.md).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "rangefuse/robust/SightMap.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

struct HypothesisParams {
  double sameDistance = 0;  ///< samples this close in d (world units) are one surface ...
  double sameCosine = 0.7;  ///< ... when their gradients agree to this cosine
  int minViews = 2;         ///< images that make a hypothesis stand on agreement alone
  double freeMargin = 0;    ///< an image looked through a point this far before its surface
                            ///< (infinite: free space off, minViews alone decides)
};

/// What resolving decided, over this rank's voxels.
struct HypothesisStats {
  uint64_t agreed = 0;     ///< voxels with a hypothesis minViews images or more agree on
  uint64_t unopposed = 0;  ///< voxels with none, but one that no other image looked through
  uint64_t removed = 0;    ///< voxels left empty: no hypothesis stood (or all outvoted)
};

/// Up to kSlots hypotheses per voxel of a brick store, each a weighted sum like VoxelSums and,
/// when the store has colour, a colour mean of its own. The first lives in the store's own sums
/// and colours (most voxels never have another); the others in blocks allocated per brick the
/// first time one of its voxels needs them.
class SurfaceHypotheses {
 public:
  static constexpr int kSlots = 3;
  /// Agreed hypotheses of this many images or more stand without the free-space vote.
  static constexpr int kVoteViews = 8;

  SurfaceHypotheses(BrickStore& store, const HypothesisParams& params);
  ~SurfaceHypotheses();
  SurfaceHypotheses(const SurfaceHypotheses&) = delete;
  SurfaceHypotheses& operator=(const SurfaceHypotheses&) = delete;

  /// One image's sample at voxel `at` (images come in scan order): joins the hypothesis it
  /// agrees with (within sameDistance, or three deviations of its noise `sigma` if more), or
  /// opens one; with every slot taken it replaces the lightest hypothesis if it
  /// weighs more. Samples of weight 0 carry no evidence and are skipped. Threads may add to
  /// different voxels at once. `colour` (null when the store has none) joins the colour mean
  /// of the same hypothesis, so an outlier's colour leaves with the outlier.
  void add(size_t at, float d, float w, const float f[3], float sigma = 0,
           const Colour* colour = nullptr);

  /// Writes into the store's sums, per voxel, the sum of the hypotheses that stand (those
  /// minViews images agree on, and those fewer saw but no other image looked through) and
  /// face the same way as the nearest of them; sums are cleared where none stands. The voxel's
  /// colour becomes the weighted mean of the colours of the hypotheses summed. `sights`:
  /// every image's map. Bricks are shared among `threads`.
  HypothesisStats resolve(const std::vector<SightMap>& sights, int threads = 1);

  /// Bytes held besides the store's sums and colours (the blocks of second and third
  /// hypotheses).
  uint64_t extraBytes() const;

 private:
  using Extra = std::array<VoxelSums, kSlots - 1>;
  using ExtraColour = std::array<VoxelColour, kSlots - 1>;

  /// The extra slots of voxel `at`, allocated if `create`; null when none and !create.
  Extra* extras(size_t at, bool create);
  /// Their colours, allocated with them when the store has colour.
  ExtraColour* extraColours(size_t at, bool create);
  /// The voxel's colour: the mean of the standing hypotheses' colours, by their weights.
  /// `own` is the first's colour, `extra` the others' (null: the voxel had only one).
  static VoxelColour mergedColour(const VoxelColour& own, const ExtraColour* extra,
                                  const bool* summed, const VoxelSums* h);
  HypothesisStats resolveBrick(size_t b, const std::vector<SightMap>& sights);
  /// How many images looked through the hypothesis' surface point (free space), counted up
  /// to `enough`.
  int lookedThrough(const VoxelSums& h, const Eigen::Vector3d& centre,
                    const std::vector<SightMap>& sights, int enough) const;
  /// Whether the hypothesis stands: seen by fewer than minViews images, when no other image
  /// looked through it; agreed on, unless as many images looked through it as saw it (tested
  /// below kVoteViews images).
  bool stands(const VoxelSums& h, const Eigen::Vector3d& centre,
              const std::vector<SightMap>& sights) const;
  /// The sums a voxel keeps (false: none stands); `agreed` when an agreed hypothesis is in.
  /// `summed[k]` tells whether hypothesis k is in.
  bool merge(const VoxelSums* h, const Eigen::Vector3d& centre, const std::vector<SightMap>& sights,
             VoxelSums& kept, bool* summed, bool& agreed) const;

  BrickStore& store_;
  HypothesisParams params_;
  std::vector<std::atomic<Extra*>> blocks_;  ///< per local brick: voxelsPerBrick Extras, or null
  std::vector<std::atomic<ExtraColour*>> colourBlocks_;  ///< the same for colours (when any)
};

}  // namespace rangefuse
