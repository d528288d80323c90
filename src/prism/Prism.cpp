#include "rangefuse/prism/Prism.h"

#include <algorithm>
#include <cmath>

#include "FootKernels.h"
#include "PrismSolve.h"

namespace rangefuse {
namespace {

double det3(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return a.dot(b.cross(c));
}

/// Roots of a0 + a1 u + a2 u^2 in [0, 1]; none when the polynomial vanishes identically.
int quadraticRootsUnit(double a0, double a1, double a2, double scale, double out[2]) {
  const double tiny = 1e-14 * scale;
  int n = 0;
  double xs[2];
  if (std::abs(a2) <= tiny) {
    if (std::abs(a1) > tiny) xs[n++] = -a0 / a1;
  } else {
    double disc = a1 * a1 - 4 * a2 * a0;
    if (disc < 0) return 0;
    double q = -0.5 * (a1 + std::copysign(std::sqrt(disc), a1));
    xs[n++] = q / a2;
    if (q != 0) xs[n++] = a0 / q;
  }
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (xs[i] >= -1e-12 && xs[i] <= 1 + 1e-12) out[m++] = std::clamp(xs[i], 0.0, 1.0);
  return m;
}

/// Eq. 9: where the line p_i + v n_i meets the edge surface spanned by (pa,na)-(pb,nb);
/// tightens [lo, hi] with every d and v of a meeting inside the envelope (Eq. 10).
void truncateAtEdgeSurface(const Eigen::Vector3d& pi, const Eigen::Vector3d& ni,
                           const Eigen::Vector3d& pa, const Eigen::Vector3d& na,
                           const Eigen::Vector3d& pb, const Eigen::Vector3d& nb, double eps,
                           double& lo, double& hi) {
  const Eigen::Vector3d A = pa - pi, B = pb - pa, C = na, D = nb - na;
  if (internal::crossingBeyond(A, B, na, nb, ni, eps)) return;  // most prisms: normals barely turn
  // X(u) = A + uB must lie in span(Y(u) = C + uD, n_i): det[X, Y, n_i] = 0.
  double a0 = det3(A, C, ni), a1 = det3(B, C, ni) + det3(A, D, ni), a2 = det3(B, D, ni);
  double scale = (A.norm() + B.norm()) * (C.norm() + D.norm());
  double us[2];
  int nu = quadraticRootsUnit(a0, a1, a2, scale, us);
  for (int k = 0; k < nu; ++k) {
    const Eigen::Vector3d X = A + us[k] * B, Y = C + us[k] * D;
    // X + d Y - v n_i = 0 holds exactly at a root; solve its normal equations for (d, v).
    const double yy = Y.dot(Y), yn = Y.dot(ni), nn = ni.dot(ni);
    const double det = yy * nn - yn * yn;
    if (!(std::abs(det) > 1e-14 * yy * nn)) continue;  // Y parallel to n_i: no crossing
    const double xy = X.dot(Y), xn = X.dot(ni);
    const double d = (-xy * nn + xn * yn) / det, v = (xn * yy - xy * yn) / det;
    if (d < -eps || d > eps) continue;
    for (double s : {d, v}) {
      if (s > 0) hi = std::min(hi, s);
      if (s < 0) lo = std::max(lo, s);
    }
  }
}

}  // namespace

Prism makePrism(const std::array<Eigen::Vector3d, 3>& p, const std::array<Eigen::Vector3d, 3>& n,
                const std::array<double, 3>& w, double eps) {
  Prism prism{p, n, w, -eps, eps};
  const internal::EnvelopeClearance clearance(p, n, eps);
  for (int i = 0; i < 3; ++i) {
    if (clearance.clear[i]) continue;  // truncateAtEdgeSurface's quick exit, found sooner
    int a = (i + 1) % 3, b = (i + 2) % 3;
    truncateAtEdgeSurface(p[i], n[i], p[a], n[a], p[b], n[b], eps, prism.dMin, prism.dMax);
  }
  return prism;
}

Eigen::AlignedBox3d prismBounds(const Prism& prism) {
  Eigen::AlignedBox3d box;
  for (int i = 0; i < 3; ++i) {
    box.extend(prism.p[i] + prism.dMin * prism.n[i]);
    box.extend(prism.p[i] + prism.dMax * prism.n[i]);
  }
  return box;
}

namespace internal {

// A meeting has X(u) + d Y(u) = v n_i; across n_i that is |d| = |X(u)⊥| / |Y(u)⊥|, where |X⊥|
// is at least the distance of the edge (A + uB, seen along n_i) from the line and |Y⊥| at most
// the larger of the end normals' (Y runs from na to nb).
bool crossingBeyond(const Eigen::Vector3d& A, const Eigen::Vector3d& B, const Eigen::Vector3d& na,
                    const Eigen::Vector3d& nb, const Eigen::Vector3d& ni, double eps) {
  const double nn = ni.squaredNorm();
  if (!(nn > 0)) return false;
  // One reciprocal, not a division per projection: the bound's 1e-6 margin covers the rounding.
  const double inv = 1 / nn;
  auto across = [&](const Eigen::Vector3d& x) { return x - (x.dot(ni) * inv) * ni; };
  const Eigen::Vector3d a = across(A), b = across(B);
  const double bb = b.squaredNorm();
  const double t = bb > 0 ? std::clamp(-a.dot(b) / bb, 0.0, 1.0) : 0.0;
  const double edge2 = (a + t * b).squaredNorm();
  const double tilt2 = std::max(across(na).squaredNorm(), across(nb).squaredNorm());
  return edge2 > (1 + 1e-6) * eps * eps * tilt2 + 1e-300;
}

EnvelopeClearance::EnvelopeClearance(const std::array<Eigen::Vector3d, 3>& p,
                                     const std::array<Eigen::Vector3d, 3>& n, double eps) {
  const Eigen::Vector3d X = (p[1] - p[0]).cross(p[2] - p[0]);
  const double nn[3] = {n[0].squaredNorm(), n[1].squaredNorm(), n[2].squaredNorm()};
  // Per vertex k: the normals' dot product of the other two, and the squared edge facing it.
  const double dot[3] = {n[1].dot(n[2]), n[2].dot(n[0]), n[0].dot(n[1])};
  const double e2[3] = {(p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm(),
                        (p[1] - p[0]).squaredNorm()};
  const double eps2 = eps * eps, longest = std::max({e2[0], e2[1], e2[2]});
  for (int i = 0; i < 3; ++i) {
    const int a = (i + 1) % 3, b = (i + 2) % 3;
    // |n_i|^2 times the squared tilts of n_a and n_b across n_i (no division, no root).
    const double tiltA = nn[i] * nn[a] - dot[b] * dot[b], tiltB = nn[i] * nn[b] - dot[a] * dot[a];
    const double across = n[i].dot(X);
    const double bound = (1 + 1e-3) * eps2 * e2[i] * std::max(tiltA, tiltB) +
                         1e-12 * (longest + eps2 * std::max(nn[a], nn[b])) * nn[i] * e2[i];
    clear[i] = across * across > bound;  // NaN or a zero normal: not cleared
  }
}

PrismCubic::PrismCubic(const Prism& prism) {
  const Eigen::Vector3d e1 = prism.p[1] - prism.p[0], e2 = prism.p[2] - prism.p[0];
  const Eigen::Vector3d f1 = prism.n[1] - prism.n[0], f2 = prism.n[2] - prism.n[0];
  N = e1.cross(e2);
  K = e1.cross(f2) + f1.cross(e2);
  L = f1.cross(f2);
  Nn = N.dot(prism.n[0]), Kn = K.dot(prism.n[0]), Ln = L.dot(prism.n[0]);
}

Eigen::Vector3d isoBarycentric(const Prism& prism, const PrismCubic& cubic,
                               const Eigen::Vector3d& x, double d) {
  Eigen::Vector3d b;
  footBarycentric(prism, cubic, x.x(), x.y(), x.z(), d, b[0], b[1]);
  b[2] = 1 - b[0] - b[1];
  return b;
}

bool solvePrismFoot(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d& x,
                    PrismFoot& foot) {
  double c[4] = {0, 0, 0, cubic.Ln};
  footCubic(cubic, prism.p[0], x.x(), x.y(), x.z(), c[0], c[1], c[2]);
  double roots[3];
  const int nr = cubicRootsInRange(c, prism.dMin, prism.dMax, roots);
  bool found = false;
  for (int k = 0; k < nr; ++k) {
    const double d = roots[k];
    if (found && std::abs(d) >= std::abs(foot.d)) continue;
    const Eigen::Vector3d b = isoBarycentric(prism, cubic, x, d);
    if (!baryInside(b)) continue;
    foot.d = d;
    foot.bary = b;
    found = true;
  }
  return found;
}

void completeHit(const Prism& prism, const PrismFoot& foot, PrismHit& hit) {
  const Eigen::Vector3d& b = foot.bary;
  hit.d = foot.d;
  hit.bary = b;
  hit.closest = b[0] * prism.p[0] + b[1] * prism.p[1] + b[2] * prism.p[2];
  hit.gradient = footGradient(prism, b);
  hit.weight = footWeight(prism, b);
}

bool solvePrismDistance(const Prism& prism, const PrismCubic& cubic, const Eigen::Vector3d& x,
                        PrismHit& hit) {
  PrismFoot foot;
  if (!solvePrismFoot(prism, cubic, x, foot)) return false;
  completeHit(prism, foot, hit);
  return true;
}

}  // namespace internal

bool solvePrismDistance(const Prism& prism, const Eigen::Vector3d& x, PrismHit& hit) {
  return internal::solvePrismDistance(prism, internal::PrismCubic(prism), x, hit);
}

}  // namespace rangefuse
