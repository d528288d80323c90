// fuse/VoxelCheck.h: a voxel in the wrong units is named with the likely intended one; a
// plausible voxel says nothing.
#include <gtest/gtest.h>

#include "rangefuse/pipeline/VoxelCheck.h"

namespace rangefuse {
namespace {

Eigen::AlignedBox3d bunnySized() {  // the Stanford bunny in metres: 0.155 across
  return Eigen::AlignedBox3d(Eigen::Vector3d(-0.095, 0.033, -0.062),
                             Eigen::Vector3d(0.061, 0.187, 0.059));
}

TEST(VoxelCheck, AVoxelInMillimetresOnScansInMetresIsNamed) {
  const std::string w = voxelUnitWarning(1, bunnySized());
  EXPECT_NE(w.find("--voxel 1 gives 0.156 voxels across"), std::string::npos) << w;
  EXPECT_NE(w.find("did you mean 0.001?"), std::string::npos) << w;
}

TEST(VoxelCheck, AVoxelFarTooSmallIsNamedToo) {
  const std::string w = voxelUnitWarning(1e-6, bunnySized());
  EXPECT_NE(w.find("did you mean 0.001?"), std::string::npos) << w;
  EXPECT_NE(voxelUnitWarning(
                0.5, Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1e5, 1, 1)))
                .find("did you mean 500?"),
            std::string::npos);
}

TEST(VoxelCheck, PlausibleVoxelsAndEmptyBoundsSayNothing) {
  for (double voxel : {0.0005, 0.001, 0.002, 0.005})
    EXPECT_EQ(voxelUnitWarning(voxel, bunnySized()), "") << voxel;
  EXPECT_EQ(voxelUnitWarning(
                0.01, Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(8, 6, 3))),
            "");  // a room at 1 cm: 800 across
  EXPECT_EQ(voxelUnitWarning(1, Eigen::AlignedBox3d()), "");
}

}  // namespace
}  // namespace rangefuse
