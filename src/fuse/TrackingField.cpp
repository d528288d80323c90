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

using Pair = std::pair<uint64_t, uint64_t>;

/// The (code, work) pairs of `work`, sorted by code.
std::vector<Pair> sortedPairs(const BrickWork& work) {
  std::vector<Pair> pairs(work.begin(), work.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

/// Rank me's own bricks of `layout` and the (code, work) pairs `more` (flat, sorted, none of
/// them held), sorted.
std::vector<Pair> ownJoined(const BrickLayout& layout, int me, const std::vector<uint64_t>& more) {
  std::vector<Pair> own;
  own.reserve(layout.rankStart[me + 1] - layout.rankStart[me] + more.size() / 2);
  for (size_t i = layout.rankStart[me]; i < layout.rankStart[me + 1]; ++i)
    own.emplace_back(layout.codes[i], layout.work[i]);
  for (size_t k = 0; k < more.size(); k += 2) own.emplace_back(more[k], more[k + 1]);
  std::inplace_merge(own.begin(), own.end() - static_cast<std::ptrdiff_t>(more.size() / 2),
                     own.end());
  return own;
}

/// Collective: `layout` with this rank's `fresh` (code, work) pairs joined, the owners' ranges
/// kept and every rank's bricks counted; the bricks bordering other ranks' new bricks are not
/// learnt (borderKnown false).
BrickLayout grownBy(const BrickLayout& layout, const std::vector<uint64_t>& fresh, MPI_Comm comm) {
  BrickLayout out;
  out.grid = layout.grid;
  out.firstCodes = layout.firstCodes;
  size_t a = 0, b = 0;
  while (a < layout.codes.size() || b < fresh.size()) {
    const uint64_t ca = a < layout.codes.size() ? layout.codes[a] : ~uint64_t{0};
    const uint64_t cb = b < fresh.size() ? fresh[b] : ~uint64_t{0};
    out.codes.push_back(std::min(ca, cb));
    out.work.push_back(ca < cb ? layout.work[a++] : (b += 2, fresh[b - 1]));
  }
  out.rankStart = runsOf(out.codes, out.firstCodes);
  const int ranks = mpi::size(comm), me = mpi::rank(comm);
  uint64_t count = out.rankStart[me + 1] - out.rankStart[me];
  std::vector<uint64_t> counts(ranks);
  MPI_Allgather(&count, 1, MPI_UINT64_T, counts.data(), 1, MPI_UINT64_T, comm);
  out.globalStart.assign(ranks + 1, 0);
  for (int r = 0; r < ranks; ++r) out.globalStart[r + 1] = out.globalStart[r] + counts[r];
  out.borderKnown = false;
  return out;
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
    const int owner = layout.ownerOfCode(code);
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
  const int ranks = mpi::size(comm_);
  BrickLayout empty;
  empty.grid = grid_;
  empty.rankStart.assign(ranks + 1, 0);
  empty.globalStart.assign(ranks + 1, 0);
  empty.firstCodes.assign(ranks + 1, ~uint64_t{0});
  empty.firstCodes[0] = 0;  // rank 0's range holds every code until the first split
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
  const uint64_t before = store_->layout().totalBricks();
  BrickLayout next = grownBy(store_->layout(), fresh, comm_);
  const uint64_t total = next.totalBricks();
  if (total == before) return;
  collectivelyOrThrow(comm_, [&] {
    const double voxels = static_cast<double>(total) * std::pow(grid_.brick, 3);
    if (voxels > static_cast<double>(settings_.maxVoxels))
      throw InputError("--voxel " + std::to_string(settings_.voxel) + ": the tracked field needs " +
                       std::to_string(static_cast<uint64_t>(voxels)) +
                       " voxels, more than --max-voxels " + std::to_string(settings_.maxVoxels));
  });
  const int me = mpi::rank(comm_);
  // Split by work anew (the sums move) only when the field has grown by half since it last
  // was: moving every brick at every frame costs more than the frame, and growing by half
  // bounds the moves to three times the final field.
  if (2 * total > 3 * balancedBricks_) {
    next = spreadSorted(ownJoined(store_->layout(), me, fresh), grid_, comm_);
    store_ = moveSums(*store_, next, comm_);
    balancedBricks_ = total;
    integrator_.reset();
    return;
  }
  std::vector<uint64_t> mine;
  for (size_t k = 0; k < fresh.size(); k += 2) mine.push_back(fresh[k]);
  store_->grow(next, mine);
  if (integrator_) integrator_->storeGrew();
}

std::vector<uint64_t> TrackingField::newBricks(size_t i, const Pose& pose) {
  // The reader plans the frame's bricks; each (brick, work) pair goes to the rank whose range
  // holds the brick.
  const BrickLayout& layout = store_->layout();
  std::vector<std::vector<char>> out(mpi::size(comm_));
  collectivelyOrThrow(comm_, [&] {
    if (!scans_.holds(i)) return;
    const std::vector<PrismScan> one{placeScan(*scans_.held->get(i), pose)};
    if (!gridHolds(grid_, one, settings_.eps))
      throw InputError(scans_.paths[i] + ": the frame lies more than " + std::to_string(kRoom) +
                       " voxels from the first frames: tracking lost");
    BrickWork work;
    addPrismWork(one[0], grid_, settings_.maxVoxels, work, settings_.threads);
    for (const Pair& p : sortedPairs(work)) mpi::pack(out[layout.ownerOfCode(p.first)], &p, 1);
  });
  std::vector<uint64_t> fresh;
  for (const auto& part : mpi::exchangeBytes(std::move(out), comm_))
    for (size_t at = 0; at < part.size();) {
      uint64_t v[2];
      mpi::unpack(part, at, v, 2);
      const int64_t known = layout.find(v[0]);
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
  // The bricks of other ranks that joined beside this rank's since the last split: the mesh's
  // halo needs them.
  const BrickLayout& layout = store_->layout();
  store_->grow(
      directoryFromOwn(ownJoined(layout, mpi::rank(comm_), {}), layout.firstCodes, grid_, comm_),
      {});
  return std::move(store_);
}

}  // namespace rangefuse
