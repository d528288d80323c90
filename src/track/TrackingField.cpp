#include "rangefuse/track/TrackingField.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/core/Error.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/GrowingBricks.h"
#include "rangefuse/pipeline/HeldScans.h"
#include "rangefuse/pipeline/PlacedScans.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse {
namespace {

using mpi::collectivelyOrThrow;
using namespace internal;

}  // namespace

TrackingField::TrackingField(const TrackingLattice& settings, const LoadedScans& scans,
                             MPI_Comm comm)
    : settings_(settings), scans_(scans), comm_(comm) {}

TrackingField::~TrackingField() = default;

std::vector<double> TrackingField::fixLattice(const std::vector<double>& origin,
                                              const std::vector<Pose>& poses) {
  // Around the first frame: the lattice reaches kRoom voxels beyond it, and the frames to come
  // are not read yet.
  const Eigen::AlignedBox3d box = placedBounds(scans_, {0}, poses, comm_);
  collectivelyOrThrow(comm_, [&] {
    grid_ =
        gridAround(box, settings_.voxel, settings_.brick, settings_.eps, kRoom / settings_.brick);
    if (origin.empty()) return;
    if (!(std::isfinite(origin[0]) && std::isfinite(origin[1]) && std::isfinite(origin[2])))
      throw InputError("tracking lattice origin is not finite");
    grid_.origin = Eigen::Vector3d(origin[0], origin[1], origin[2]);
  });
  return latticeOrigin();
}

std::vector<double> TrackingField::latticeOrigin() const {
  return {grid_.origin.x(), grid_.origin.y(), grid_.origin.z()};
}

const BrickStore& TrackingField::build(const std::vector<size_t>& which,
                                       const std::vector<Pose>& poses) {
  bricks_ = std::make_unique<GrowingBricks>(grid_, settings_.maxVoxels, settings_.threads, comm_);
  bricks_->startEmpty(settings_.colour);
  for (size_t i : which) {
    // A frame let go of since is read once for both of add()'s passes, not once for each
    // (a read-ahead thread gained nothing on two cores busy with two ranks).
    bool read = false;
    collectivelyOrThrow(comm_, [&] {
      read = scans_.holds(i) && !scans_.held->kept(i);
      if (read) scans_.held->readAndOffer(i);
    });
    add(i, poses);
    if (read) scans_.held->release(i);
  }
  return bricks_->store();
}

const BrickStore& TrackingField::add(size_t i, const std::vector<Pose>& poses) {
  std::vector<PrismScan> one;
  collectivelyOrThrow(comm_, [&] {
    if (!scans_.holds(i)) return;
    one.push_back(placeScan(*scans_.held->get(i), poses[i]));
    if (!gridHolds(grid_, one, settings_.eps))
      throw InputError(scans_.paths[i] + ": the frame lies more than " + std::to_string(kRoom) +
                       " voxels from the first frames: tracking lost");
  });
  const IntegrationStats added = bricks_->add(one.empty() ? nullptr : &one[0]);
  voxelUpdates_ += added.voxelUpdates;
  prisms_ += added.prisms;
  return bricks_->store();
}

const BrickStore& TrackingField::store() const {
  return bricks_->store();
}

std::unique_ptr<BrickStore> TrackingField::release() {
  return bricks_->release();
}

}  // namespace rangefuse
