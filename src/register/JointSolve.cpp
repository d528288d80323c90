#include "rangefuse/register/JointSolve.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "VoxelTerms.h"
#include "rangefuse/parallel/FixedPointSum.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

uint64_t pairKey(uint32_t s, uint32_t t) {
  return uint64_t{s} << 32 | t;
}

/// Every pair of scans (s <= t) that share a voxel on any rank, sorted: the same list everywhere.
std::vector<uint64_t> sharedPairs(const std::vector<std::vector<VoxelShare>>& voxels,
                                  MPI_Comm comm) {
  std::vector<uint64_t> mine;
  for (const auto& shares : voxels) {
    if (shares.size() < 2) continue;
    for (size_t i = 0; i < shares.size(); ++i)
      for (size_t j = i; j < shares.size(); ++j)
        mine.push_back(pairKey(shares[i].scan, shares[j].scan));
  }
  std::sort(mine.begin(), mine.end());
  mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
  std::vector<char> bytes;
  mpi::pack(bytes, mine.data(), mine.size());
  std::vector<uint64_t> all;
  for (const auto& part : mpi::allgatherBytes(bytes, comm)) {
    const size_t n = part.size() / sizeof(uint64_t), at = all.size();
    all.resize(at + n);
    size_t pos = 0;
    mpi::unpack(part, pos, all.data() + at, n);
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

uint64_t pointsInSharedVoxels(const std::vector<std::vector<VoxelShare>>& voxels) {
  uint64_t n = 0;
  for (const auto& shares : voxels)
    if (shares.size() >= 2)
      for (const VoxelShare& s : shares) n += s.points;
  return n;
}

/// Calls add(s, t, points) for every pair of scans s < t sharing a voxel, with the control
/// points both put there.
template <class Add>
void voxelPairs(const std::vector<VoxelShare>& shares, Add&& add) {
  for (size_t i = 0; i < shares.size(); ++i)
    for (size_t j = i + 1; j < shares.size(); ++j)
      add(shares[i].scan, shares[j].scan, uint64_t{shares[i].points} + shares[j].points);
}

}  // namespace

void VoxelShare::add(const Eigen::Vector3d& p, const Eigen::Vector3d& f, double r, double w,
                     const MotionFrame& frame) {
  Vector6d a;
  a << (p - frame.centre).cross(f) / frame.length, f;
  points += 1;
  weight += w;
  jacobian += w * a;
  residual += w * r;
}

double JointEquations::rms(size_t s) const {
  return weight[s] > 0 ? std::sqrt(squares[s] / weight[s]) : 0;
}

JointEquations jointEquations(const std::vector<std::vector<VoxelShare>>& voxels, size_t scans) {
  JointEquations eq(scans);
  for (const auto& shares : voxels)
    internal::voxelTerms(
        shares,
        [&](uint32_t s, uint32_t t, const Matrix6d& h) {
          auto it = eq.blocks.try_emplace({s, t}, Matrix6d::Zero()).first;
          it->second += h;
        },
        [&](uint32_t s, const Vector6d& g) { eq.gradient[s] += g; },
        [&](const VoxelShare& a, double e) {
          eq.weight[a.scan] += a.weight;
          eq.squares[a.scan] += a.weight * e * e;
          eq.points[a.scan] += a.points;
        });
  for (const auto& shares : voxels)
    voxelPairs(shares, [&](uint32_t a, uint32_t b, uint64_t n) { eq.pairPoints[{a, b}] += n; });
  return eq;
}

JointEquations reduceJointEquations(const std::vector<std::vector<VoxelShare>>& voxels,
                                    size_t scans, double maxResidual, MPI_Comm comm) {
  const std::vector<uint64_t> pairs = sharedPairs(voxels, comm);
  std::unordered_map<uint64_t, size_t> slot;
  for (size_t k = 0; k < pairs.size(); ++k) slot[pairs[k]] = k;
  // Bounds from the total weight (each point weighs at most 1, each Jacobian entry is at most
  // 1): a block entry gathers at most Σ m, a gradient entry Σ m |e| with |e| <= 2 maxResidual.
  uint64_t points = pointsInSharedVoxels(voxels);
  MPI_Allreduce(MPI_IN_PLACE, &points, 1, MPI_UINT64_T, MPI_SUM, comm);
  const double P = static_cast<double>(points), e = 2 * maxResidual;
  FixedPointSum blocks(36 * pairs.size(), P), gradient(6 * scans, e * P),
      stats(2 * scans, std::max(P, e * e * P));
  JointEquations eq(scans);
  for (const auto& shares : voxels)
    internal::voxelTerms(
        shares,
        [&](uint32_t s, uint32_t t, const Matrix6d& h) {
          const size_t at = 36 * slot.at(pairKey(s, t));
          for (int k = 0; k < 36; ++k) blocks.add(at + k, h.data()[k]);
        },
        [&](uint32_t s, const Vector6d& g) {
          for (int k = 0; k < 6; ++k) gradient.add(6 * s + k, g[k]);
        },
        [&](const VoxelShare& a, double r) {
          stats.add(2 * a.scan, a.weight);
          stats.add(2 * a.scan + 1, a.weight * r * r);
          eq.points[a.scan] += a.points;
        });
  const std::vector<double> H = blocks.reduce(comm), g = gradient.reduce(comm),
                            st = stats.reduce(comm);
  for (size_t k = 0; k < pairs.size(); ++k)
    eq.blocks[{static_cast<uint32_t>(pairs[k] >> 32), static_cast<uint32_t>(pairs[k])}] =
        Eigen::Map<const Matrix6d>(H.data() + 36 * k);
  for (size_t s = 0; s < scans; ++s) {
    eq.gradient[s] = Eigen::Map<const Vector6d>(g.data() + 6 * s);
    eq.weight[s] = st[2 * s];
    eq.squares[s] = st[2 * s + 1];
  }
  MPI_Allreduce(MPI_IN_PLACE, eq.points.data(), static_cast<int>(scans), MPI_UINT64_T, MPI_SUM,
                comm);
  // Overlap per pair: integers, so the sum is the same in any order.
  std::vector<uint64_t> overlap(pairs.size(), 0);
  for (const auto& shares : voxels)
    voxelPairs(shares,
               [&](uint32_t a, uint32_t b, uint64_t n) { overlap[slot.at(pairKey(a, b))] += n; });
  MPI_Allreduce(MPI_IN_PLACE, overlap.data(), static_cast<int>(overlap.size()), MPI_UINT64_T,
                MPI_SUM, comm);
  for (size_t k = 0; k < pairs.size(); ++k)
    if (overlap[k] > 0)
      eq.pairPoints[{static_cast<uint32_t>(pairs[k] >> 32), static_cast<uint32_t>(pairs[k])}] =
          overlap[k];
  return eq;
}

std::vector<Vector6d> solveJoint(const JointEquations& eq, const std::vector<char>& free,
                                 double damping) {
  const size_t scans = eq.gradient.size();
  std::vector<int> column(scans, -1);
  int n = 0;
  for (size_t s = 0; s < scans; ++s)
    if (free[s]) column[s] = 6 * n++;
  std::vector<Vector6d> delta(scans, Vector6d::Zero());
  if (n == 0) return delta;
  std::vector<Eigen::Triplet<double>> entries;
  for (const auto& [st, h] : eq.blocks) {
    const int a = column[st.first], b = column[st.second];
    if (a < 0 || b < 0) continue;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        entries.emplace_back(a + i, b + j, h(i, j));
        if (a != b) entries.emplace_back(b + j, a + i, h(i, j));
      }
    if (a == b)
      for (int i = 0; i < 6; ++i)
        entries.emplace_back(a + i, a + i, damping * h.diagonal().maxCoeff());
  }
  for (int k = 0; k < 6 * n; ++k) entries.emplace_back(k, k, 1e-300);
  Eigen::SparseMatrix<double> H(6 * n, 6 * n);
  H.setFromTriplets(entries.begin(), entries.end());
  Eigen::VectorXd g(6 * n);
  for (size_t s = 0; s < scans; ++s)
    if (column[s] >= 0) g.segment<6>(column[s]) = eq.gradient[s];
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
  if (ldlt.info() != Eigen::Success) return delta;
  const Eigen::VectorXd x = ldlt.solve(-g);
  for (size_t s = 0; s < scans; ++s)
    if (column[s] >= 0) delta[s] = x.segment<6>(column[s]);
  return delta;
}

Pose motionPose(const Vector6d& delta, const MotionFrame& frame) {
  Pose p;
  const Eigen::Vector3d w = delta.head<3>() / frame.length;
  if (w.norm() > 0) p.R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  p.t = frame.centre + delta.tail<3>() - p.R * frame.centre;
  return p;
}

}  // namespace rangefuse
