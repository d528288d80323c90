#include <algorithm>
#include <cmath>

#include "rangefuse/prism/Prism.h"

namespace rangefuse::internal {
namespace {

/// Newton steps every point takes before its last step is checked: from the linear root of a
/// nearly straight prism's cubic, three steps nearly always reach the root to rounding.
constexpr int kNewtonSteps = 3;

double cubicAt(const double c[3], double c3, double x) {
  return ((c3 * x + c[2]) * x + c[1]) * x + c[0];
}
double slopeAt(const double c[3], double c3, double x) {
  return (3 * c3 * x + 2 * c[2]) * x + c[1];
}

/// True when the slope (a quadratic) keeps one strict sign over [lo, hi], so that the cubic has
/// one root at most there: c1 outweighs the slope's other terms (most prisms, nearly straight),
/// or the slope has one sign at both ends and at its vertex (cubicRootsInRange's two tests).
bool monotonic(const double c[3], double c3, double lo, double hi) {
  const double r = std::max(std::abs(lo), std::abs(hi));
  if (std::abs(c[1]) > 1.01 * (2 * std::abs(c[2]) * r + 3 * std::abs(c3) * r * r)) return true;
  const double sLo = slopeAt(c, c3, lo), sHi = slopeAt(c, c3, hi);
  if (!(sLo * sHi > 0)) return false;
  if (c3 == 0) return true;
  const double vertex = -c[2] / (3 * c3);
  return !(vertex > lo && vertex < hi) || slopeAt(c, c3, vertex) * sLo > 0;
}

/// Eq. 6's coefficients at every point (c3 is the prism's alone).
void coefficients(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d* points, int n,
                  double (*c)[3]) {
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d w = prism.p[0] - points[i];
    c[i][0] = cubic.N.dot(w);
    c[i][1] = cubic.Nn + cubic.K.dot(w);
    c[i][2] = cubic.Kn + cubic.L.dot(w);
  }
}

/// Barycentric coordinates of x in the iso-triangle T(d) (the same products as solvePrismFoot).
Eigen::Vector3d baryAt(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d& x,
                       double d) {
  const Eigen::Vector3d m = cubic.N + d * (cubic.K + d * cubic.L);
  const Eigen::Vector3d q1 = prism.p[0] - x + d * prism.n[0], q2 = prism.p[1] - x + d * prism.n[1],
                        q3 = prism.p[2] - x + d * prism.n[2];
  Eigen::Vector3d b(q2.cross(q3).dot(m), q3.cross(q1).dot(m), 0);
  b /= m.squaredNorm();
  b[2] = 1 - b[0] - b[1];
  return b;
}

}  // namespace

void solveFeet(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d* points, int n,
               PrismFoot* feet, bool* inside) {
  double c[kFootBatch][3], d[kFootBatch];
  bool settled[kFootBatch], root[kFootBatch];
  const double lo = prism.dMin, hi = prism.dMax, c3 = cubic.Ln;
  coefficients(prism, cubic, points, n, c);
  // Each loop below runs over every point without branching on it: the points' chains of
  // divisions overlap.
  for (int i = 0; i < n; ++i) {
    const double fa = cubicAt(c[i], c3, lo), fb = cubicAt(c[i], c3, hi);
    root[i] = (fa < 0) != (fb < 0) || fa == 0 || fb == 0;
    d[i] = std::clamp(-c[i][0] / c[i][1], lo, hi);
  }
  for (int step = 0; step < kNewtonSteps; ++step)
    for (int i = 0; i < n; ++i)
      d[i] = std::clamp(d[i] - cubicAt(c[i], c3, d[i]) / slopeAt(c[i], c3, d[i]), lo, hi);
  // After the last step the error is about f''/(2 f') times its square (bracketedRoot's test).
  for (int i = 0; i < n; ++i) {
    const double tol = 1e-15 * (1 + std::abs(d[i]));
    const double slope = slopeAt(c[i], c3, d[i]), last = cubicAt(c[i], c3, d[i]) / slope;
    const double curvature = 6 * c3 * d[i] + 2 * c[i][2];
    settled[i] = std::abs(curvature) * last * last <= 2 * tol * std::abs(slope);  // NaN: false
    d[i] -= last;
  }
  for (int i = 0; i < n; ++i) settled[i] = settled[i] && monotonic(c[i], c3, lo, hi);
  Eigen::Vector3d b[kFootBatch];
  for (int i = 0; i < n; ++i) b[i] = baryAt(prism, cubic, points[i], d[i]);
  const double tolerance = -1e-9;
  for (int i = 0; i < n; ++i) {
    if (!settled[i]) {
      inside[i] = solvePrismFoot(prism, cubic, points[i], feet[i]);
      continue;
    }
    // Written so that a NaN coordinate (a triangle without area) is outside.
    inside[i] = root[i] && b[i][0] >= tolerance && b[i][1] >= tolerance && b[i][2] >= tolerance;
    if (inside[i]) feet[i] = PrismFoot{d[i], b[i]};
  }
}

}  // namespace rangefuse::internal
