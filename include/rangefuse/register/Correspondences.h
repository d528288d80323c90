// Correspondences read from the fused field in O(1) (Tubic et al. Eqs. 14-15), summed per
// brick so that ranks can combine them in an order that does not depend on the rank count.
#pragma once

#include <mpi.h>

#include <vector>

#include "rangefuse/register/RigidFit.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

struct CorrespondenceSettings {
  float minWeight = 0.05f;  ///< ignore voxels whose summed weight is below this
  double maxDistance = 0;   ///< ignore voxels with |d| above this (world units; the envelope)
  double minCosine = 0.5;   ///< ignore voxels whose gradient makes a larger angle with the normal
  float minImages = 1;      ///< ignore voxels fewer images contributed to
  bool weightByImages = false;  ///< weight by k / (k + 1), k images saw the voxel
  /// planeSums: Huber's robust weight min(1, huber / |r|) on the residual r (world units; 0:
  /// none), so a few wrong correspondences pull a fit less than many right ones.
  double huber = 0;
};

/// The last brick looked up: neighbouring control points mostly share one, and the hash lookup
/// of a brick is the larger part of a correspondence.
struct BrickCache {
  uint64_t code = ~uint64_t{0};
  int64_t local = -1;
};

/// A control point's corresponding point and what it was read from.
struct Correspondence {
  Eigen::Vector3d q;  ///< the corresponding point
  size_t brick = 0;   ///< the local brick of the voxel
  /// k / (k + 1) for a voxel k images saw: the residual's variance is the control point's
  /// noise plus the field's, which averages k images, so this is its inverse-variance weight.
  double weight = 1;
};

/// What the field says at a control point p: from the voxel nearest to p, its unit gradient f
/// and the signed distance of p along it, d + f.(p - p_v) (Tubic Eq. 14 to first order).
struct FieldSample {
  size_t brick = 0;  ///< the local brick of the voxel
  size_t voxel = 0;  ///< the voxel's offset into the store's sums
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  double distance = 0;
  float images = 0;  ///< the images that contributed to the voxel
};

/// The field at control point p (normal n). False when the nearest voxel is not local,
/// unobserved, too light, seen by too few images, outside the envelope, or faces away from n
/// (the other side of a thin part). `cache`, when given, saves looking up the same brick twice
/// in a row.
bool sampleField(const BrickStore& store, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                 const CorrespondenceSettings& settings, FieldSample& out,
                 BrickCache* cache = nullptr);

/// The corresponding point of p (normal n) from the voxel nearest to it: p - f [d + f.(p - p_v)],
/// with f the unit gradient. False when that voxel is not local, unobserved, too light, seen by
/// too few images, outside the envelope, or faces away from n (the other side of a thin part).
/// `cache`, when given, saves looking up the same brick twice in a row.
bool correspondence(const BrickStore& store, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                    const CorrespondenceSettings& settings, Correspondence& out,
                    BrickCache* cache = nullptr);

/// Collective: for control points p (world, normals n) with weights, the sums over all
/// correspondences, made by the ranks owning each point's voxel, added per brick and then in
/// brick order. Every rank gets the same sums, bit for bit, whatever the number of ranks.
/// Points are taken relative to the lattice origin (store.grid().origin), so a fit from them
/// is in that frame.
RigidSums correspondenceSums(const BrickStore& store, const std::vector<Eigen::Vector3d>& points,
                             const std::vector<Eigen::Vector3d>& normals,
                             const std::vector<double>& weights,
                             const CorrespondenceSettings& settings, MPI_Comm comm);

/// The normal equations of point-to-plane steps against the field: for control point p with
/// residual r (its signed distance, Tubic Eq. 14) and unit gradient f, J = [f, (p - c) x f] about
/// a centre c, A = sum w J J^T, b = sum w r J; plus what the step's judgement needs.
struct PlaneSums {
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  double w = 0, wr2 = 0, wLever = 0, count = 0;

  void add(const Eigen::Vector3d& lever, const Eigen::Vector3d& f, double r, double weight);
  PlaneSums& operator+=(const PlaneSums& o);
  double rms() const { return w > 0 ? std::sqrt(wr2 / w) : 0; }
};

/// Collective: PlaneSums of control points p (world, normals n) about `centre`, Huber-weighted
/// (settings.huber), made by the ranks owning each point's voxel and added per brick, then in
/// brick order: the same bits on every rank, whatever the number of ranks.
PlaneSums planeSums(const BrickStore& store, const std::vector<Eigen::Vector3d>& points,
                    const std::vector<Eigen::Vector3d>& normals, const std::vector<double>& weights,
                    const Eigen::Vector3d& centre, const CorrespondenceSettings& settings,
                    MPI_Comm comm);

}  // namespace rangefuse
