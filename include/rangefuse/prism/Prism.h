// Fundamental prisms and the distance along interpolated normals (Tubic et al. §4.3-4.4).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

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

/// Where a point meets a prism: its distance along the interpolated normal and the
/// barycentric coordinates of its foot; what rasterisation needs before a voxel keeps it.
struct PrismFoot {
  double d = 0;
  Eigen::Vector3d bary;
};

/// The interpolated normal at a foot, normalised: the gradient of the signed field.
inline Eigen::Vector3d footGradient(const Prism& prism, const Eigen::Vector3d& b) {
  return (b[0] * prism.n[0] + b[1] * prism.n[1] + b[2] * prism.n[2]).normalized();
}

/// The confidence at a foot (Eq. 13's interpolation).
inline double footWeight(const Prism& prism, const Eigen::Vector3d& b) {
  return b[0] * prism.w[0] + b[1] * prism.w[1] + b[2] * prism.w[2];
}

}  // namespace rangefuse
