// How a compact scan's normals and confidences are held and packed (private to route/): a unit
// normal as two 16-bit octahedral coordinates, a confidence in [0, 1] as a 16-bit fraction
// (decision 58). compactScan rounds each to the value its code gives back, so packing and
// unpacking a compact scan loses nothing, and every rank count sees the same values. Inline:
// unpacking decodes every vertex of every part.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rangefuse::internal {
namespace detail {

inline constexpr double kSteps = 32767;             // an octahedral coordinate's steps to 1
inline constexpr uint32_t kZeroCode = 0x80008000u;  // -32768 twice: no normal's coordinates

/// -1 or 1 by x's sign bit, a zero's too: a fold's direction. A normal unfolded onto x = 0
/// keeps its code's sign as -0, and its code comes back.
inline double signOf(double x) {
  return std::copysign(1.0, x);
}

/// x rounded to the nearest whole number, halves away from zero (as std::lround, inline and
/// without a branch: a normal's signs are as likely as not).
inline int roundedOf(double x) {
  return static_cast<int>(x + std::copysign(0.5, x));
}

/// A coordinate in [-1, 1] as a signed 16-bit step, in the code's low bits.
inline uint32_t stepOf(double x) {
  return static_cast<uint16_t>(static_cast<int16_t>(roundedOf(std::clamp(x, -1.0, 1.0) * kSteps)));
}

/// The coordinate of a code's low 16 bits.
inline double coordinateOf(uint32_t bits) {
  return static_cast<int16_t>(bits & 0xffffu) / kSteps;
}

/// Octahedral coordinates of the lower half folded over the diagonals (and back: the fold is
/// its own inverse).
inline void fold(double& u, double& v) {
  const double fu = (1 - std::abs(v)) * signOf(u), fv = (1 - std::abs(u)) * signOf(v);
  u = fu, v = fv;
}

}  // namespace detail

/// The code of unit normal n: its octahedral coordinates (the lower half folded over) in steps
/// of 1/32767, u in the low 16 bits, v in the high. A zero or non-finite n has a code of its
/// own, whose normal is zero.
inline uint32_t normalCode(const Eigen::Vector3d& n) {
  const double l1 = std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z());
  if (!(l1 > 0) || !std::isfinite(l1)) return detail::kZeroCode;
  const double inv = 1 / l1;
  const double u = n.x() * inv, v = n.y() * inv;
  double fu = u, fv = v;
  detail::fold(fu, fv);
  const bool lower = n.z() < 0;  // selected, not branched on
  return detail::stepOf(lower ? fu : u) | detail::stepOf(lower ? fv : v) << 16;
}

/// The unit normal a code stands for (zero for a zero normal's code); normalCode of it gives
/// the code back.
inline Eigen::Vector3d normalOf(uint32_t code) {
  if (code == detail::kZeroCode) return Eigen::Vector3d::Zero();
  double u = detail::coordinateOf(code), v = detail::coordinateOf(code >> 16);
  const double z = 1 - std::abs(u) - std::abs(v);
  if (z < 0) detail::fold(u, v);
  const Eigen::Vector3d n(u, v, z);  // |u| + |v| + |z| = 1: never zero
  return n * (1 / std::sqrt(n.squaredNorm()));
}

/// n as its code gives it back: within 1e-4 radians of a unit n (6.4e-5 the largest of 10^6).
inline Eigen::Vector3d quantisedNormal(const Eigen::Vector3d& n) {
  return normalOf(normalCode(n));
}

/// The code of a confidence: c clamped to [0, 1] (NaN to 0) in steps of 1/65535.
inline uint16_t confidenceCode(double c) {
  return static_cast<uint16_t>(
      detail::roundedOf(std::clamp(std::isnan(c) ? 0.0 : c, 0.0, 1.0) * 65535));
}

/// The confidence a code stands for; confidenceCode of it gives the code back.
inline double confidenceOf(uint16_t code) {
  return code / 65535.0;
}

/// c as its code gives it back: within 7.7e-6 of c in [0, 1].
inline double quantisedConfidence(double c) {
  return confidenceOf(confidenceCode(c));
}

}  // namespace rangefuse::internal
