// A voxel size in the wrong units is the commonest first-run slip (scans in metres, --voxel 1):
// caught from the scans' extent before any work is planned.
#pragma once

#include <Eigen/Geometry>
#include <string>

namespace rangefuse {

/// A warning when `voxel` gives implausibly few (under 20) or many (over 50 000) voxels across
/// the largest side of `bounds`, naming the likely intended voxel (the given one scaled by a
/// power of ten to about 300 voxels across); empty when the voxel is plausible or the bounds
/// are empty. A depth stream's frames are checked by the extent of its first frame.
std::string voxelUnitWarning(double voxel, const Eigen::AlignedBox3d& bounds);

}  // namespace rangefuse
