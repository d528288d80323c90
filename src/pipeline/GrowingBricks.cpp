#include "rangefuse/pipeline/GrowingBricks.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Limits.h"
#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/route/ScanRouting.h"
#include "rangefuse/volume/BrickPlanning.h"

namespace rangefuse::internal {
namespace {

using Pair = std::pair<uint64_t, uint64_t>;

/// Each scan takes a quarter off every brick's work before it adds its own, so a brick's work
/// is mostly that of the last few scans. A stream's next frames see about what its last ones
/// saw: split by all the work it ever took, the real kitchen's ranks made 29 and 42 M voxel
/// updates over frames 0-299, and the rank with less waited for the other at every frame.
constexpr int kWorkDecayShift = 2;
/// Every kCheckEvery scans the ranks compare the voxel updates they made since the last
/// check, and split the bricks anew when the most is more than kDrift times the mean.
constexpr uint64_t kCheckEvery = 8;
constexpr double kDrift = 1.10;
/// A brick costs the cut a quarter of the mean brick's work: with recent work, most bricks
/// have almost none, and a full mean would cut by brick count more than by the work to come.
constexpr uint64_t kBrickCostDivisor = 4;

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

/// The bricks of rank me's range that `part`'s prisms reach and `layout` lacks, as (code, 0)
/// pairs sorted by code: they join with no work, and take the updates they are given.
/// Refused as addBrickWork refuses, before a prism's box of too many bricks is listed.
std::vector<uint64_t> freshBricks(const PrismScan& part, const BrickLayout& layout, int me,
                                  uint64_t maxVoxels) {
  BrickWork reached;
  BrickCoord lastLo(1, 1, 1), lastHi(0, 0, 0);
  for (size_t t = 0; t < part.surface.triangles.size(); ++t) {
    BrickCoord lo, hi;
    if (!bricksOfBox(layout.grid, prismBounds(scanPrism(part, t)), lo, hi)) continue;
    if (lo == lastLo && hi == lastHi) continue;  // neighbours (grid order) mostly share a box
    lastLo = lo, lastHi = hi;
    addBrickWork(layout.grid, lo, hi, 0, maxVoxels, reached);
  }
  std::vector<uint64_t> codes;
  for (const auto& [code, work] : reached)
    if (layout.ownerOfCode(code) == me && layout.find(code) < 0) codes.push_back(code);
  std::sort(codes.begin(), codes.end());
  std::vector<uint64_t> fresh;
  for (const uint64_t code : codes) fresh.insert(fresh.end(), {code, 0});
  return fresh;
}

/// Collective: the bricks of this rank's range that any rank's routed triangles reach (sorted,
/// each once), from every rank's `reached` (routeRounds').
std::vector<uint64_t> reachedHere(ReachedBricks&& reached, MPI_Comm comm) {
  const int me = mpi::rank(comm);
  std::vector<std::vector<char>> out(reached.size());
  for (size_t r = 0; r < reached.size(); ++r)
    if (static_cast<int>(r) != me) mpi::pack(out[r], reached[r].data(), reached[r].size());
  std::vector<uint64_t> codes = std::move(reached[me]);
  int lists = codes.empty() ? 0 : 1;
  for (const std::vector<char>& bytes : mpi::exchangeBytes(std::move(out), comm)) {
    const size_t n = bytes.size() / sizeof(uint64_t), at = codes.size();
    if (n == 0) continue;
    codes.resize(at + n);
    size_t pos = 0;
    mpi::unpack(bytes, pos, codes.data() + at, n);
    ++lists;
  }
  if (lists > 1) {  // several readers' lists, each sorted: one list
    std::sort(codes.begin(), codes.end());
    codes.erase(std::unique(codes.begin(), codes.end()), codes.end());
  }
  return codes;
}

/// Of `reached` (sorted codes of this rank's range), the bricks `layout` lacks, as (code, 0)
/// pairs: freshBricks' answer, from the bricks routing found. Routing has listed them all
/// already, so there is no estimate to refuse here; growBy checks the field's total.
std::vector<uint64_t> freshOf(const std::vector<uint64_t>& reached, const BrickLayout& layout) {
  std::vector<uint64_t> fresh;
  for (const uint64_t code : reached)
    if (layout.find(code) < 0) fresh.insert(fresh.end(), {code, 0});
  return fresh;
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
  const int me = mpi::rank(comm);
  out.globalStart = globalStartOf(out.rankStart[me + 1] - out.rankStart[me], comm);
  out.borderKnown = false;
  return out;
}

/// Collective: `store` on `layout`, another split of its bricks: each brick that changes owner
/// is sent by its old owner to its new one; the others stay in place.
void moveSums(BrickStore& store, const BrickLayout& layout, MPI_Comm comm) {
  const int me = mpi::rank(comm);
  const bool coloured = store.hasColour();
  const size_t per = store.voxelsPerBrick();
  std::vector<std::vector<char>> out(mpi::size(comm));
  for (size_t b = 0; b < store.brickCount(); ++b) {
    const uint64_t code = store.code(b);
    const int owner = layout.ownerOfCode(code);
    if (owner == me) continue;
    mpi::pack(out[owner], &code, 1);
    mpi::pack(out[owner], &store.sums()[b * per], per);
    if (coloured) mpi::pack(out[owner], &store.colours()[b * per], per);
  }
  const std::vector<std::vector<char>> in = mpi::exchangeBytes(std::move(out), comm);
  // The bricks of this rank's new run that it does not hold yet are those it is sent.
  std::vector<uint64_t> arriving;
  for (size_t i = layout.rankStart[me]; i < layout.rankStart[me + 1]; ++i)
    if (store.localBrick(layout.codes[i]) < 0) arriving.push_back(layout.codes[i]);
  store.rehome(layout, arriving);
  for (const auto& part : in)
    for (size_t at = 0; at < part.size();) {
      uint64_t code;
      mpi::unpack(part, at, &code, 1);
      const size_t local = static_cast<size_t>(store.localBrick(code)) * per;
      mpi::unpack(part, at, &store.sums()[local], per);
      if (coloured) mpi::unpack(part, at, &store.colours()[local], per);
    }
}

/// Collective: the mean work of a brick (total bricks given), a share of which every brick
/// adds to the cut. Most of a growing field's bricks lie out of the latest scans' sight, with
/// little work left: a cut by work alone would give one rank most of them, and of memory.
uint64_t meanWork(const std::vector<Pair>& own, uint64_t bricks, MPI_Comm comm) {
  uint64_t work = 0;
  for (const Pair& p : own) work += p.second;
  MPI_Allreduce(MPI_IN_PLACE, &work, 1, MPI_UINT64_T, MPI_SUM, comm);
  return bricks ? work / bricks : 0;
}

}  // namespace

GrowingBricks::GrowingBricks(const VoxelGrid& grid, uint64_t maxVoxels, int threads, MPI_Comm comm)
    : grid_(grid), maxVoxels_(maxVoxels), threads_(threads), comm_(comm) {}

GrowingBricks::~GrowingBricks() = default;

void GrowingBricks::startEmpty(ColourKind colour) {
  const int ranks = mpi::size(comm_);
  BrickLayout empty;
  empty.grid = grid_;
  empty.rankStart.assign(ranks + 1, 0);
  empty.globalStart.assign(ranks + 1, 0);
  empty.firstCodes.assign(ranks + 1, ~uint64_t{0});
  empty.firstCodes[0] = 0;
  integrator_.reset();
  store_ = std::make_unique<BrickStore>(empty, mpi::rank(comm_));
  store_->enableColour(colour);
  balancedAt_ = empty.globalStart;
}

void GrowingBricks::start(const BrickLayout& layout) {
  integrator_.reset();
  store_ = std::make_unique<BrickStore>(layout, mpi::rank(comm_));
  balancedAt_ = layout.globalStart;
  memoryLedger().set(Held::field, store_->bytes());
}

PrismIntegrator& GrowingBricks::integrator() {
  if (!integrator_) integrator_ = std::make_unique<PrismIntegrator>(*store_, threads_);
  return *integrator_;
}

IntegrationStats GrowingBricks::add(PrismScan* placed) {
  std::vector<std::vector<size_t>> rounds(1);
  if (placed) rounds[0].push_back(0);
  RoutedParts parts;
  RoutingStats routing;
  const auto take = [&](size_t) { return TakenScan{{}, std::move(*placed)}; };
  // Routing finds the bricks each triangle reaches; a lone rank routes nothing (decision 57).
  const bool alone = mpi::size(comm_) == 1;
  ReachedBricks reached;
  if (!routeRounds(rounds, take, store_->layout(), 0, store_->hasColour(), comm_, parts, routing,
                   RouteTo::ranges, alone ? nullptr : &reached))
    throw mpi::Reported();
  IndexedScans mine = parts.takeAll();  // one reader: one part at most
  const PrismScan* part = mine.empty() ? nullptr : &mine[0].second;
  store_->decayWork(kWorkDecayShift);
  growBy(part, alone ? nullptr : &reached);
  IntegrationStats added;
  if (part) added = addCounted(*part);
  updatesSinceCheck_ += added.voxelUpdates;
  if (splitIfDue() && integrator_) integrator_->storeGrew();
  return added;
}

void GrowingBricks::growBy(const PrismScan* part, ReachedBricks* reached) {
  const BrickLayout& layout = store_->layout();
  const std::vector<uint64_t> codes =
      reached ? reachedHere(std::move(*reached), comm_) : std::vector<uint64_t>{};
  std::vector<uint64_t> fresh;  // (code, work) pairs, sorted
  mpi::collectivelyOrThrow(comm_, [&] {
    if (reached)
      fresh = freshOf(codes, layout);
    else if (part)
      fresh = freshBricks(*part, layout, mpi::rank(comm_), maxVoxels_);
  });
  const uint64_t before = layout.totalBricks();
  BrickLayout next = grownBy(layout, fresh, comm_);
  const uint64_t total = next.totalBricks();
  if (total == before) return;
  const double voxels = static_cast<double>(total) * std::pow(grid_.brick, 3);
  if (voxels > static_cast<double>(maxVoxels_))  // the same total on every rank
    throw InputError("--voxel " + formatNumber(grid_.voxel) + ": the field needs " +
                     std::to_string(static_cast<uint64_t>(voxels)) +
                     " voxels, more than --max-voxels " + std::to_string(maxVoxels_));
  std::vector<uint64_t> mine;
  for (size_t k = 0; k < fresh.size(); k += 2) mine.push_back(fresh[k]);
  store_->grow(next, mine);
  if (integrator_) integrator_->storeGrew();
  memoryLedger().set(Held::field, store_->bytes());
}

IntegrationStats GrowingBricks::addCounted(const PrismScan& part) {
  PrismIntegrator& integrator = this->integrator();
  integrator.countUpdatesPerBrick();
  const IntegrationStats added = integrator.addScan(part);
  const std::vector<uint64_t> updates = integrator.updatesPerBrick();
  const BrickLayout& layout = store_->layout();
  for (size_t b = 0; b < updates.size(); ++b)
    if (updates[b] > 0)
      store_->addWork(static_cast<size_t>(layout.find(store_->code(b))),
                      static_cast<uint64_t>(kWorkPerUpdate) * updates[b]);
  return added;
}

bool GrowingBricks::drifted() {
  if (++scansSinceCheck_ < kCheckEvery) return false;
  std::vector<uint64_t> updates(mpi::size(comm_));
  MPI_Allgather(&updatesSinceCheck_, 1, MPI_UINT64_T, updates.data(), 1, MPI_UINT64_T, comm_);
  scansSinceCheck_ = 0, updatesSinceCheck_ = 0;
  uint64_t most = 0, all = 0;
  for (const uint64_t u : updates) most = std::max(most, u), all += u;
  return static_cast<double>(most) * static_cast<double>(updates.size()) >
         kDrift * static_cast<double>(all);
}

bool GrowingBricks::splitIfDue() {
  const BrickLayout& layout = store_->layout();
  // Both tests run on every rank at every scan: drifted() is collective.
  const bool grew = needsSplit(layout.globalStart), drift = drifted();
  if (!grew && !drift) return false;
  std::vector<Pair> own = ownJoined(layout, mpi::rank(comm_), {});
  const uint64_t brickCost = meanWork(own, layout.totalBricks(), comm_) / kBrickCostDivisor;
  const BrickLayout next = spreadSorted(std::move(own), grid_, comm_, brickCost);
  moveSums(*store_, next, comm_);
  ++splits_;
  balancedAt_ = store_->layout().globalStart;
  memoryLedger().set(Held::field, store_->bytes());
  return true;
}

bool GrowingBricks::needsSplit(const std::vector<uint64_t>& start) const {
  // Split by work anew (the sums move) once a rank has gained half a fair share of bricks
  // since the last split: moving every brick at every scan costs more than the scan, and
  // new surface tends to land in one or two ranks' ranges, which would otherwise take all
  // of the growth. A rank then holds at most its share and half again.
  const uint64_t ranks = start.size() - 1, before = balancedAt_.back();
  for (size_t r = 0; r < ranks; ++r) {
    const uint64_t gained = (start[r + 1] - start[r]) - (balancedAt_[r + 1] - balancedAt_[r]);
    if (2 * ranks * gained > before) return true;
  }
  return false;
}

std::unique_ptr<BrickStore> GrowingBricks::release() {
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

}  // namespace rangefuse::internal
