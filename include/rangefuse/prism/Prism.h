// Fundamental prisms and the distance along interpolated normals (Tubic et al. §4.3-4.4).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "rangefuse/volume/VoxelGrid.h"

namespace rangefuse {

/// A generator triangle with unit vertex normals and confidences, valid for distances
/// d in [dMin, dMax]: the envelope [-eps, eps] truncated before the prism twists.
struct Prism {
  std::array<Eigen::Vector3d, 3> p;
  std::array<Eigen::Vector3d, 3> n;
  std::array<double, 3> w{};
  double dMin = 0, dMax = 0;
};

/// The field of one prism at one point.
struct PrismHit {
  double d = 0;              ///< signed distance along the interpolated normal (Eq. 6)
  Eigen::Vector3d bary;      ///< barycentric coordinates of the closest point
  Eigen::Vector3d closest;   ///< closest point on the generator triangle (Eq. 7)
  Eigen::Vector3d gradient;  ///< unit gradient of the signed field: the interpolated normal
  double weight = 0;         ///< confidence interpolated as in Eq. 13
};

/// Builds a prism with envelope `eps`, truncated where a vertex normal line meets the
/// facing edge surface inside the envelope (Eqs. 9-10).
Prism makePrism(const std::array<Eigen::Vector3d, 3>& p, const std::array<Eigen::Vector3d, 3>& n,
                const std::array<double, 3>& w, double eps);

/// Axis-aligned bounds of the prism (the hull of its six corner points).
Eigen::AlignedBox3d prismBounds(const Prism& prism);

/// Solves Eq. 6 for the root d in [dMin, dMax] whose iso-triangle T(d) contains x.
/// Returns false when x lies outside the prism.
bool solvePrismDistance(const Prism& prism, const Eigen::Vector3d& x, PrismHit& hit);

using PrismVisitor = std::function<void(const VoxelIndex&, const PrismHit&)>;

namespace internal {

/// Eq. 6's cubic in d, det[T(d) - x] = (N + d K + d^2 L) . (p0 - x + d n0), whose prism-only
/// parts are computed once: each point then costs three dot products, not seven determinants.
struct PrismCubic {
  explicit PrismCubic(const Prism& prism);
  Eigen::Vector3d N, K, L;  ///< T(d)'s (unnormalised) normal is N + d K + d^2 L
  double Nn = 0, Kn = 0, Ln = 0;
};

/// True when the line p_i + v n_i cannot meet the edge surface pa + u B + d (na + u (nb - na)),
/// u in [0, 1], at |d| <= eps (A = pa - p_i): makePrism's quick exit before Eq. 9's quadratic.
bool crossingBeyond(const Eigen::Vector3d& A, const Eigen::Vector3d& B, const Eigen::Vector3d& na,
                    const Eigen::Vector3d& nb, const Eigen::Vector3d& ni, double eps);

/// solvePrismDistance with the prism's cubic computed once (the same bits).
bool solvePrismDistance(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d& x,
                        PrismHit& hit);

/// The voxel rows a prism may cross: rows run along the longest side of the prism's box, and
/// each is cut to where it lies between five slabs that hold the prism's six corner points
/// (and so the whole prism, a blend of its corners): across its two end triangles and its
/// three sides. Cheap (a few products a row) and never too short, so the exact solve at each
/// voxel left decides, as it does for every voxel of the box.
class PrismRows {
 public:
  PrismRows(const Prism& prism, const VoxelGrid& grid);

  bool empty() const { return (lo.array() > hi.array()).any(); }
  /// Voxels [a0, a1] along `along` of the row at (vb, vc) on the two other axes, false if none.
  bool span(int vb, int vc, int& a0, int& a1) const;

  int along = 0, b = 1, c = 2;  ///< the rows' axis and the two fixed ones
  VoxelIndex lo, hi;            ///< voxels of the prism's box

 private:
  /// The prism lies where lo <= atRow0 + perB vb + perC vc + perStep a <= hi (a: along);
  /// perStepInv is 1 / perStep (0 when perStep is), as a product is cheaper than a division.
  struct Slab {
    double lo, hi, atRow0, perB, perC, perStep, perStepInv;
  };
  static constexpr int kSlabs = 5;
  Slab slabs_[kSlabs];
  int count_ = 0;
};

inline bool PrismRows::span(int vb, int vc, int& a0, int& a1) const {
  double from = lo[along], to = hi[along];
  for (int k = 0; k < count_; ++k) {
    const Slab& s = slabs_[k];
    const double at = s.atRow0 + s.perB * vb + s.perC * vc;
    if (s.perStep == 0) {
      if (at < s.lo || at > s.hi) return false;
      continue;
    }
    double t0 = (s.lo - at) * s.perStepInv, t1 = (s.hi - at) * s.perStepInv;
    if (t0 > t1) std::swap(t0, t1);
    from = std::max(from, t0);
    to = std::min(to, t1);
    if (from > to) return false;
  }
  if (!(from <= to)) return false;
  const double pad = 1e-6;  // lattice units: rounding never cuts a voxel the solve would keep
  a0 = std::max(lo[along], static_cast<int>(std::ceil(from - pad)));
  a1 = std::min(hi[along], static_cast<int>(std::floor(to + pad)));
  return a0 <= a1;
}

/// Visits the voxels of `rows` (PrismRows of the prism, perhaps with a smaller box) that lie
/// inside the prism.
template <class Visit>
void rasterizeRows(const Prism& prism, const VoxelGrid& grid, const PrismRows& rows,
                   Visit&& visit) {
  if (rows.empty()) return;
  const PrismCubic cubic(prism);
  PrismHit hit;
  VoxelIndex v;
  int a0, a1;
  for (v[rows.b] = rows.lo[rows.b]; v[rows.b] <= rows.hi[rows.b]; ++v[rows.b])
    for (v[rows.c] = rows.lo[rows.c]; v[rows.c] <= rows.hi[rows.c]; ++v[rows.c]) {
      if (!rows.span(v[rows.b], v[rows.c], a0, a1)) continue;
      for (v[rows.along] = a0; v[rows.along] <= a1; ++v[rows.along])
        if (solvePrismDistance(prism, cubic, grid.centre(v), hit)) visit(v, hit);
    }
}

}  // namespace internal

/// Visits every voxel centre inside the prism: visit(VoxelIndex, PrismHit), each once. Rows
/// of the bounding box are cut to the prism's slabs (internal::PrismRows), so most outside
/// voxels are never solved for.
template <class Visit>
void rasterizePrism(const Prism& prism, const VoxelGrid& grid, Visit&& visit) {
  internal::rasterizeRows(prism, grid, internal::PrismRows(prism, grid), visit);
}

/// Reference for rasterizePrism: solves at every voxel of the bounding box.
void rasterizePrismBruteForce(const Prism& prism, const VoxelGrid& grid, const PrismVisitor& visit);

namespace internal {
/// Real roots of c0 + c1 x + c2 x^2 + c3 x^3 in [lo, hi], ascending; robust to any
/// leading coefficient being zero.
int cubicRootsInRange(const double c[4], double lo, double hi, double roots[3]);
}  // namespace internal

}  // namespace rangefuse
