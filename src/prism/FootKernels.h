// The arithmetic of one point's foot, shared by the one-point solve (Prism.cpp, CubicRoots.cpp)
// and the batched one (PrismFeet.cpp) so that both give the same bits: scalars in, scalars
// out, inlined into the batch's loops, which the compiler then vectorises.
#pragma once

#include "PrismSolve.h"
#include "rangefuse/prism/Prism.h"

namespace rangefuse::internal {

/// The cubic c0 + c1 x + c2 x^2 + c3 x^3 at x (Horner), its slope and its second derivative.
inline double evalCubic(const double c[4], double x) {
  return ((c[3] * x + c[2]) * x + c[1]) * x + c[0];
}
inline double evalSlope(const double c[4], double x) {
  return (3 * c[3] * x + 2 * c[2]) * x + c[1];
}
inline double evalCurvature(const double c[4], double x) {
  return 6 * c[3] * x + 2 * c[2];
}

/// a . b grouped as Eigen groups a Vector3d's dot product: a0 b0 + (a1 b1 + a2 b2).
inline double dot3(double ax, double ay, double az, double bx, double by, double bz) {
  return ax * bx + (ay * by + az * bz);
}

/// Eq. 6's coefficients c0, c1, c2 at the point (x, y, z); c3 is cubic.Ln.
inline void footCubic(const PrismCubic& cubic, const Eigen::Vector3d& p0, double x, double y,
                      double z, double& c0, double& c1, double& c2) {
  const double wx = p0.x() - x, wy = p0.y() - y, wz = p0.z() - z;
  c0 = dot3(cubic.N.x(), cubic.N.y(), cubic.N.z(), wx, wy, wz);
  c1 = cubic.Nn + dot3(cubic.K.x(), cubic.K.y(), cubic.K.z(), wx, wy, wz);
  c2 = cubic.Kn + dot3(cubic.L.x(), cubic.L.y(), cubic.L.z(), wx, wy, wz);
}

/// The first two barycentric coordinates of the point (x, y, z) in the iso-triangle T(d) (the
/// third is 1 - b0 - b1).
inline void footBarycentric(const Prism& prism, const PrismCubic& cubic, double x, double y,
                            double z, double d, double& b0, double& b1) {
  const Eigen::Vector3d &N = cubic.N, &K = cubic.K, &L = cubic.L;
  double m[3], q[3][3];  // T(d)'s normal; T(d)'s corners less the point
  for (int k = 0; k < 3; ++k) m[k] = N[k] + d * (K[k] + d * L[k]);
  for (int j = 0; j < 3; ++j) {
    q[j][0] = prism.p[j].x() - x + d * prism.n[j].x();
    q[j][1] = prism.p[j].y() - y + d * prism.n[j].y();
    q[j][2] = prism.p[j].z() - z + d * prism.n[j].z();
  }
  const auto tripleWithM = [&](const double* u, const double* v) {
    return dot3(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0],
                m[0], m[1], m[2]);
  };
  const double area = dot3(m[0], m[1], m[2], m[0], m[1], m[2]);
  b0 = tripleWithM(q[1], q[2]) / area;
  b1 = tripleWithM(q[2], q[0]) / area;
}

}  // namespace rangefuse::internal
