// The field a depth stream is tracked against and fused into: prism fields on one fixed
// lattice, growing brick by brick as the camera sees new surface. Each frame is added once, at
// its tracked pose, and the field that tracks is the field that is meshed.
#pragma once

#include <mpi.h>

#include <memory>

#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse {
namespace internal {
class GrowingBricks;
}

/// The lattice and colour of the tracking field (from the run's FieldSettings).
struct TrackingLattice {
  double voxel = 0;
  int brick = 8;
  double eps = 0;  ///< prism half-thickness, world units
  uint64_t maxVoxels = 0;
  int threads = 1;
  ColourKind colour = ColourKind::none;  ///< what the field fuses beside the distance
};

/// A RegistrationField whose add() never rebuilds: the bricks a new frame's prisms reach join
/// the field, each on the rank whose range of codes holds it (a rank's directory knows its own
/// bricks and, once released, those bordering them), and the sums already held stay
/// where they are; when a rank has gained half a fair share of bricks, the bricks are split
/// over the ranks by work anew and the sums move to their new owners unchanged
/// (internal::GrowingBricks). A voxel's sums are therefore
/// those of adding the frames in order, on any number of ranks. The lattice is fixed by the
/// first call and reaches kRoom voxels beyond the first frame in every direction; a frame
/// outside it is an error.
class TrackingField : public RegistrationField {
 public:
  static constexpr int kRoom = 1 << 14;  ///< voxels of lattice around the first frames

  TrackingField(const TrackingLattice& settings, const LoadedScans& scans, MPI_Comm comm);
  ~TrackingField() override;

  std::vector<double> fixLattice(const std::vector<double>& origin,
                                 const std::vector<Pose>& poses) override;
  const BrickStore& build(const std::vector<size_t>& scans,
                          const std::vector<Pose>& poses) override;
  const BrickStore& add(size_t i, const std::vector<Pose>& poses) override;
  std::vector<double> latticeOrigin() const override;

  /// The field as it stands (valid until the next add).
  const BrickStore& store() const;
  /// The field as it stands, for meshing; the tracking field is empty afterwards.
  std::unique_ptr<BrickStore> release();
  /// Voxel updates made so far on this rank.
  uint64_t voxelUpdates() const { return voxelUpdates_; }
  /// Prisms this rank rasterised into its bricks.
  uint64_t prisms() const { return prisms_; }

 private:
  TrackingLattice settings_;
  const LoadedScans& scans_;
  MPI_Comm comm_;
  VoxelGrid grid_;
  std::unique_ptr<internal::GrowingBricks> bricks_;
  uint64_t voxelUpdates_ = 0;
  uint64_t prisms_ = 0;
};

}  // namespace rangefuse
