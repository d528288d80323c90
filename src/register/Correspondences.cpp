#include "rangefuse/register/Correspondences.h"

#include <cmath>
#include <map>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {

bool sampleField(const BrickStore& store, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                 const CorrespondenceSettings& s, FieldSample& out, BrickCache* cache) {
  const VoxelGrid& g = store.grid();
  const VoxelIndex v = g.nearest(p);  // Eq. 15
  if ((v.array() < 0).any()) return false;
  const BrickCoord bc = brickOf(v, g.brick);
  const uint64_t code = mortonEncode(bc);
  const int64_t b = cache && cache->code == code ? cache->local : store.localBrick(code);
  if (cache) *cache = BrickCache{code, b};
  if (b < 0) return false;
  const size_t offset = store.offset(b, bc, v);
  const VoxelSums& sums = store.sums()[offset];
  if (!(sums.w > s.minWeight) || sums.images < s.minImages) return false;
  const double d = sums.wd / sums.w;
  Eigen::Vector3d f(sums.wf[0], sums.wf[1], sums.wf[2]);
  if (std::abs(d) > s.maxDistance || !(f.norm() > 0)) return false;
  f.normalize();
  if (f.dot(n) < s.minCosine) return false;
  out.brick = static_cast<size_t>(b);
  out.voxel = offset;
  out.f = f;
  // The gradient of the signed field, corrected to first order for p's offset from the voxel
  // centre.
  out.distance = d + f.dot(p - g.centre(v));
  out.images = sums.images;
  return true;
}

bool correspondence(const BrickStore& store, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                    const CorrespondenceSettings& s, Correspondence& out, BrickCache* cache) {
  FieldSample sample;
  if (!sampleField(store, p, n, s, sample, cache)) return false;
  // Eq. 14: step back along the gradient by the distance.
  out.q = p - sample.f * sample.distance;
  out.brick = sample.brick;
  out.weight = s.weightByImages ? sample.images / (sample.images + 1.0) : 1.0;
  return true;
}

namespace {

/// Collective: the per-brick sums of every rank (`used` marks those this rank made), added in
/// the bricks' code order (a growing store's local order is not), so that every rank gets the same
/// bits whatever the rank count.
template <class Sums>
Sums addInBrickOrder(const BrickStore& store, const std::vector<Sums>& perBrick,
                     const std::vector<char>& used, MPI_Comm comm) {
  std::vector<char> buf;
  for (size_t local = 0; local < perBrick.size(); ++local) {
    if (!used[local]) continue;
    const uint64_t pos = store.code(local);  // code order is layout order
    mpi::pack(buf, &pos, 1);
    mpi::pack(buf, &perBrick[local], 1);
  }
  std::map<uint64_t, Sums> all;
  for (const auto& part : mpi::allgatherBytes(buf, comm))
    for (size_t at = 0; at < part.size();) {
      uint64_t pos;
      Sums s;
      mpi::unpack(part, at, &pos, 1);
      mpi::unpack(part, at, &s, 1);
      all[pos] = s;
    }
  Sums total;
  for (const auto& kv : all) total += kv.second;  // brick order: rank-count independent
  return total;
}

}  // namespace

RigidSums correspondenceSums(const BrickStore& store, const std::vector<Eigen::Vector3d>& points,
                             const std::vector<Eigen::Vector3d>& normals,
                             const std::vector<double>& weights,
                             const CorrespondenceSettings& settings, MPI_Comm comm) {
  const VoxelGrid& g = store.grid();
  // This rank's sums per local brick; local order is global order (a rank owns one run).
  std::vector<RigidSums> perBrick(store.brickCount());
  std::vector<char> used(store.brickCount(), 0);
  BrickCache cache;
  for (size_t i = 0; i < points.size(); ++i) {
    Correspondence c;
    if (!(weights[i] > 0) || !correspondence(store, points[i], normals[i], settings, c, &cache))
      continue;
    // About the lattice origin, which lies by the data: far from the world origin the moments
    // would otherwise lose their digits to cancellation (1e5 m offset: poses off by 10 voxels).
    perBrick[c.brick].add(points[i] - g.origin, c.q - g.origin, weights[i] * c.weight);
    used[c.brick] = 1;
  }
  return addInBrickOrder(store, perBrick, used, comm);
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
  std::vector<PlaneSums> perBrick(store.brickCount());
  std::vector<char> used(store.brickCount(), 0);
  BrickCache cache;
  for (size_t i = 0; i < points.size(); ++i) {
    FieldSample s;
    if (!(weights[i] > 0) || !sampleField(store, points[i], normals[i], settings, s, &cache))
      continue;
    const double r = std::abs(s.distance);
    const double huber = settings.huber > 0 && r > settings.huber ? settings.huber / r : 1.0;
    perBrick[s.brick].add(points[i] - centre, s.f, s.distance, weights[i] * huber);
    used[s.brick] = 1;
  }
  return addInBrickOrder(store, perBrick, used, comm);
}

}  // namespace rangefuse
