// The joint solve of all poses against brute force: the same least-squares problem with every
// voxel's offset kept as an unknown, solved densely.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "rangefuse/register/JointSolve.h"

using namespace rangefuse;

namespace {

/// Random voxels shared by 2-4 of `scans` scans: planes through random points, noisy offsets.
std::vector<std::vector<VoxelShare>> randomVoxels(size_t voxels, uint32_t scans, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), w(0.2, 1);
  const MotionFrame frame{Eigen::Vector3d(0.1, -0.2, 0.3), 2.0};
  std::vector<std::vector<VoxelShare>> out(voxels);
  for (auto& shares : out) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const Eigen::Vector3d f = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    for (uint32_t s = 0; s < scans; ++s) {
      if (shares.size() >= 2 && u(rng) < 0) continue;
      VoxelShare share;
      share.scan = s;
      const int points = 1 + static_cast<int>(rng() % 3);
      for (int k = 0; k < points; ++k)
        share.add(p + 0.01 * Eigen::Vector3d(u(rng), u(rng), u(rng)), f, 0.1 * u(rng), w(rng),
                  frame);
      shares.push_back(share);
    }
  }
  return out;
}

/// Minimises Σ_v Σ_s m_s (r̄_s + ā_s δ_s − μ_v)² over δ of the free scans and every μ_v.
std::vector<Vector6d> bruteForce(const std::vector<std::vector<VoxelShare>>& voxels, uint32_t scans,
                                 const std::vector<char>& free) {
  std::vector<int> column(scans, -1);
  int n = 0;
  for (uint32_t s = 0; s < scans; ++s)
    if (free[s]) column[s] = 6 * n++;
  const int unknowns = 6 * n + static_cast<int>(voxels.size());
  int rows = 0;
  for (const auto& shares : voxels) rows += static_cast<int>(shares.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, unknowns);
  Eigen::VectorXd b(rows);
  int row = 0;
  for (size_t v = 0; v < voxels.size(); ++v)
    for (const VoxelShare& s : voxels[v]) {
      const double sw = std::sqrt(s.weight);
      if (column[s.scan] >= 0) A.block<1, 6>(row, column[s.scan]) = sw * s.jacobian / s.weight;
      A(row, 6 * n + static_cast<int>(v)) = -sw;
      b[row++] = -sw * s.residual / s.weight;
    }
  const Eigen::VectorXd x = A.colPivHouseholderQr().solve(b);
  std::vector<Vector6d> delta(scans, Vector6d::Zero());
  for (uint32_t s = 0; s < scans; ++s)
    if (column[s] >= 0) delta[s] = x.segment<6>(column[s]);
  return delta;
}

}  // namespace

TEST(JointSolve, MatchesBruteForceWithTheVoxelOffsetsAsUnknowns) {
  const uint32_t scans = 4;
  const auto voxels = randomVoxels(80, scans, 7);
  const std::vector<char> free = {0, 1, 1, 1};  // scan 0 is the anchor
  const std::vector<Vector6d> expected = bruteForce(voxels, scans, free);
  const std::vector<Vector6d> got = solveJoint(jointEquations(voxels, scans), free, 0);
  EXPECT_EQ(got[0], Vector6d::Zero());
  for (uint32_t s = 1; s < scans; ++s) {
    EXPECT_GT(expected[s].norm(), 1e-3);  // a problem with an answer to find
    EXPECT_LT((got[s] - expected[s]).norm(), 1e-9 * expected[s].norm()) << "scan " << s;
  }
}

TEST(JointSolve, AVoxelOneScanAloneSawAddsNothing) {
  const MotionFrame frame;
  VoxelShare share;
  share.add(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d::UnitZ(), 0.5, 1, frame);
  share.add(Eigen::Vector3d(1, 2, 4), Eigen::Vector3d::UnitZ(), -0.5, 1, frame);
  const JointEquations eq = jointEquations({{share}}, 1);
  EXPECT_TRUE(eq.blocks.empty());
  EXPECT_EQ(eq.gradient[0], Vector6d::Zero());
  EXPECT_EQ(eq.points[0], 0u);
}

TEST(JointSolve, PlanesOffsetFromTheAnchorsMoveOntoIt) {
  // Scans 1 and 2 see a plane z = const at offsets +0.2 and -0.2 of the anchor's (0). Each
  // voxel holds all three; the solution moves 1 and 2 onto the anchor's plane along z.
  const MotionFrame frame;
  std::vector<std::vector<VoxelShare>> voxels;
  for (int x = -3; x <= 3; ++x)
    for (int y = -3; y <= 3; ++y) {
      std::vector<VoxelShare> shares(3);
      const double offset[3] = {0, 0.2, -0.2};
      for (uint32_t s = 0; s < 3; ++s) {
        shares[s].scan = s;
        shares[s].add(Eigen::Vector3d(x, y, offset[s]), Eigen::Vector3d::UnitZ(), offset[s], 1,
                      frame);
      }
      voxels.push_back(shares);
    }
  const std::vector<Vector6d> d = solveJoint(jointEquations(voxels, 3), {0, 1, 1}, 0);
  EXPECT_NEAR(d[1][5], -0.2, 1e-12);
  EXPECT_NEAR(d[2][5], 0.2, 1e-12);
  EXPECT_LT(d[1].head<5>().norm(), 1e-12);  // nothing constrains x, y, or turns about z
}

TEST(JointSolve, MotionPoseIsTheLinearisedMotionForSmallSteps) {
  const MotionFrame frame{Eigen::Vector3d(1, 2, 3), 5.0};
  Vector6d delta;
  delta << 1e-6, -2e-6, 3e-6, 4e-6, 5e-6, -6e-6;
  const Pose m = motionPose(delta, frame);
  const Eigen::Vector3d p(4, -1, 2);
  const Eigen::Vector3d linear =
      (delta.head<3>() / frame.length).cross(p - frame.centre) + Eigen::Vector3d(delta.tail<3>());
  EXPECT_LT((m.apply(p) - p - linear).norm(), 1e-11);
  EXPECT_LT((motionPose(Vector6d::Zero(), frame).apply(p) - p).norm(), 1e-15);
}
