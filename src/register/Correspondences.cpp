#include "rangefuse/register/Correspondences.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {

namespace {

/// Where a control point's nearest voxel lies among this rank's sums (brick < 0: not here).
struct VoxelPlace {
  VoxelIndex v = VoxelIndex::Zero();
  int64_t brick = -1;
  size_t offset = 0;
};

/// The voxel nearest to p (Eq. 15), when one of this rank's bricks holds it.
VoxelPlace locateVoxel(const BrickStore& store, const Eigen::Vector3d& p, BrickCache* cache) {
  const VoxelGrid& g = store.grid();
  VoxelPlace at;
  at.v = g.nearest(p);
  if ((at.v.array() < 0).any()) return at;
  const BrickCoord bc = brickOf(at.v, g.brick);
  const uint64_t code = mortonEncode(bc);
  at.brick = cache && cache->code == code ? cache->local : store.localBrick(code);
  if (cache) *cache = BrickCache{code, at.brick};
  if (at.brick >= 0) at.offset = store.offset(at.brick, bc, at.v);
  return at;
}

/// sampleField's tests and values, at the voxel `at` (which this rank holds).
bool sampleVoxel(const BrickStore& store, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                 const CorrespondenceSettings& s, const VoxelPlace& at, FieldSample& out) {
  const VoxelSums& sums = store.sums()[at.offset];
  if (!(sums.w > s.minWeight) || sums.images < s.minImages) return false;
  const double d = sums.wd / sums.w;
  Eigen::Vector3d f(sums.wf[0], sums.wf[1], sums.wf[2]);
  if (std::abs(d) > s.maxDistance || !(f.norm() > 0)) return false;
  f.normalize();
  if (f.dot(n) < s.minCosine) return false;
  out.brick = static_cast<size_t>(at.brick);
  out.voxel = at.offset;
  out.f = f;
  // The gradient of the signed field, corrected to first order for p's offset from the voxel
  // centre.
  out.distance = d + f.dot(p - store.grid().centre(at.v));
  out.images = sums.images;
  return true;
}

/// Eq. 14: the corresponding point steps back from p along the gradient by the distance.
Correspondence correspondenceOf(const Eigen::Vector3d& p, const FieldSample& sample,
                                const CorrespondenceSettings& s) {
  Correspondence c;
  c.q = p - sample.f * sample.distance;
  c.brick = sample.brick;
  c.weight = s.weightByImages ? sample.images / (sample.images + 1.0) : 1.0;
  return c;
}

/// Calls visit(i, sample) for each control point of positive weight that samples the field, in
/// order. A control point's voxel is rarely in cache (a frame's points spread over the field),
/// and its load was seven tenths of sampleField's time: the voxels of a batch are looked up
/// and asked for first, then read. The order and the arithmetic are sampleField's.
template <class Visit>
void forEachSample(const BrickStore& store, const std::vector<Eigen::Vector3d>& points,
                   const std::vector<Eigen::Vector3d>& normals, const std::vector<double>& weights,
                   const CorrespondenceSettings& s, Visit visit) {
  constexpr size_t kBatch = 32;
  VoxelPlace places[kBatch];
  BrickCache cache;
  for (size_t first = 0; first < points.size(); first += kBatch) {
    const size_t m = std::min(kBatch, points.size() - first);
    for (size_t k = 0; k < m; ++k) {
      places[k] =
          weights[first + k] > 0 ? locateVoxel(store, points[first + k], &cache) : VoxelPlace{};
      if (places[k].brick >= 0) __builtin_prefetch(&store.sums()[places[k].offset]);
    }
    for (size_t k = 0; k < m; ++k) {
      const size_t i = first + k;
      FieldSample sample;
      if (places[k].brick >= 0 && sampleVoxel(store, points[i], normals[i], s, places[k], sample))
        visit(i, sample);
    }
  }
}

}  // namespace

bool sampleField(const BrickStore& store, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                 const CorrespondenceSettings& s, FieldSample& out, BrickCache* cache) {
  const VoxelPlace at = locateVoxel(store, p, cache);
  return at.brick >= 0 && sampleVoxel(store, p, n, s, at, out);
}

bool correspondence(const BrickStore& store, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                    const CorrespondenceSettings& s, Correspondence& out, BrickCache* cache) {
  FieldSample sample;
  if (!sampleField(store, p, n, s, sample, cache)) return false;
  out = correspondenceOf(p, sample, s);
  return true;
}

namespace {

/// The total of the bricks' sums so far, passed from rank to rank, with the last brick's code.
template <class Sums>
struct RunningTotal {
  Sums total;
  uint64_t last = 0;
  uint64_t any = 0;      ///< 1 once a brick was added
  uint64_t inOrder = 1;  ///< 0 if a rank's bricks did not all follow the ranks' before it
};

/// This rank's sums per local brick, held only for the bricks the points reach: a frame's
/// points reach a few hundred of a rank's thousands of bricks, and a fit is made several times
/// a frame (a zeroed sum for every brick is 1.8 MB on the kitchen).
template <class Sums>
class BrickSums {
 public:
  explicit BrickSums(size_t bricks) : slot_(bricks, -1) {}

  /// The sums of local brick b, zero when first asked for.
  Sums& operator[](size_t b) {
    int32_t& slot = slot_[b];
    if (slot < 0) {
      slot = static_cast<int32_t>(sums_.size());
      sums_.emplace_back();
      bricks_.push_back(b);
    }
    return sums_[static_cast<size_t>(slot)];
  }

  /// Collective: every rank's bricks' sums added in the bricks' code order (a growing store's
  /// local order is not), so that every rank gets the same bits whatever the rank count. A
  /// store holds its owner's run of the layout's sorted codes, so code order is rank order:
  /// the total is passed from rank to rank, each adding its own bricks in order. A tracked
  /// frame's fits call this several times a frame, and gathering every rank's bricks' sums
  /// instead (about 2,000 bricks of 376 bytes a rank on the kitchen) took a third of the fits'
  /// time.
  Sums total(const BrickStore& store, MPI_Comm comm) const {
    std::vector<std::pair<uint64_t, size_t>> mine;  // (code, slot)
    mine.reserve(bricks_.size());
    for (size_t k = 0; k < bricks_.size(); ++k) mine.emplace_back(store.code(bricks_[k]), k);
    std::sort(mine.begin(), mine.end());
    RunningTotal<Sums> run;
    mpi::passAlong(
        &run, sizeof run,
        [&] {
          if (mine.empty()) return;
          if (run.any && !(run.last < mine.front().first)) run.inOrder = 0;
          for (const auto& [code, k] : mine) run.total += sums_[k];
          run.last = mine.back().first, run.any = 1;
        },
        comm);
    if (!run.inOrder)  // every rank learns it from the last one: all throw
      throw std::logic_error("field sums: the ranks' bricks are not in code order");
    return run.total;
  }

 private:
  std::vector<int32_t> slot_;   ///< per local brick: its place in sums_, or -1
  std::vector<Sums> sums_;      ///< in the order the bricks were first reached
  std::vector<size_t> bricks_;  ///< the local brick of each of sums_
};

}  // namespace

RigidSums correspondenceSums(const BrickStore& store, const std::vector<Eigen::Vector3d>& points,
                             const std::vector<Eigen::Vector3d>& normals,
                             const std::vector<double>& weights,
                             const CorrespondenceSettings& settings, MPI_Comm comm) {
  const VoxelGrid& g = store.grid();
  // This rank's sums per local brick, added over the ranks in brick order.
  BrickSums<RigidSums> perBrick(store.brickCount());
  forEachSample(store, points, normals, weights, settings, [&](size_t i, const FieldSample& f) {
    const Correspondence c = correspondenceOf(points[i], f, settings);
    // About the lattice origin, which lies by the data: far from the world origin the moments
    // would otherwise lose their digits to cancellation (1e5 m offset: poses off by 10 voxels).
    perBrick[c.brick].add(points[i] - g.origin, c.q - g.origin, weights[i] * c.weight);
  });
  return perBrick.total(store, comm);
}

void PlaneSums::add(const Eigen::Vector3d& lever, const Eigen::Vector3d& f, double r,
                    double weight) {
  Eigen::Matrix<double, 6, 1> J;
  J.head<3>() = f;
  J.tail<3>() = lever.cross(f);
  A += weight * J * J.transpose();
  b += weight * r * J;
  w += weight, wr2 += weight * r * r, wLever += weight * lever.norm(), count += 1;
}

PlaneSums& PlaneSums::operator+=(const PlaneSums& o) {
  A += o.A, b += o.b, w += o.w, wr2 += o.wr2, wLever += o.wLever, count += o.count;
  return *this;
}

PlaneSums planeSums(const BrickStore& store, const std::vector<Eigen::Vector3d>& points,
                    const std::vector<Eigen::Vector3d>& normals, const std::vector<double>& weights,
                    const Eigen::Vector3d& centre, const CorrespondenceSettings& settings,
                    MPI_Comm comm) {
  BrickSums<PlaneSums> perBrick(store.brickCount());
  forEachSample(store, points, normals, weights, settings, [&](size_t i, const FieldSample& s) {
    const double r = std::abs(s.distance);
    const double huber = settings.huber > 0 && r > settings.huber ? settings.huber / r : 1.0;
    perBrick[s.brick].add(points[i] - centre, s.f, s.distance, weights[i] * huber);
  });
  return perBrick.total(store, comm);
}

}  // namespace rangefuse
