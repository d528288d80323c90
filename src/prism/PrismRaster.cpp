#include <algorithm>
#include <cmath>

#include "rangefuse/prism/Prism.h"

namespace rangefuse {
namespace {

/// An axis-aligned line: coordinate `ax` free, the other two (b, c) fixed at (yb, yc).
struct Row {
  int ax, b, c;
  double yb, yc;
};

/// Span [lo, hi] along the row's free axis covered by the boundary hits seen so far.
struct Span {
  double lo = INFINITY, hi = -INFINITY;
  void add(double t) {
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
};

/// The row meets the planar triangle q (an iso-triangle T(dMin) or T(dMax)).
void hitTriangle(const Row& r, const std::array<Eigen::Vector3d, 3>& q, Span& span) {
  double ub = q[1][r.b] - q[0][r.b], uc = q[1][r.c] - q[0][r.c];
  double vb = q[2][r.b] - q[0][r.b], vc = q[2][r.c] - q[0][r.c];
  double den = ub * vc - vb * uc;
  if (den == 0) return;
  double pb = r.yb - q[0][r.b], pc = r.yc - q[0][r.c];
  double l1 = (pb * vc - vb * pc) / den, l2 = (ub * pc - pb * uc) / den;
  const double tol = -1e-9;
  if (l1 < tol || l2 < tol || 1 - l1 - l2 < tol) return;
  span.add((1 - l1 - l2) * q[0][r.ax] + l1 * q[1][r.ax] + l2 * q[2][r.ax]);
}

/// The row meets the edge surface (1-u)(pa + d na) + u(pb + d nb), u in [0,1], d in range.
void hitEdgeSurface(const Row& r, const Eigen::Vector3d& pa, const Eigen::Vector3d& na,
                    const Eigen::Vector3d& pb, const Eigen::Vector3d& nb, double dMin, double dMax,
                    Span& span) {
  const double Ab = pa[r.b] - r.yb, Ac = pa[r.c] - r.yc;
  const double Bb = pb[r.b] - pa[r.b], Bc = pb[r.c] - pa[r.c];
  const double Cb = na[r.b], Cc = na[r.c], Db = nb[r.b] - na[r.b], Dc = nb[r.c] - na[r.c];
  auto point = [&](double u, double d) {
    return ((1 - u) * (pa[r.ax] + d * na[r.ax]) + u * (pb[r.ax] + d * nb[r.ax]));
  };
  // Eliminating d from the two fixed coordinates leaves a quadratic in u.
  const double k0 = Ac * Cb - Cc * Ab, k1 = Ac * Db + Bc * Cb - Cc * Bb - Dc * Ab;
  const double k2 = Bc * Db - Dc * Bb;
  const double scale = (std::abs(Ab) + std::abs(Ac) + std::abs(Bb) + std::abs(Bc)) *
                       (std::abs(Cb) + std::abs(Cc) + std::abs(Db) + std::abs(Dc));
  const double tiny = 1e-14 * scale;
  double us[2];
  int nu = 0;
  if (std::abs(k2) > tiny) {
    double disc = k1 * k1 - 4 * k2 * k0;
    if (disc < 0) return;
    double q = -0.5 * (k1 + std::copysign(std::sqrt(disc), k1));
    us[nu++] = q / k2;
    if (q != 0) us[nu++] = k0 / q;
  } else if (std::abs(k1) > tiny) {
    us[nu++] = -k0 / k1;
  }
  const double dTol = 1e-9 * (dMax - dMin);
  for (int i = 0; i < nu; ++i) {
    double u = us[i];
    if (u < -1e-9 || u > 1 + 1e-9) continue;
    double denB = Cb + u * Db, denC = Cc + u * Dc;
    if (std::max(std::abs(denB), std::abs(denC)) <= 1e-12) {
      // Normals along the row: the row runs inside the surface for the whole d range.
      span.add(point(u, dMin));
      span.add(point(u, dMax));
      continue;
    }
    double d = std::abs(denB) > std::abs(denC) ? -(Ab + u * Bb) / denB : -(Ac + u * Bc) / denC;
    if (d >= dMin - dTol && d <= dMax + dTol) span.add(point(u, d));
  }
}

Span rowSpan(const Prism& pr, const Row& r) {
  Span span;
  std::array<Eigen::Vector3d, 3> lo, hi;
  for (int i = 0; i < 3; ++i) {
    lo[i] = pr.p[i] + pr.dMin * pr.n[i];
    hi[i] = pr.p[i] + pr.dMax * pr.n[i];
  }
  hitTriangle(r, lo, span);
  hitTriangle(r, hi, span);
  for (int i = 0; i < 3; ++i) {
    int j = (i + 1) % 3;
    hitEdgeSurface(r, pr.p[i], pr.n[i], pr.p[j], pr.n[j], pr.dMin, pr.dMax, span);
  }
  return span;
}

}  // namespace

void rasterizePrism(const Prism& prism, const VoxelGrid& grid, const PrismVisitor& visit) {
  const Eigen::AlignedBox3d box = prismBounds(prism);
  VoxelIndex lo, hi;
  grid.voxelRange(box, lo, hi);
  if ((lo.array() > hi.array()).any()) return;
  Eigen::Vector3d::Index ax;
  box.sizes().maxCoeff(&ax);  // few, long rows
  Row row{static_cast<int>(ax), static_cast<int>((ax + 1) % 3), static_cast<int>((ax + 2) % 3), 0,
          0};
  PrismHit hit;
  VoxelIndex v;
  for (v[row.b] = lo[row.b]; v[row.b] <= hi[row.b]; ++v[row.b]) {
    row.yb = grid.origin[row.b] + grid.voxel * v[row.b];
    for (v[row.c] = lo[row.c]; v[row.c] <= hi[row.c]; ++v[row.c]) {
      row.yc = grid.origin[row.c] + grid.voxel * v[row.c];
      Span s = rowSpan(prism, row);
      if (!(s.lo <= s.hi)) continue;
      const double pad = 1e-7;  // lattice units; the exact test below decides
      int a0 = std::max(
          lo[row.ax], static_cast<int>(std::ceil((s.lo - grid.origin[row.ax]) / grid.voxel - pad)));
      int a1 =
          std::min(hi[row.ax],
                   static_cast<int>(std::floor((s.hi - grid.origin[row.ax]) / grid.voxel + pad)));
      for (v[row.ax] = a0; v[row.ax] <= a1; ++v[row.ax])
        if (solvePrismDistance(prism, grid.centre(v), hit)) visit(v, hit);
    }
  }
}

void rasterizePrismBruteForce(const Prism& prism, const VoxelGrid& grid,
                              const PrismVisitor& visit) {
  VoxelIndex lo, hi, v;
  grid.voxelRange(prismBounds(prism), lo, hi);
  PrismHit hit;
  for (v.z() = lo.z(); v.z() <= hi.z(); ++v.z())
    for (v.y() = lo.y(); v.y() <= hi.y(); ++v.y())
      for (v.x() = lo.x(); v.x() <= hi.x(); ++v.x())
        if (solvePrismDistance(prism, grid.centre(v), hit)) visit(v, hit);
}

}  // namespace rangefuse
