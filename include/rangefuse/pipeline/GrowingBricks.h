// Bricks that grow as placed scans join a field (private to the fuse stage): the tracking
// field and registration's growing field both add each scan's new bricks where they are
// owned, without moving the sums already held.
#pragma once

#include <mpi.h>

#include <memory>
#include <vector>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/route/ScanRouting.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse::internal {

/// A field's store, grown a scan at a time, and the integrator adding to it. A brick new to
/// the field joins the rank whose range of codes holds it, and every sum stays where it is,
/// so a voxel's sums are those of adding the scans in order on any number of ranks. The bricks
/// are split by their recent work (voxel updates) anew, the sums of those that change owner moving,
/// when a rank has gained half a fair share of bricks since the last split, or when the ranks'
/// voxel updates over the last scans drift apart: a stream's next frames fall where its last ones
/// did.
class GrowingBricks {
 public:
  /// Bricks on `grid`, at most maxVoxels voxels; planning and adding use `threads`.
  GrowingBricks(const VoxelGrid& grid, uint64_t maxVoxels, int threads, MPI_Comm comm);
  ~GrowingBricks();

  /// Starts with no bricks, every code in rank 0's range until the first split.
  void startEmpty(ColourKind colour);
  /// Starts with the bricks of a planned layout (already split).
  void start(const BrickLayout& layout);
  /// Collective: adds a scan placed in the world (on the rank that read it, which gives it up;
  /// null on the others). It is routed to the owners of the ranges of codes its prisms reach;
  /// each owner joins the bricks of its range that its part reaches and adds the part, each
  /// brick's work growing by the voxel updates it took (measured, they split the ranks' updates
  /// more evenly than a prediction did on real frames); then the bricks are split anew if due.
  /// Throws InputError on every rank past maxVoxels.
  IntegrationStats add(PrismScan* placed);
  /// The integrator on the store, made at first use; it follows the store as it grows and as
  /// its bricks are split anew.
  PrismIntegrator& integrator();
  BrickStore& store() { return *store_; }
  const BrickStore& store() const { return *store_; }
  bool empty() const { return !store_; }
  /// Times the bricks were split anew since the start.
  uint64_t splits() const { return splits_; }
  /// Collective: the store in code order, its directory knowing the bricks that border its
  /// own; the growth is empty afterwards.
  std::unique_ptr<BrickStore> release();

 private:
  /// Collective: joins the bricks of this rank's range that `part`'s prisms reach (this rank's
  /// routed part of a scan, or null): those routing listed in every rank's `reached`, or
  /// without it (a lone rank), those found from the part's prisms.
  void growBy(const PrismScan* part, ReachedBricks* reached);
  /// Adds `part` to the field, and to each brick's work the voxel updates it took.
  IntegrationStats addCounted(const PrismScan& part);
  /// Collective: splits the bricks by their work anew when a rank has gained half a fair
  /// share of bricks or the ranks' updates drifted apart (drifted()); true when they moved.
  bool splitIfDue();
  /// Collective: counts a scan, and every kCheckEvery scans tells whether the ranks' voxel
  /// updates since the last check drifted apart.
  bool drifted();
  /// True when the bricks, as `start` splits them, should be split by work anew.
  bool needsSplit(const std::vector<uint64_t>& start) const;

  VoxelGrid grid_;
  uint64_t maxVoxels_;
  int threads_;
  MPI_Comm comm_;
  std::unique_ptr<BrickStore> store_;
  std::unique_ptr<PrismIntegrator> integrator_;
  std::vector<uint64_t> balancedAt_;  ///< every rank's first brick when last split by work
  uint64_t scansSinceCheck_ = 0, updatesSinceCheck_ = 0;  ///< since drifted() last compared
  uint64_t splits_ = 0;
};

}  // namespace rangefuse::internal
