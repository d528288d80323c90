#include <algorithm>
#include <cmath>

#include "FootKernels.h"
#include "PrismSolve.h"
#include "rangefuse/prism/Prism.h"

namespace rangefuse::internal {
namespace {

/// Newton steps every point takes before its last step is checked: from the linear root of a
/// nearly straight prism's cubic, three steps nearly always reach the root to rounding.
constexpr int kNewtonSteps = 3;

/// A batch of points as a structure of arrays: the loops over it have no branch and no
/// stride, so the compiler keeps two points in each SSE2 register. Each point's arithmetic is
/// FootKernels.h's, as for one point at a time: the same bits.
struct Batch {
  int n = 0;
  double x[3][kFootBatch];                                ///< the points' coordinates
  double c0[kFootBatch], c1[kFootBatch], c2[kFootBatch];  ///< Eq. 6 (c3: the prism's Ln)
  double fLo[kFootBatch], fHi[kFootBatch];                ///< the cubic at the envelope's ends
  double d[kFootBatch];                                   ///< the root, as Newton leaves it
  double last[kFootBatch], error[kFootBatch], bound[kFootBatch];  ///< the last step's test
  double b[3][kFootBatch];  ///< barycentric coordinates of each point in T(d)
};

/// Eq. 6's coefficients, the cubic at lo and hi, and Newton's start (the linear root).
void coefficients(const PrismCubic& cubic, const Eigen::Vector3d& p0, double lo, double hi,
                  Batch& s) {
  const double c3 = cubic.Ln;
  for (int i = 0; i < s.n; ++i) {
    double c0, c1, c2;
    footCubic(cubic, p0, s.x[0][i], s.x[1][i], s.x[2][i], c0, c1, c2);
    const double c[4] = {c0, c1, c2, c3};
    s.c0[i] = c0, s.c1[i] = c1, s.c2[i] = c2;
    s.fLo[i] = evalCubic(c, lo);
    s.fHi[i] = evalCubic(c, hi);
    s.d[i] = std::clamp(-c0 / c1, lo, hi);
  }
}

/// kNewtonSteps steps, then the last one taken apart: its size and bracketedRoot's test of it
/// (the error after it is about f''/(2 f') times its square).
void newtonSteps(double c3, double lo, double hi, Batch& s) {
  for (int step = 0; step < kNewtonSteps; ++step)
    for (int i = 0; i < s.n; ++i) {
      const double c[4] = {s.c0[i], s.c1[i], s.c2[i], c3};
      s.d[i] = std::clamp(s.d[i] - evalCubic(c, s.d[i]) / evalSlope(c, s.d[i]), lo, hi);
    }
  for (int i = 0; i < s.n; ++i) {
    const double c[4] = {s.c0[i], s.c1[i], s.c2[i], c3}, d = s.d[i];
    const double tol = 1e-15 * (1 + std::abs(d));
    const double slope = evalSlope(c, d), last = evalCubic(c, d) / slope;
    const double curvature = evalCurvature(c, d);
    s.error[i] = std::abs(curvature) * last * last;
    s.bound[i] = 2 * tol * std::abs(slope);
    s.last[i] = last;
    s.d[i] = d - last;
  }
}

/// isoBarycentric at every point and its d.
void isoBarycentric(const Prism& prism, const PrismCubic& cubic, Batch& s) {
  for (int i = 0; i < s.n; ++i) {
    double b0, b1;
    footBarycentric(prism, cubic, s.x[0][i], s.x[1][i], s.x[2][i], s.d[i], b0, b1);
    s.b[0][i] = b0, s.b[1][i] = b1, s.b[2][i] = 1 - b0 - b1;
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
  Batch s;
  s.n = n;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) s.x[k][i] = points[i][k];
  const double lo = prism.dMin, hi = prism.dMax, c3 = cubic.Ln;
  coefficients(cubic, prism.p[0], lo, hi, s);
  newtonSteps(c3, lo, hi, s);
  isoBarycentric(prism, cubic, s);
  for (int i = 0; i < n; ++i) {
    const double c[4] = {s.c0[i], s.c1[i], s.c2[i], c3}, d = s.d[i];
    const Eigen::Vector3d b(s.b[0][i], s.b[1][i], s.b[2][i]);
    const bool converged = s.error[i] <= s.bound[i];            // NaN: false
    const bool tiny = std::abs(s.last[i]) <= 1e-9 * (hi - lo);  // a root, not a clamped end
    if (converged && cubicMonotonicIn(c, lo, hi)) {
      const double fa = s.fLo[i], fb = s.fHi[i];
      const bool root = (fa < 0) != (fb < 0) || fa == 0 || fb == 0;
      inside[i] = root && baryInside(b);  // false without area (coordinates not finite)
      if (inside[i]) feet[i] = PrismFoot{d, b};
    } else if (converged && tiny && nearestRootInside(c, d, lo, hi) && baryInside(b)) {
      inside[i] = true;
      feet[i] = PrismFoot{d, b};
    } else {
      solveTurning(prism, cubic, points[i], c, d, converged && tiny, b, feet[i], inside[i]);
    }
  }
}

}  // namespace rangefuse::internal
