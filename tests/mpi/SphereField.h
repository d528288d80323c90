// A sphere's distance field in bricks of 4^3 unit voxels, for the distributed mesh and render
// tests: known answers that cross rank boundaries.
#pragma once

#include <algorithm>
#include <cmath>

#include "rangefuse/volume/BrickStore.h"

namespace rangefuse::test {

inline const Eigen::Vector3d kCentre(20.3, 19.6, 20.2);
inline const double kRadius = 12.2;

inline double sphere(const Eigen::Vector3d& p) {
  return (p - kCentre).norm() - kRadius;
}

/// Bricks of 4^3 unit voxels within reach of the sphere, split over `ranks`.
inline BrickLayout sphereLayout(int ranks) {
  BrickLayout l;
  l.grid.brick = 4;
  for (int z = 0; z < 12; ++z)
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x) {
        Eigen::Vector3d centre = 4.0 * Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(1.5);
        if (std::abs(sphere(centre)) < 6) l.codes.push_back(mortonEncode({x, y, z}));
      }
  std::sort(l.codes.begin(), l.codes.end());
  l.work.assign(l.codes.size(), 1);
  l.setRuns(partitionWork(l.work, ranks));
  return l;
}

/// A distance field observed within 3 voxels of the surface.
inline void fillSphere(BrickStore& store) {
  const int B = store.grid().brick;
  for (size_t b = 0; b < store.brickCount(); ++b) {
    BrickCoord base = mortonDecode(store.code(b)) * B;
    for (int z = 0; z < B; ++z)
      for (int y = 0; y < B; ++y)
        for (int x = 0; x < B; ++x) {
          VoxelIndex v = base + VoxelIndex(x, y, z);
          double d = sphere(store.grid().centre(v));
          VoxelSums& s = store.sums()[store.offset(b, v)];
          if (std::abs(d) > 3) continue;
          const Eigen::Vector3d n = (store.grid().centre(v) - kCentre).normalized();
          s = VoxelSums{static_cast<float>(d), 1, {float(n.x()), float(n.y()), float(n.z())}, 1};
        }
  }
}

}  // namespace rangefuse::test
