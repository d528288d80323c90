#include "rangefuse/core/TriangleClosest.h"

#include <Eigen/Geometry>  // cross() is defined here, not in Eigen/Core
#include <algorithm>
#include <cmath>

namespace rangefuse {

namespace {

/// Where along [a, b] (0 at a) the segment comes closest to p; 0 for a point.
double alongSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double length2 = (b - a).squaredNorm();
  return length2 > 0 ? std::clamp((p - a).dot(b - a) / length2, 0.0, 1.0) : 0.0;
}

/// A triangle without area is its three edges: the closest of their closest points.
Eigen::Vector3d closestOnEdges(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double s = alongSegment(p, a, b), t = alongSegment(p, b, c), u = alongSegment(p, c, a);
  const Eigen::Vector3d candidates[3] = {{1 - s, s, 0}, {0, 1 - t, t}, {u, 0, 1 - u}};
  Eigen::Vector3d best = candidates[0];
  double nearest = INFINITY;
  for (const Eigen::Vector3d& w : candidates) {
    const double d = (p - (w[0] * a + w[1] * b + w[2] * c)).squaredNorm();
    if (d < nearest) nearest = d, best = w;
  }
  return best;
}

}  // namespace

// Voronoi-region walk over the triangle's vertices, edges and face.
Eigen::Vector3d closestBarycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  // Marching cubes leaves triangles with two corners at one point, where the walk divides by 0.
  if (ab.cross(ac).squaredNorm() == 0) return closestOnEdges(p, a, b, c);
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = va + vb + vc;
  if (denom == 0) return {1, 0, 0};  // degenerate triangle: its vertex regions cover it
  return {1 - (vb + vc) / denom, vb / denom, vc / denom};
}

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d w = closestBarycentric(p, a, b, c);
  return w[0] * a + w[1] * b + w[2] * c;
}

}  // namespace rangefuse
