#include "rangefuse/pipeline/RegistrationField.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "rangefuse/core/Error.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/pipeline/GrowingBricks.h"
#include "rangefuse/pipeline/PlacedScans.h"
#include "rangefuse/pipeline/RegisterStage.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse {
namespace {

constexpr int kLatticeMargin = 4;  // bricks of room below the scans for their motion

using mpi::collectivelyOrThrow;
using namespace internal;

/// Prism fields on one lattice for the whole registration. Algorithm 1 adds each registered
/// scan in place — one rasterisation per scan, not one per fused scan for every new scan.
/// Bricks are planned for the fused scans; a scan added later brings the bricks its prisms
/// reach and no others (GrowingBricks), and the field is planned anew only when a scan leaves
/// the lattice. A voxel's value depends on the lattice and the order of the scans, not on the
/// bricks planned, so a resumed run that rebuilds the field gets the same values. Each rank
/// holds only the scans it read: it places them and routes their triangles to the brick
/// owners whenever the field is built or grows.
class GrowingPrismField : public RegistrationField {
 public:
  GrowingPrismField(const FieldSettings& f, std::string resumed, const LoadedScans& scans,
                    MPI_Comm comm)
      : f_(f), resumed_(std::move(resumed)), scans_(scans), comm_(comm), eps_(f.eps()) {}

  std::vector<double> fixLattice(const std::vector<double>& origin,
                                 const std::vector<Pose>& poses) override {
    const Eigen::AlignedBox3d box =
        placedBounds(scans_, everyScan(scans_.names.size()), poses, comm_);
    collectivelyOrThrow(comm_, [&] {
      grid_ = gridAround(box, f_.voxel, f_.brick, eps_, kLatticeMargin);
      if (origin.empty()) return;
      if (!(std::isfinite(origin[0]) && std::isfinite(origin[1]) && std::isfinite(origin[2])))
        throw InputError(resumed_ + ": registration lattice origin is not finite");
      grid_.origin = Eigen::Vector3d(origin[0], origin[1], origin[2]);
    });
    return latticeOrigin();
  }

  const BrickStore& build(const std::vector<size_t>& which,
                          const std::vector<Pose>& poses) override {
    if (bricks_ && holdsExactly(which, poses)) return bricks_->store();  // Algorithm 1's last
    poses_ = poses;
    placed_.clear();
    for (size_t i : which) placed_.emplace_back(i, poses[i]);
    return rebuild();
  }

  const BrickStore& add(size_t i, const std::vector<Pose>& poses) override {
    poses_ = poses;
    placed_.emplace_back(i, poses[i]);
    std::vector<PrismScan> one;
    int holds = 1;
    collectivelyOrThrow(comm_, [&] {
      if (!scans_.holds(i)) return;
      one.push_back(placeScan(*scans_.held->get(i), poses[i]));
      holds = gridHolds(grid_, one, eps_);
    });
    MPI_Allreduce(MPI_IN_PLACE, &holds, 1, MPI_INT, MPI_MIN, comm_);
    if (!holds) return rebuild();
    collectivelyOrThrow(comm_, [&] { bricks_->add(one.empty() ? nullptr : &one[0]); });
    return bricks_->store();
  }

  std::vector<double> latticeOrigin() const override {
    return {grid_.origin.x(), grid_.origin.y(), grid_.origin.z()};
  }

 private:
  /// True when the field holds just these scans, in this order, at these poses.
  bool holdsExactly(const std::vector<size_t>& which, const std::vector<Pose>& poses) const {
    if (which.size() != placed_.size()) return false;
    for (size_t k = 0; k < which.size(); ++k) {
      const auto& [i, pose] = placed_[k];
      if (which[k] != i || !(poses[i].R == pose.R && poses[i].t == pose.t)) return false;
    }
    return true;
  }

  /// The bricks of the fused scans at poses_ planned anew (the lattice anew if a scan left
  /// it), then the scans added in order.
  const BrickStore& rebuild() {
    std::vector<size_t> order;
    for (const auto& [i, pose] : placed_) order.push_back(i);
    const Eigen::AlignedBox3d box =
        placedBounds(scans_, everyScan(scans_.names.size()), poses_, comm_);
    collectivelyOrThrow(comm_, [&] {
      if (!gridHoldsBox(grid_, box, eps_))
        grid_ = gridAround(box, f_.voxel, f_.brick, eps_, kLatticeMargin);
    });
    bricks_.reset();  // the old field's memory goes before the new one's comes
    bricks_ = std::make_unique<GrowingBricks>(grid_, f_.maxVoxels, f_.threads, comm_);
    bricks_->start(planPlacedOn(scans_, order, poses_, grid_, f_.maxVoxels, f_.threads, comm_));
    addRouted(scans_, order, poses_, bricks_->integrator(), bricks_->store().layout(), comm_);
    return bricks_->store();
  }

  const FieldSettings f_;
  const std::string resumed_;  ///< the checkpoint the lattice origin came from
  const LoadedScans& scans_;
  MPI_Comm comm_;
  double eps_;
  VoxelGrid grid_;
  std::vector<Pose> poses_;
  std::vector<std::pair<size_t, Pose>> placed_;  ///< the fused scans and their poses, in order
  std::unique_ptr<GrowingBricks> bricks_;
};

/// Consensus and naive fields need every view at once: each call builds from scratch, with the
/// placed scans routed to the ranks whose bricks lie within the consensus margin of them.
class RebuiltField : public RegistrationField {
 public:
  RebuiltField(const FieldSettings& f, const LoadedScans& scans, MPI_Comm comm)
      : f_(f), scans_(scans), comm_(comm) {}

  std::vector<double> fixLattice(const std::vector<double>&, const std::vector<Pose>&) override {
    return {};
  }

  const BrickStore& build(const std::vector<size_t>& which,
                          const std::vector<Pose>& poses) override {
    which_ = which;
    field_ = FusedField{};
    field_.layout = planPlaced(scans_, which, poses, f_, comm_);
    field_.store = std::make_unique<BrickStore>(field_.layout, mpi::rank(comm_));
    if (!methodInfo(f_.method).closestSurface) {
      PrismIntegrator integrator(*field_.store, f_.threads);
      routePlaced(scans_, which, poses, field_.layout, 0, comm_,
                  [&](size_t, const PrismScan& part) { integrator.addScan(part); });
      return *field_.store;
    }
    field_.scans.resize(which.size());
    field_.scanCount = which.size();
    routePlaced(scans_, which, poses, field_.layout, routeReach(f_), comm_,
                [&](size_t k, PrismScan& part) { field_.scans[k] = std::move(part); });
    collectivelyOrThrow(comm_, [&] {
      evaluateClosestSurfaceField(f_, field_, 1);
      field_.scans = {};
    });
    return *field_.store;
  }

  const BrickStore& add(size_t i, const std::vector<Pose>& poses) override {
    std::vector<size_t> longer = which_;
    longer.push_back(i);
    return build(longer, poses);
  }

  std::vector<double> latticeOrigin() const override { return {}; }

 private:
  const FieldSettings f_;
  const LoadedScans& scans_;
  MPI_Comm comm_;
  std::vector<size_t> which_;
  FusedField field_;
};

}  // namespace

std::unique_ptr<RegistrationField> makeRegistrationField(const FieldSettings& field,
                                                         RegistrationFieldMode mode,
                                                         const std::string& resumed,
                                                         const LoadedScans& scans, MPI_Comm comm) {
  if (!methodInfo(field.method).closestSurface && mode == RegistrationFieldMode::Grow)
    return std::make_unique<GrowingPrismField>(field, resumed, scans, comm);
  return std::make_unique<RebuiltField>(field, scans, comm);
}

}  // namespace rangefuse
