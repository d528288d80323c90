// The closest point of a triangle to a point: the geometry distances to scans and meshes share.
#pragma once

#include <Eigen/Core>

namespace rangefuse {

/// Closest point to p on triangle (a, b, c), exact in every region (vertex, edge, face).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// The same, as barycentric coordinates (weights of a, b, c).
Eigen::Vector3d closestBarycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace rangefuse
