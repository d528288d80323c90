// Prism fields of whole scans added into the distributed bricks (Tubic Eqs. 11-13).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/prism/PrismRaster.h"
#include "rangefuse/robust/SightMap.h"
#include "rangefuse/robust/SurfaceHypotheses.h"
#include "rangefuse/surface/RangeNoise.h"
#include "rangefuse/surface/ScanSurface.h"
#include "rangefuse/volume/BrickPlanning.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

/// Per triangle of a scan, the [dMin, dMax] of its prism with envelope `eps` (Eqs. 9-10).
/// Computed once per scan (by the rank that read it) and shared.
using PrismLimits = std::vector<std::array<double, 2>>;
PrismLimits computePrismLimits(const ScanSurface& scan, double eps);

/// A scan's surface together with its prism limits: what the field stages need.
struct PrismScan {
  ScanSurface surface;
  PrismLimits limits;
  std::shared_ptr<SightMap> sight;  ///< what the scan saw (robust fusion; else null)
  RangeNoise noise;  ///< the grid's depth noise as read (empty for bands of a station)
  /// Set (a streamed field's scans, compactScan): its points lie on a lattice of its own,
  /// origin + n * quantum for 24- or 32-bit n, its normals and confidences are the values of
  /// 32- and 16-bit codes and its limits floats', so routing packs them in a third of the
  /// bytes and loses nothing (decisions 45, 58).
  double quantum = 0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  bool compact() const { return quantum > 0; }
};

/// The prism of triangle `t` of a scan.
Prism scanPrism(const PrismScan& scan, size_t t);

/// Bounds of a scan's points.
Eigen::AlignedBox3d pointBounds(const PrismScan& scan);

/// A lattice whose origin is a multiple of the brick size `margin` bricks below every prism, so
/// that all voxel and brick indices are non-negative. Throws InputError if the grid is too large.
VoxelGrid fitGrid(const std::vector<PrismScan>& scans, double voxel, int brick, double eps,
                  int margin = 1);

/// True when every prism of the scans lies at least a brick inside the lattice (fitGrid's
/// guarantee), so that the scans can be added to a field on this grid.
bool gridHolds(const VoxelGrid& grid, const std::vector<PrismScan>& scans, double eps);

/// Work units of one voxel update in a brick's work: the cost model keeps fractions of an
/// update as integers, whose sums are the same in any order (the cut, on any rank count).
constexpr double kWorkPerUpdate = 16;
/// A prism's set-up (bounds, row spans, feet's cubic) costs about as much as this many voxel
/// updates (fitted over merge factors 0.5-3 on a depth sequence: 320 ns a prism, 60 ns an
/// update; docs/distributed.md).
constexpr double kPrismSetupUpdates = 5;

/// The voxel updates a prism is expected to make: the voxel centres within its volume (the
/// triangle's area times the prism's extent across the envelope, in voxels).
double expectedUpdates(const Prism& prism, double voxel);

/// Adds a prism's predicted cost (`setupUpdates` and its expected updates, in kWorkPerUpdate
/// units) to the bricks its bounding box touches, shared as the box's voxels are; every such
/// brick enters `work`. Throws InputError as addBrickWork does.
void addPrismCost(const Prism& prism, const VoxelGrid& grid, uint64_t maxVoxels, BrickWork& work,
                  double setupUpdates = kPrismSetupUpdates);

/// Adds the predicted cost of every prism of the scan (addPrismCost), with the triangles shared
/// among `threads`.
void addPrismWork(const PrismScan& scan, const VoxelGrid& grid, uint64_t maxVoxels, BrickWork& work,
                  int threads = 1, double setupUpdates = kPrismSetupUpdates);

/// Every brick some prism's bounding box touches, with the predicted cost of its prisms as its
/// work (addPrismWork), split over `ranks`. The same on every rank. Throws InputError, before
/// allocating any voxel, when the bricks would hold more than maxVoxels voxels.
BrickLayout planBricks(const std::vector<PrismScan>& scans, const VoxelGrid& grid, int ranks,
                       uint64_t maxVoxels = InputLimits{}.maxVoxels,
                       double setupUpdates = kPrismSetupUpdates);

struct IntegrationStats {
  uint64_t prisms = 0;        ///< prisms rasterized on this rank
  uint64_t voxelUpdates = 0;  ///< voxels that received a value from an image
};

/// Adds images in scan order: per image, each voxel keeps the value of the prism with the
/// smallest |d|; that value is then added, weighted, to the running sums. With several threads
/// each owns a slab of voxels along z for a whole batch of images (cut so that each gets as
/// many of their points) and goes through the batch on its own, every image's prisms that reach
/// its slab in order: each voxel still sees the images in order and each image's triangles in
/// order, the same bits as one thread, and no thread waits for another between images. An
/// image's values are kept in a list per slab, not in an array over the field: 4 bytes a voxel
/// (where its latest value lies) instead of a value's 20.
class PrismIntegrator {
 public:
  /// An image: its parts (a station's bands) in order, adding up to one scan's triangles.
  using Image = std::vector<const PrismScan*>;

  explicit PrismIntegrator(BrickStore& store, int threads = 1);
  /// Images' samples go to `hypotheses` (robust fusion) instead of the store's sums.
  PrismIntegrator(BrickStore& store, int threads, SurfaceHypotheses* hypotheses);
  IntegrationStats addScan(const PrismScan& scan);
  /// One image made of several parts: the same bits as adding their triangles joined into one
  /// scan, without the copy.
  IntegrationStats addImage(const Image& parts);
  /// Images in order: the same bits as adding them one at a time.
  IntegrationStats addImages(const std::vector<Image>& images);
  /// Follows the store after BrickStore::grow(): its new bricks take samples too.
  void storeGrew();
  /// Bytes of its per-voxel index and the threads' sample lists.
  uint64_t bytes() const;
  /// From now on counts the voxel updates of each local brick (a growing field's work, and a
  /// check of the planner's cost model; off by default, it costs a shift a sample).
  void countUpdatesPerBrick();
  /// Per local brick, the voxel updates counted since countUpdatesPerBrick().
  std::vector<uint64_t> updatesPerBrick() const;

 private:
  /// The value the image gives voxel `at` (its offset in the sums: a rank holds under 2^32
  /// voxels, and 24 bytes a sample, not 32, is a quarter less memory to write and read).
  struct Sample {
    uint32_t at;
    float d, w, f[3];
  };
  /// One thread's share: voxels with z in [zLo, zHi], and the values this image gives them.
  struct Slab {
    int zLo = 0, zHi = -1;
    std::vector<Sample> samples;
    std::vector<Colour> colours;         ///< the samples' colours, when the store has colour
    std::vector<float> sigmas;           ///< the samples' depth noise (robust fusion)
    std::vector<uint64_t> brickUpdates;  ///< per local brick, when counted
  };
  /// Checks the store fits 32-bit offsets and finds the voxel layers its bricks span.
  void measureStore();
  bool touchesOwnedBrick(const BrickCoord& lo, const BrickCoord& hi) const;
  void cutSlabs(const std::vector<Image>& images);
  /// Adds the images' samples within the slab; returns the prisms counted (see rasterizeSlab).
  IntegrationStats integrateSlab(const std::vector<Image>& images, Slab& slab);
  uint64_t rasterizeSlab(const PrismScan& scan, Slab& slab);
  /// The sample this image gives voxel `at` in the slab's list, or null if none yet.
  Sample* sampleOf(Slab& slab, size_t at) const;
  void accumulate(Slab& slab);
  /// Adds the slab's samples to its count per local brick.
  void countBrickUpdates(Slab& slab) const;

  BrickStore& store_;
  SurfaceHypotheses* hypotheses_ = nullptr;
  int zFirst_ = 0, zLayers_ = 0;  ///< the voxel layers the rank's bricks span
  /// Per voxel, where in its slab's list its latest sample was put; a stale entry (another
  /// image's) is told apart because the list does not hold this voxel there.
  std::vector<uint32_t> latest_;
  std::vector<Slab> slabs_;
};

}  // namespace rangefuse
