// The growing field of Algorithm 1 against a fresh build of the same scans, voxel by voxel:
// the fast path (scans added in place, each bringing its new bricks) must give the simple
// one's values and bricks.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <map>

#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/pipeline/RegistrationField.h"
#include "rangefuse/route/ScanLoader.h"

using namespace rangefuse;

namespace {

constexpr double kFieldVoxel = 0.002;  // 2 mm: the real bunny scans, quickly

using VoxelKey = std::pair<uint64_t, uint32_t>;  // brick code, voxel within the brick
using VoxelValues = std::map<VoxelKey, std::array<float, 6>>;

/// Every observed voxel of a distributed field, gathered on every rank.
VoxelValues observedVoxels(const BrickStore& store) {
  std::vector<char> mine;
  const size_t per = store.voxelsPerBrick();
  for (size_t b = 0; b < store.brickCount(); ++b)
    for (uint32_t k = 0; k < per; ++k) {
      const VoxelSums& s = store.sums()[b * per + k];
      if (s.w == 0 && s.images == 0) continue;
      const uint64_t code = store.code(b);
      const std::array<float, 6> v{s.wd, s.w, s.wf[0], s.wf[1], s.wf[2], s.images};
      mpi::pack(mine, &code, 1);
      mpi::pack(mine, &k, 1);
      mpi::pack(mine, v.data(), v.size());
    }
  VoxelValues all;
  for (const auto& part : mpi::allgatherBytes(mine, MPI_COMM_WORLD))
    for (size_t at = 0; at < part.size();) {
      VoxelKey key;
      std::array<float, 6> v;
      mpi::unpack(part, at, &key.first, 1);
      mpi::unpack(part, at, &key.second, 1);
      mpi::unpack(part, at, v.data(), v.size());
      all[key] = v;
    }
  return all;
}

/// Same voxels, same bits.
void expectIdentical(const VoxelValues& a, const VoxelValues& b) {
  ASSERT_EQ(a.size(), b.size());
  size_t differing = 0;
  for (auto ia = a.begin(), ib = b.begin(); ia != a.end(); ++ia, ++ib)
    differing += ia->first != ib->first ||
                 std::memcmp(ia->second.data(), ib->second.data(), sizeof(float) * 6) != 0;
  EXPECT_EQ(differing, 0u) << "of " << a.size() << " voxels";
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
  const VoxelValues a = observedVoxels(fast), b = observedVoxels(simple);
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
