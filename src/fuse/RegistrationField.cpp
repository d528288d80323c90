#include "rangefuse/fuse/RegistrationField.h"

#include <cmath>

#include "rangefuse/core/Error.h"
#include "rangefuse/fuse/RegisterStage.h"
#include "rangefuse/fuse/ScanLoader.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

constexpr int kLatticeMargin = 4;  // bricks of room below the scans for their motion

template <class Fn>
void collectivelyOrThrow(MPI_Comm comm, Fn&& fn) {
  if (!mpi::collectively(comm, fn)) throw mpi::Reported();
}

/// Prism fields on one lattice for the whole registration. Algorithm 1 adds each registered
/// scan in place — one rasterisation per scan, not one per fused scan for every new scan.
/// Bricks are planned around every scan with a brick of room and planned anew only when a
/// scan leaves them. A voxel's value depends on the lattice and the order of the scans, not
/// on the bricks planned, so a resumed run that rebuilds the field gets the same values.
class GrowingPrismField : public RegistrationField {
 public:
  GrowingPrismField(const FuseOptions& o, const LoadedScans& scans, MPI_Comm comm)
      : o_(o), scans_(scans), comm_(comm), eps_(o.envelope * o.voxel) {}

  std::vector<double> fixLattice(const std::vector<double>& origin,
                                 const std::vector<Pose>& poses) override {
    collectivelyOrThrow(comm_, [&] {
      grid_ = fitGrid(placeAll(scans_, allScans(scans_), poses), o_.voxel, o_.brick, eps_,
                      kLatticeMargin);
      if (origin.empty()) return;
      if (!(std::isfinite(origin[0]) && std::isfinite(origin[1]) && std::isfinite(origin[2])))
        throw InputError(o_.resume + ": registration lattice origin is not finite");
      grid_.origin = Eigen::Vector3d(origin[0], origin[1], origin[2]);
    });
    return latticeOrigin();
  }

  const BrickStore& build(const std::vector<size_t>& which,
                          const std::vector<Pose>& poses) override {
    if (store_ && holdsExactly(which, poses)) return *store_;  // e.g. Algorithm 1's last field
    poses_ = poses;
    placed_.clear();
    for (size_t i : which) placed_.emplace_back(i, poses[i]);
    world_ = placeAll(scans_, which, poses);
    return rebuild();
  }

  const BrickStore& add(size_t i, const std::vector<Pose>& poses) override {
    poses_ = poses;
    placed_.emplace_back(i, poses[i]);
    world_.push_back(placeScan(scans_.local[i], poses[i]));
    const std::vector<PrismScan> one(world_.end() - 1, world_.end());
    bool holds = false;
    collectivelyOrThrow(comm_, [&] { holds = gridHolds(grid_, one, eps_) && layoutHolds(one); });
    if (!holds) return rebuild();
    integrator_->addScan(world_.back());
    return *store_;
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

  /// True when every brick the scan's prisms touch is planned.
  bool layoutHolds(const std::vector<PrismScan>& one) const {
    const BrickLayout needed = planBricks(one, grid_, 1, o_.limits.maxVoxels);
    for (uint64_t code : needed.codes)
      if (store_->layout().find(code) < 0) return false;
    return true;
  }

  /// New bricks around every scan at poses_, then the fused scans added in order.
  const BrickStore& rebuild() {
    collectivelyOrThrow(comm_, [&] {
      const std::vector<PrismScan> everyScan = placeAll(scans_, allScans(scans_), poses_);
      if (!gridHolds(grid_, everyScan, eps_))
        grid_ = fitGrid(everyScan, o_.voxel, o_.brick, eps_, kLatticeMargin);
      BrickLayout layout = planBricks(everyScan, grid_, mpi::size(comm_), o_.limits.maxVoxels);
      dilateBricks(layout, mpi::size(comm_), o_.limits.maxVoxels);
      store_ = std::make_unique<BrickStore>(layout, mpi::rank(comm_));
    });
    integrator_ = std::make_unique<PrismIntegrator>(*store_);
    for (const PrismScan& s : world_) integrator_->addScan(s);
    return *store_;
  }

  const FuseOptions& o_;
  const LoadedScans& scans_;
  MPI_Comm comm_;
  double eps_;
  VoxelGrid grid_;
  std::vector<Pose> poses_;
  std::vector<std::pair<size_t, Pose>> placed_;  ///< the fused scans and their poses, in order
  std::vector<PrismScan> world_;                 ///< the same scans in the world
  std::unique_ptr<BrickStore> store_;
  std::unique_ptr<PrismIntegrator> integrator_;
};

/// Consensus and naive fields need every view at once: each call builds from scratch.
class RebuiltField : public RegistrationField {
 public:
  RebuiltField(const FuseOptions& o, const LoadedScans& scans, MPI_Comm comm)
      : o_(o), scans_(scans), comm_(comm) {}

  std::vector<double> fixLattice(const std::vector<double>&, const std::vector<Pose>&) override {
    return {};
  }

  const BrickStore& build(const std::vector<size_t>& which,
                          const std::vector<Pose>& poses) override {
    which_ = which;
    RankCounters ignored;
    if (!buildFieldOf(o_, placeAll(scans_, which, poses), comm_, field_, ignored))
      throw mpi::Reported();
    return *field_.store;
  }

  const BrickStore& add(size_t i, const std::vector<Pose>& poses) override {
    std::vector<size_t> longer = which_;
    longer.push_back(i);
    return build(longer, poses);
  }

  std::vector<double> latticeOrigin() const override { return {}; }

 private:
  const FuseOptions& o_;
  const LoadedScans& scans_;
  MPI_Comm comm_;
  std::vector<size_t> which_;
  FusedField field_;
};

}  // namespace

std::unique_ptr<RegistrationField> makeRegistrationField(const FuseOptions& o,
                                                         const LoadedScans& scans, MPI_Comm comm) {
  if (o.method == "prism" && o.registerField == "grow")
    return std::make_unique<GrowingPrismField>(o, scans, comm);
  return std::make_unique<RebuiltField>(o, scans, comm);
}

}  // namespace rangefuse
