#include "rangefuse/fuse/TrackingField.h"

#include <algorithm>
#include <cmath>

#include "PlacedScans.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse {
namespace {

using mpi::collectivelyOrThrow;
using namespace internal;

/// The bricks of `work` and those within `reach` bricks of them, as (code, work) pairs sorted by
/// code: room for the next frames' motion without growing again.
std::vector<std::pair<uint64_t, uint64_t>> withNeighbours(const BrickWork& work, int reach) {
  std::vector<std::pair<uint64_t, uint64_t>> pairs;
  pairs.reserve(work.size() * 4);
  for (const auto& [code, count] : work) {
    const BrickCoord b = mortonDecode(code);
    for (int z = -reach; z <= reach; ++z)
      for (int y = -reach; y <= reach; ++y)
        for (int x = -reach; x <= reach; ++x) {
          const BrickCoord n = b + BrickCoord(x, y, z);
          if ((n.array() >= 0).all()) pairs.emplace_back(mortonEncode(n), x || y || z ? 0 : count);
        }
  }
  std::sort(pairs.begin(), pairs.end());
  // One entry a code, its work the sum (the brick's own count; neighbours add nothing).
  size_t out = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (out > 0 && pairs[out - 1].first == pairs[k].first)
      pairs[out - 1].second += pairs[k].second;
    else
      pairs[out++] = pairs[k];
  }
  pairs.resize(out);
  return pairs;
}

/// The sorted union of a layout's bricks and `more` (code, work) pairs, work added.
BrickLayout merged(const BrickLayout& layout, const std::vector<uint64_t>& more, int ranks) {
  BrickLayout out;
  out.grid = layout.grid;
  size_t a = 0, b = 0;
  while (a < layout.codes.size() || b < more.size()) {
    const uint64_t ca = a < layout.codes.size() ? layout.codes[a] : ~uint64_t{0};
    const uint64_t cb = b < more.size() ? more[b] : ~uint64_t{0};
    const uint64_t code = std::min(ca, cb);
    uint64_t work = 0;
    if (ca == code) work += layout.work[a++];
    if (cb == code) work += more[b + 1], b += 2;
    out.codes.push_back(code);
    out.work.push_back(work);
  }
  out.rankStart = partitionWork(out.work, ranks);
  return out;
}

/// Collective: a store on `layout` holding the sums of `from` (on another layout of the same
/// lattice), each brick sent by its old owner to its new one.
std::unique_ptr<BrickStore> moveSums(const BrickStore& from, const BrickLayout& layout,
                                     MPI_Comm comm) {
  const int me = mpi::rank(comm);
  auto to = std::make_unique<BrickStore>(layout, me);
  const size_t per = from.voxelsPerBrick();
  std::vector<std::vector<char>> out(mpi::size(comm));
  for (size_t b = 0; b < from.brickCount(); ++b) {
    const uint64_t code = from.code(b);
    const VoxelSums* sums = &from.sums()[b * per];
    const int owner = layout.ownerOf(static_cast<size_t>(layout.find(code)));
    if (owner == me) {
      std::copy(sums, sums + per, &to->sums()[to->localBrick(code) * per]);
      continue;
    }
    mpi::pack(out[owner], &code, 1);
    mpi::pack(out[owner], sums, per);
  }
  for (const auto& in : mpi::exchangeBytes(std::move(out), comm))
    for (size_t at = 0; at < in.size();) {
      uint64_t code;
      mpi::unpack(in, at, &code, 1);
      mpi::unpack(in, at, &to->sums()[to->localBrick(code) * per], per);
    }
  return to;
}

}  // namespace

TrackingField::TrackingField(const TrackingFieldSettings& settings, const LoadedScans& scans,
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
  BrickLayout empty;
  empty.grid = grid_;
  empty.rankStart.assign(mpi::size(comm_) + 1, 0);
  store_ = std::make_unique<BrickStore>(empty, mpi::rank(comm_));
  integrator_.reset();
  for (size_t i : which) add(i, poses);
  return *store_;
}

const BrickStore& TrackingField::add(size_t i, const std::vector<Pose>& poses) {
  grow(i, poses[i]);
  integrate(i, poses);
  return *store_;
}

void TrackingField::grow(size_t i, const Pose& pose) {
  // The reader plans the frame's bricks; every rank learns the (brick, work) pairs.
  std::vector<char> mine;
  collectivelyOrThrow(comm_, [&] {
    if (!scans_.holds(i)) return;
    const std::vector<PrismScan> one{placeScan(*scans_.held->get(i), pose)};
    if (!gridHolds(grid_, one, settings_.eps))
      throw InputError(scans_.paths[i] + ": the frame lies more than " + std::to_string(kRoom) +
                       " voxels from the first frames: tracking lost");
    BrickWork work;
    addPrismWork(one[0], grid_, settings_.maxVoxels, work, settings_.threads);
    // A frame whose prisms reach bricks the layout lacks brings a room of two bricks around
    // its own: the field grows (reallocated and moved) every few frames, not at every frame.
    std::vector<std::pair<uint64_t, uint64_t>> pairs = withNeighbours(work, 0);
    const bool grows = std::any_of(pairs.begin(), pairs.end(), [&](const auto& p) {
      return store_->layout().find(p.first) < 0;
    });
    if (grows) pairs = withNeighbours(work, 2);
    for (const auto& [code, count] : pairs) {
      const int64_t at = store_->layout().find(code);
      if (at >= 0 && count == 0) continue;  // known, and no work to add
      mpi::pack(mine, &code, 1);
      mpi::pack(mine, &count, 1);
    }
  });
  std::vector<uint64_t> pairs;
  for (const auto& part : mpi::allgatherBytes(mine, comm_))
    for (size_t at = 0; at < part.size();) {
      uint64_t v[2];
      mpi::unpack(part, at, v, 2);
      pairs.insert(pairs.end(), v, v + 2);
    }
  const BrickLayout& layout = store_->layout();
  bool grows = false;
  for (size_t k = 0; k < pairs.size(); k += 2) {
    const int64_t at = layout.find(pairs[k]);
    if (at >= 0)
      store_->addWork(static_cast<size_t>(at), pairs[k + 1]);
    else
      grows = true;
  }
  if (!grows) return;
  std::vector<uint64_t> fresh;
  for (size_t k = 0; k < pairs.size(); k += 2)
    if (layout.find(pairs[k]) < 0) fresh.insert(fresh.end(), {pairs[k], pairs[k + 1]});
  const BrickLayout next = merged(layout, fresh, mpi::size(comm_));
  collectivelyOrThrow(comm_, [&] {
    const double voxels = static_cast<double>(next.codes.size()) * std::pow(grid_.brick, 3);
    if (voxels > static_cast<double>(settings_.maxVoxels))
      throw InputError("--voxel " + std::to_string(settings_.voxel) + ": the tracked field needs " +
                       std::to_string(static_cast<uint64_t>(voxels)) +
                       " voxels, more than --max-voxels " + std::to_string(settings_.maxVoxels));
  });
  store_ = moveSums(*store_, next, comm_);
  integrator_.reset();
}

void TrackingField::integrate(size_t i, const std::vector<Pose>& poses) {
  if (!integrator_) integrator_ = std::make_unique<PrismIntegrator>(*store_, settings_.threads);
  routePlaced(scans_, {i}, poses, store_->layout(), 0, comm_, [&](size_t, const PrismScan& part) {
    voxelUpdates_ += integrator_->addScan(part).voxelUpdates;
  });
}

std::unique_ptr<BrickStore> TrackingField::release() {
  integrator_.reset();
  return std::move(store_);
}

}  // namespace rangefuse
