// Fundamental prisms and the distance along interpolated normals (Tubic et al. §4.3-4.4).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
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

/// Visits every voxel centre inside the prism. Rows of the bounding box are cut to the
/// span between their entry into and exit from the prism, so most outside voxels are
/// never solved for.
void rasterizePrism(const Prism& prism, const VoxelGrid& grid, const PrismVisitor& visit);

/// Reference for rasterizePrism: solves at every voxel of the bounding box.
void rasterizePrismBruteForce(const Prism& prism, const VoxelGrid& grid, const PrismVisitor& visit);

namespace internal {
/// Real roots of c0 + c1 x + c2 x^2 + c3 x^3 in [lo, hi], ascending; robust to any
/// leading coefficient being zero.
int cubicRootsInRange(const double c[4], double lo, double hi, double roots[3]);
}  // namespace internal

}  // namespace rangefuse
