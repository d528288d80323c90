// The growing field of Algorithm 1 against a fresh build of the same scans, voxel by voxel:
// the fast path (scans added in place, each bringing its new bricks) must give the simple
// one's values and bricks.
#include <gtest/gtest.h>

#include "ObservedVoxels.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/pipeline/RegistrationField.h"
#include "rangefuse/route/ScanLoader.h"

using namespace rangefuse;

namespace {

constexpr double kFieldVoxel = 0.002;  // 2 mm: the real bunny scans, quickly

using test::expectIdentical;

/// Every observed voxel of the field, gathered on every rank.
test::VoxelValues observedVoxels(const BrickStore& store) {
  return test::observedVoxels(store, MPI_COMM_WORLD);
}

RunSettings bunnySettings() {
  FuseOptions o;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.field.voxel = kFieldVoxel;
  return runSettings(o);
}

LoadedScans bunnyScans(const RunSettings& s) {
  Progress progress(MPI_COMM_WORLD);
  LoadedScans scans;
  EXPECT_TRUE(loadScans(s.read, MPI_COMM_WORLD, progress, scans));
  return scans;
}

std::unique_ptr<RegistrationField> growingField(const RunSettings& s, const LoadedScans& scans) {
  return makeRegistrationField(s.field, RegistrationFieldMode::Grow, "", scans, MPI_COMM_WORLD);
}

/// `pose` moved by `shift` and turned by `degrees` about the bunny's middle.
Pose moved(const Pose& pose, const Eigen::Vector3d& shift, double degrees) {
  const Eigen::Vector3d centre(-0.017, 0.110, -0.002);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d(1, 2, 0.5).normalized())
          .toRotationMatrix();
  return Pose{R * pose.R, R * (pose.t - centre) + centre + shift};
}

}  // namespace

TEST(RegistrationField, GrownFieldEqualsAFreshBuildVoxelByVoxel) {
  const RunSettings o = bunnySettings();
  const LoadedScans scans = bunnyScans(o);
  std::vector<Pose> poses = scans.poses;
  auto grown = growingField(o, scans);
  grown->fixLattice({}, poses);
  grown->build({0}, poses);
  grown->add(1, poses);  // the bricks it reaches join the field
  poses[3] = moved(poses[3], Eigen::Vector3d(3, -2, 1) * kFieldVoxel, 1);
  grown->add(3, poses);
  poses[5] = moved(poses[5], Eigen::Vector3d(0, 20, 0) * kFieldVoxel, 2);
  const BrickStore& fast = grown->add(5, poses);  // far from the others: many new bricks

  auto fresh = growingField(o, scans);
  fresh->fixLattice(grown->latticeOrigin(), poses);
  const BrickStore& simple = fresh->build({0, 1, 3, 5}, poses);
  const test::VoxelValues a = observedVoxels(fast), b = observedVoxels(simple);
  EXPECT_GT(a.size(), 10000u);
  expectIdentical(a, b);
  // Bricks on demand: the grown field holds the bricks the scans reach and no room around them.
  EXPECT_EQ(fast.layout().totalBricks(), simple.layout().totalBricks());
}

TEST(RegistrationField, LatticeMovesWhenAScanLeavesIt) {
  const RunSettings o = bunnySettings();
  const LoadedScans scans = bunnyScans(o);
  std::vector<Pose> poses = scans.poses;
  auto grown = growingField(o, scans);
  const std::vector<double> before = grown->fixLattice({}, poses);
  grown->build({0, 1}, poses);
  poses[2] = moved(poses[2], Eigen::Vector3d(-0.2, 0, 0), 0);  // 100 voxels: past the margin
  const BrickStore& fast = grown->add(2, poses);
  const std::vector<double> after = grown->latticeOrigin();
  EXPECT_LT(after[0], before[0] - 0.15);
  EXPECT_EQ(after[1], before[1]);

  auto fresh = growingField(o, scans);
  EXPECT_EQ(fresh->fixLattice({}, poses), after);  // what a run started here would choose
  expectIdentical(observedVoxels(fast), observedVoxels(fresh->build({0, 1, 2}, poses)));
}
