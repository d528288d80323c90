#include <algorithm>
#include <cmath>

#include "rangefuse/prism/Prism.h"

namespace rangefuse::internal {
namespace {

/// Newton steps every point takes before its last step is checked: from the linear root of a
/// nearly straight prism's cubic, three steps nearly always reach the root to rounding.
constexpr int kNewtonSteps = 3;

double cubicAt(const double c[4], double x) {
  return ((c[3] * x + c[2]) * x + c[1]) * x + c[0];
}
double slopeAt(const double c[4], double x) {
  return (3 * c[3] * x + 2 * c[2]) * x + c[1];
}

/// Eq. 6's coefficients at every point.
void coefficients(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d* points, int n,
                  double (*c)[4]) {
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d w = prism.p[0] - points[i];
    c[i][0] = cubic.N.dot(w);
    c[i][1] = cubic.Nn + cubic.K.dot(w);
    c[i][2] = cubic.Kn + cubic.L.dot(w);
    c[i][3] = cubic.Ln;
  }
}

/// True when d, a root Newton converged to, lies in [lo, hi] and no other root lies as near the
/// generator: the cubic is monotonic from -|d| to |d|. A cubic that turns in the envelope (a
/// tilted prism's, far from the generator) then needs no search of all its roots when the
/// nearest one's iso-triangle holds the point, which solvePrismFoot would pick.
bool nearestRootInside(const double c[4], double d, double lo, double hi) {
  if (!(d >= lo && d <= hi)) return false;
  const double r = std::abs(d);
  return cubicMonotonicIn(c, std::max(lo, -r), std::min(hi, r));
}

/// The foot of a point whose cubic turns in [lo, hi] (or whose Newton steps did not settle):
/// most such cubics still have one root there: `newton`, the last Newton step, when it settled
/// (a root) in that root's piece, else the root found in the piece from it; the few cubics
/// with several roots in range are searched in full.
void solveTurning(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d& x,
                  const double c[4], double newton, bool settled, const Eigen::Vector3d& bary,
                  PrismFoot& foot, bool& inside) {
  double a, b;
  const int roots = rootBrackets(c, prism.dMin, prism.dMax, a, b);
  if (roots == 0) {
    inside = false;
  } else if (roots == 1 && settled && newton >= a && newton <= b) {
    inside = baryInside(bary);
    if (inside) foot = PrismFoot{newton, bary};
  } else if (roots == 1) {
    const double d = rootBetween(c, a, b, newton);
    const Eigen::Vector3d at = isoBarycentric(prism, cubic, x, d);
    inside = baryInside(at);
    if (inside) foot = PrismFoot{d, at};
  } else {
    inside = solvePrismFoot(prism, cubic, x, foot);
  }
}

}  // namespace

void solveFeet(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d* points, int n,
               PrismFoot* feet, bool* inside) {
  double c[kFootBatch][4], d[kFootBatch];
  bool root[kFootBatch];
  const double lo = prism.dMin, hi = prism.dMax;
  coefficients(prism, cubic, points, n, c);
  // Each loop below runs over every point without branching on it: the points' chains of
  // divisions overlap.
  for (int i = 0; i < n; ++i) {
    const double fa = cubicAt(c[i], lo), fb = cubicAt(c[i], hi);
    root[i] = (fa < 0) != (fb < 0) || fa == 0 || fb == 0;
    d[i] = std::clamp(-c[i][0] / c[i][1], lo, hi);
  }
  for (int step = 0; step < kNewtonSteps; ++step)
    for (int i = 0; i < n; ++i)
      d[i] = std::clamp(d[i] - cubicAt(c[i], d[i]) / slopeAt(c[i], d[i]), lo, hi);
  // After the last step the error is about f''/(2 f') times its square (bracketedRoot's test).
  bool converged[kFootBatch], tiny[kFootBatch];
  for (int i = 0; i < n; ++i) {
    const double tol = 1e-15 * (1 + std::abs(d[i]));
    const double slope = slopeAt(c[i], d[i]), last = cubicAt(c[i], d[i]) / slope;
    const double curvature = 6 * c[i][3] * d[i] + 2 * c[i][2];
    converged[i] = std::abs(curvature) * last * last <= 2 * tol * std::abs(slope);  // NaN: false
    tiny[i] = std::abs(last) <= 1e-9 * (hi - lo);  // a root, not a clamped end of a line
    d[i] -= last;
  }
  Eigen::Vector3d b[kFootBatch];
  for (int i = 0; i < n; ++i) b[i] = isoBarycentric(prism, cubic, points[i], d[i]);
  for (int i = 0; i < n; ++i) {
    if (converged[i] && cubicMonotonicIn(c[i], lo, hi)) {
      inside[i] = root[i] && baryInside(b[i]);  // false without area (coordinates not finite)
      if (inside[i]) feet[i] = PrismFoot{d[i], b[i]};
    } else if (converged[i] && tiny[i] && nearestRootInside(c[i], d[i], lo, hi) &&
               baryInside(b[i])) {
      inside[i] = true;
      feet[i] = PrismFoot{d[i], b[i]};
    } else {
      solveTurning(prism, cubic, points[i], c[i], d[i], converged[i] && tiny[i], b[i], feet[i],
                   inside[i]);
    }
  }
}

}  // namespace rangefuse::internal
