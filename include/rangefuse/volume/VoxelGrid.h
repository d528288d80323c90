// The global voxel lattice: voxel (i,j,k) has its centre at origin + voxel * (i,j,k).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "rangefuse/core/Rounding.h"

namespace rangefuse {

using VoxelIndex = Eigen::Vector3i;

struct VoxelGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double voxel = 1.0;
  int brick = 8;  ///< bricks are brick^3 voxels

  Eigen::Vector3d centre(const VoxelIndex& v) const { return origin + voxel * v.cast<double>(); }

  /// Continuous lattice coordinate of p along `axis` (voxel centres at integers).
  double coord(const Eigen::Vector3d& p, int axis) const {
    return (p[axis] - origin[axis]) / voxel;
  }

  /// Nearest voxel centre (Tubic Eq. 15).
  VoxelIndex nearest(const Eigen::Vector3d& p) const {
    return VoxelIndex(static_cast<int>(std::floor(coord(p, 0) + 0.5)),
                      static_cast<int>(std::floor(coord(p, 1) + 0.5)),
                      static_cast<int>(std::floor(coord(p, 2) + 0.5)));
  }

  /// Voxels whose centres lie inside `box`: [lo, hi] inclusive (empty if lo > hi).
  void voxelRange(const Eigen::AlignedBox3d& box, VoxelIndex& lo, VoxelIndex& hi) const {
    for (int a = 0; a < 3; ++a) {
      lo[a] = ceilToInt(coord(box.min(), a));
      hi[a] = floorToInt(coord(box.max(), a));
    }
  }
};

/// Floor division, for brick coordinates of negative voxel indices.
inline int floorDiv(int a, int b) {
  // Bricks of 8 (the default) or any power of two: a shift, not a division (a voxel's brick is
  // asked at every voxel a prism holds). GCC and Clang shift negative ints arithmetically.
  if ((b & (b - 1)) == 0) return a >> __builtin_ctz(static_cast<unsigned>(b));
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

}  // namespace rangefuse
