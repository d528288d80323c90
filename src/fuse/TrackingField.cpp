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

/// The (code, work) pairs of `work`, sorted by code.
std::vector<std::pair<uint64_t, uint64_t>> sortedPairs(const BrickWork& work) {
  std::vector<std::pair<uint64_t, uint64_t>> pairs(work.begin(), work.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

/// The sorted union of a layout's bricks and `more` (code, work) pairs, work added; no owners.
BrickLayout joined(const BrickLayout& layout, const std::vector<uint64_t>& more) {
  BrickLayout out;
  out.grid = layout.grid;
  out.codes.reserve(layout.codes.size() + more.size() / 2);
  out.work.reserve(out.codes.capacity());
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
  return out;
}

/// The first code each rank owns (ranks + 1 entries, the last past every code): a brick that
/// joins later goes to the rank whose range holds its code, so no old brick changes owner.
std::vector<uint64_t> ownedRanges(const BrickLayout& layout) {
  std::vector<uint64_t> bounds(layout.rankStart.size(), ~uint64_t{0});
  bounds[0] = 0;
  for (size_t r = 1; r + 1 < bounds.size(); ++r)
    if (layout.rankStart[r] < layout.codes.size()) bounds[r] = layout.codes[layout.rankStart[r]];
  return bounds;
}

/// Rank runs of `layout` by code ranges `bounds` (see ownedRanges).
void ownByRanges(BrickLayout& layout, const std::vector<uint64_t>& bounds) {
  layout.rankStart.resize(bounds.size());
  for (size_t r = 0; r < bounds.size(); ++r)
    layout.rankStart[r] =
        static_cast<size_t>(std::lower_bound(layout.codes.begin(), layout.codes.end(), bounds[r]) -
                            layout.codes.begin());
  layout.rankStart.back() = layout.codes.size();
}

/// Collective: a store on `layout` holding the sums of `from` (on another layout of the same
/// lattice), each brick sent by its old owner to its new one.
std::unique_ptr<BrickStore> moveSums(const BrickStore& from, const BrickLayout& layout,
                                     MPI_Comm comm) {
  const int me = mpi::rank(comm);
  auto to = std::make_unique<BrickStore>(layout, me);
  to->enableColour(from.colourKind());
  const bool coloured = from.hasColour();
  const size_t per = from.voxelsPerBrick();
  std::vector<std::vector<char>> out(mpi::size(comm));
  for (size_t b = 0; b < from.brickCount(); ++b) {
    const uint64_t code = from.code(b);
    const VoxelSums* sums = &from.sums()[b * per];
    const int owner = layout.ownerOf(static_cast<size_t>(layout.find(code)));
    const VoxelColour* colours = coloured ? &from.colours()[b * per] : nullptr;
    if (owner == me) {
      const size_t at = to->localBrick(code) * per;
      std::copy(sums, sums + per, &to->sums()[at]);
      if (coloured) std::copy(colours, colours + per, &to->colours()[at]);
      continue;
    }
    mpi::pack(out[owner], &code, 1);
    mpi::pack(out[owner], sums, per);
    if (coloured) mpi::pack(out[owner], colours, per);
  }
  for (const auto& in : mpi::exchangeBytes(std::move(out), comm))
    for (size_t at = 0; at < in.size();) {
      uint64_t code;
      mpi::unpack(in, at, &code, 1);
      const size_t local = to->localBrick(code) * per;
      mpi::unpack(in, at, &to->sums()[local], per);
      if (coloured) mpi::unpack(in, at, &to->colours()[local], per);
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
  store_->enableColour(settings_.colour);
  integrator_.reset();
  balancedBricks_ = 0;
  for (size_t i : which) add(i, poses);
  return *store_;
}

const BrickStore& TrackingField::add(size_t i, const std::vector<Pose>& poses) {
  grow(i, poses[i]);
  integrate(i, poses);
  return *store_;
}

void TrackingField::grow(size_t i, const Pose& pose) {
  const std::vector<uint64_t> fresh = newBricks(i, pose);
  if (fresh.empty()) return;
  BrickLayout next = joined(store_->layout(), fresh);
  collectivelyOrThrow(comm_, [&] {
    const double voxels = static_cast<double>(next.codes.size()) * std::pow(grid_.brick, 3);
    if (voxels > static_cast<double>(settings_.maxVoxels))
      throw InputError("--voxel " + std::to_string(settings_.voxel) + ": the tracked field needs " +
                       std::to_string(static_cast<uint64_t>(voxels)) +
                       " voxels, more than --max-voxels " + std::to_string(settings_.maxVoxels));
  });
  // Split by work anew (the sums move) only when the field has grown by half since it last
  // was: moving every brick at every frame costs more than the frame, and growing by half
  // bounds the moves to three times the final field.
  if (2 * next.codes.size() > 3 * balancedBricks_) {
    next.rankStart = partitionWork(next.work, mpi::size(comm_));
    store_ = moveSums(*store_, next, comm_);
    balancedBricks_ = next.codes.size();
    ranges_ = ownedRanges(next);
    integrator_.reset();
    return;
  }
  ownByRanges(next, ranges_);
  std::vector<uint64_t> mine;
  const int me = mpi::rank(comm_);
  for (size_t k = 0; k < fresh.size(); k += 2)
    if (next.ownerOf(static_cast<size_t>(next.find(fresh[k]))) == me) mine.push_back(fresh[k]);
  store_->grow(next, mine);
  if (integrator_) integrator_->storeGrew();
}

std::vector<uint64_t> TrackingField::newBricks(size_t i, const Pose& pose) {
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
    for (const auto& [code, count] : sortedPairs(work)) {
      mpi::pack(mine, &code, 1);
      mpi::pack(mine, &count, 1);
    }
  });
  std::vector<uint64_t> fresh;
  for (const auto& part : mpi::allgatherBytes(mine, comm_))
    for (size_t at = 0; at < part.size();) {
      uint64_t v[2];
      mpi::unpack(part, at, v, 2);
      const int64_t known = store_->layout().find(v[0]);
      if (known >= 0)
        store_->addWork(static_cast<size_t>(known), v[1]);
      else
        fresh.insert(fresh.end(), v, v + 2);
    }
  return fresh;
}

void TrackingField::integrate(size_t i, const std::vector<Pose>& poses) {
  if (!integrator_) integrator_ = std::make_unique<PrismIntegrator>(*store_, settings_.threads);
  routePlaced(scans_, {i}, poses, store_->layout(), 0, comm_, [&](size_t, const PrismScan& part) {
    voxelUpdates_ += integrator_->addScan(part).voxelUpdates;
  });
}

std::unique_ptr<BrickStore> TrackingField::release() {
  integrator_.reset();
  store_->sortBricks();
  return std::move(store_);
}

}  // namespace rangefuse
