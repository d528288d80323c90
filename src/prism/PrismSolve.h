// Solving for a point's foot in a prism (private to the prism stage): the prism's cubic
// computed once, the solves one point or a batch at a time, and the cubic's roots.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

#include "rangefuse/prism/Prism.h"

namespace rangefuse::internal {

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

/// Which of a triangle's three vertices pass crossingBeyond (vertex i against the edge facing
/// it), by a cheaper test that the three share. For a point q of that edge, the part of q - p_i
/// across n_i is at least |q - p_i| cos(n_i, m), m the triangle's normal, and |q - p_i| is at
/// least the triangle's height h_i over the edge; the tilt is |n_a| sin(n_a, n_i). With
/// X = (p1 - p0) x (p2 - p0) and e_i the facing edge, (h_i cos)^2 = (n_i . X)^2 / (|n_i|^2
/// |e_i|^2): above eps^2 tilt^2, no meeting lies inside the envelope. Its margins (a thousandth,
/// and a trillionth of the squared lengths) exceed both tests' rounding, so a vertex cleared
/// here is one crossingBeyond clears. It clears all three vertices of 86 % of a real Kinect
/// frame's triangles, where crossingBeyond clears 90 %; the rest take crossingBeyond's test.
struct EnvelopeClearance {
  EnvelopeClearance(const std::array<Eigen::Vector3d, 3>& p,
                    const std::array<Eigen::Vector3d, 3>& n, double eps);
  bool clear[3];  ///< vertex i's normal line meets its facing edge surface nowhere within eps
};

/// solvePrismDistance with the prism's cubic computed once (the same bits).
bool solvePrismDistance(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d& x,
                        PrismHit& hit);

/// The foot of x in the prism (the root of smallest |d| whose iso-triangle holds x), false
/// when x lies outside: solvePrismDistance without the closest point, gradient and weight.
bool solvePrismFoot(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d& x,
                    PrismFoot& foot);

/// Most feet solveFeet takes at once.
constexpr int kFootBatch = 16;

/// The feet of n <= kFootBatch points, as solvePrismFoot finds them (inside[i] says whether
/// points[i] lies in the prism), in one pass per step over all points: the points' solves
/// are independent, so the processor overlaps them instead of waiting on one chain of
/// divisions and branches at a time. Every point takes a fixed number of Newton steps from
/// the linear root; one whose last step is not at rounding (bracketedRoot's test), or whose
/// cubic may have several roots in range and is not shown monotonic from -|d| to |d| around
/// a root d whose iso-triangle holds it, is solved by solvePrismFoot.
void solveFeet(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d* points, int n,
               PrismFoot* feet, bool* inside);

/// Fills the rest of a hit from its foot (the same bits as solvePrismDistance).
void completeHit(const Prism& prism, const PrismFoot& foot, PrismHit& hit);

/// Barycentric coordinates of x in the iso-triangle T(d); not finite when T(d) has no area.
Eigen::Vector3d isoBarycentric(const Prism& prism, const PrismCubic& cubic,
                               const Eigen::Vector3d& x, double d);

/// True when barycentric coordinates lie in the triangle, to a tolerance of 1e-9 (false for
/// any that is not a number).
inline bool baryInside(const Eigen::Vector3d& b) {
  const double tol = -1e-9;
  return b[0] >= tol && b[1] >= tol && b[2] >= tol;
}

/// Real roots of c0 + c1 x + c2 x^2 + c3 x^3 in [lo, hi], ascending; robust to any
/// leading coefficient being zero.
int cubicRootsInRange(const double c[4], double lo, double hi, double roots[3]);

/// How many roots the cubic has in [lo, hi], one in each of its monotonic pieces there whose
/// ends differ in sign, and [a, b], the last such piece; -1 when that does not settle it (a
/// value of zero at an end of a piece, or one that is not finite).
int rootBrackets(const double c[4], double lo, double hi, double& a, double& b);

/// The root in [a, b] of a cubic monotonic there whose ends differ in sign (a bracket of
/// rootBrackets), searched from `guess` when it lies inside, else from the secant.
double rootBetween(const double c[4], double a, double b, double guess);

/// True when the slope (a quadratic) has one strict sign on [lo, hi]: at both ends and at its
/// vertex when that lies inside. Cheaper than the critical points (no root).
bool slopeKeepsSign(const double c[4], double lo, double hi);

/// True when the cubic's slope keeps one strict sign over [lo, hi], so that one root at most
/// lies there (cubicRootsInRange's quick path). Inline: asked for nearly every voxel solved.
inline bool cubicMonotonicIn(const double c[4], double lo, double hi) {
  // Most prisms are nearly straight: the slope then keeps c1's sign over the whole range
  // (|c1| beats the other terms of the derivative).
  const double r = std::max(std::abs(lo), std::abs(hi));
  if (std::abs(c[1]) > 1.01 * (2 * std::abs(c[2]) * r + 3 * std::abs(c[3]) * r * r)) return true;
  return slopeKeepsSign(c, lo, hi);
}

}  // namespace rangefuse::internal
