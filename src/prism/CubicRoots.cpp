#include <algorithm>
#include <cmath>

#include "FootKernels.h"
#include "PrismSolve.h"
#include "rangefuse/prism/Prism.h"

namespace rangefuse::internal {
namespace {

/// Root of a function monotonic on [a, b] with a sign change: Newton kept inside the
/// bracket, bisection when it would leave it. Newton stops once the step it would take next,
/// about f''/(2 f') times the square of this one, is below the tolerance: the same accuracy
/// as waiting for that step, one evaluation sooner.
double bracketedRoot(const double c[4], double a, double b, double fa, double start) {
  double x = start;
  for (int it = 0; it < 60; ++it) {
    double fx = evalCubic(c, x);
    if (fx == 0) return x;
    if ((fx < 0) == (fa < 0))
      a = x, fa = fx;
    else
      b = x;
    const double slope = evalSlope(c, x), tol = 1e-15 * (1 + std::abs(x));
    double nx = slope != 0 ? x - fx / slope : 0.5 * (a + b);
    const bool newton = nx > a && nx < b;
    if (!newton) nx = 0.5 * (a + b);
    const double step = std::abs(nx - x);
    if (step <= tol) return nx;
    if (newton && std::abs(evalCurvature(c, x)) * step * step <= 2 * tol * std::abs(slope))
      return nx;
    x = nx;
  }
  return x;
}

/// Critical points of the cubic strictly inside (lo, hi), ascending.
int criticalPoints(const double c[4], double lo, double hi, double out[2]) {
  double a = 3 * c[3], b = 2 * c[2], k = c[1];
  double xs[2];
  int n = 0;
  if (a == 0) {
    if (b != 0) xs[n++] = -k / b;
  } else {
    double disc = b * b - 4 * a * k;
    if (disc >= 0) {
      double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      if (q != 0) {
        xs[n++] = q / a;
        xs[n++] = k / q;
      } else {
        xs[n++] = 0;
      }
    }
  }
  if (n == 2 && xs[1] < xs[0]) std::swap(xs[0], xs[1]);  // ascending (std::sort costs a call)
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (xs[i] > lo && xs[i] < hi) out[m++] = xs[i];
  return m;
}

/// The root in [lo, hi] of a cubic known to be monotonic there, if any.
int monotonicRoot(const double c[4], double lo, double hi, double roots[3]) {
  const double fa = evalCubic(c, lo), fb = evalCubic(c, hi);
  if (fa == 0 || fb == 0) {
    roots[0] = fa == 0 ? lo : hi;
    return 1;
  }
  if ((fa < 0) == (fb < 0)) return 0;
  // Nearly linear: Newton from the linear root converges in a step or two.
  double start = -c[0] / c[1];
  if (!(start > lo && start < hi)) start = 0.5 * (lo + hi);
  roots[0] = bracketedRoot(c, lo, hi, fa, start);
  return 1;
}

}  // namespace

bool slopeKeepsSign(const double c[4], double lo, double hi) {
  const double sLo = evalSlope(c, lo), sHi = evalSlope(c, hi);
  if (!(sLo * sHi > 0)) return false;
  if (c[3] == 0) return true;
  const double vertex = -c[2] / (3 * c[3]);
  return !(vertex > lo && vertex < hi) || evalSlope(c, vertex) * sLo > 0;
}

int rootBrackets(const double c[4], double lo, double hi, double& a, double& b) {
  double knots[4] = {lo};
  int nk = 1 + criticalPoints(c, lo, hi, knots + 1);
  knots[nk++] = hi;
  int n = 0;
  double fa = evalCubic(c, lo);
  for (int i = 1; i < nk; ++i) {
    const double fb = evalCubic(c, knots[i]);
    // A root on a knot, or a value that is not a number: the caller searches.
    if (fa == 0 || fb == 0 || !std::isfinite(fa) || !std::isfinite(fb)) return -1;
    if ((fa < 0) != (fb < 0)) ++n, a = knots[i - 1], b = knots[i];
    fa = fb;
  }
  return n;
}

double rootBetween(const double c[4], double a, double b, double guess) {
  const double fa = evalCubic(c, a);
  if (guess > a && guess < b) return bracketedRoot(c, a, b, fa, guess);
  return bracketedRoot(c, a, b, fa, a - fa * (b - a) / (evalCubic(c, b) - fa));  // secant start
}

int cubicRootsInRange(const double c[4], double lo, double hi, double roots[3]) {
  if (cubicMonotonicIn(c, lo, hi)) return monotonicRoot(c, lo, hi, roots);
  double knots[4] = {lo};
  int nk = 1 + criticalPoints(c, lo, hi, knots + 1);
  knots[nk++] = hi;
  int nr = 0;
  for (int i = 0; i + 1 < nk; ++i) {
    double a = knots[i], b = knots[i + 1];
    double fa = evalCubic(c, a), fb = evalCubic(c, b);
    double r;
    if (fa == 0)
      r = a;
    else if (fb == 0)
      r = b;
    else if ((fa < 0) != (fb < 0))
      r = bracketedRoot(c, a, b, fa, a - fa * (b - a) / (fb - fa));  // secant start
    else
      continue;
    if (nr == 0 || r != roots[nr - 1]) roots[nr++] = r;
  }
  return nr;
}

}  // namespace rangefuse::internal
