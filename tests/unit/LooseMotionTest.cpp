#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "rangefuse/register/LooseMotion.h"
#include "rangefuse/register/Stragglers.h"

namespace rangefuse {
namespace {

/// Accumulates the joint solve's point-to-plane block Σ a aᵀ, a = [(p − c) × n / L, n], of
/// points p with unit normals n: what a scan whose points lie on these surfaces adds.
struct Block {
  MotionFrame frame;
  Matrix6d sum = Matrix6d::Zero();
  void add(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    Vector6d a;
    a << (p - frame.centre).cross(n) / frame.length, n;
    sum += a * a.transpose();
  }
};

constexpr double kPi = 3.14159265358979323846;

/// A torus (tube radius r about a circle of radius R) about `axis` through `centre`.
void addTorus(Block& b, const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double R,
              double r) {
  const Eigen::Quaterniond turn =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis);
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 36; ++j) {
      const double u = 2 * kPi * i / 90, v = 2 * kPi * j / 36;
      const Eigen::Vector3d n(std::cos(u) * std::cos(v), std::sin(u) * std::cos(v), std::sin(v));
      const Eigen::Vector3d ring(R * std::cos(u), R * std::sin(u), 0);
      b.add(centre + turn * (ring + r * n), turn * n);
    }
}

void addSphere(Block& b, const Eigen::Vector3d& centre, double r) {
  for (int i = 0; i < 40; ++i)
    for (int j = 1; j < 20; ++j) {
      const double u = 2 * kPi * i / 40, v = kPi * j / 20;
      const Eigen::Vector3d n(std::cos(u) * std::sin(v), std::sin(u) * std::sin(v), std::cos(v));
      b.add(centre + r * n, n);
    }
}

TEST(LooseMotion, ATorusTurnsFreelyAboutItsAxisAndNothingElse) {
  Block b{{Eigen::Vector3d(1, 2, 3), 60}};
  const Eigen::Vector3d centre(6, -3, 2), axis = Eigen::Vector3d(0, 0.6, 0.8);
  addTorus(b, centre, axis, 30, 10);
  addSphere(b, centre + 20 * axis, 12);  // on the axis: the scene keeps its symmetry
  const LooseMotion m = loosestMotion(b.sum, b.frame);
  EXPECT_EQ(m.looseWays, 1);
  EXPECT_LT(m.hold, 1e-6);
  ASSERT_TRUE(m.turn);
  EXPECT_GT(std::abs(m.axis.dot(axis)), 1 - 1e-9);
  // The axis point nearest the frame's centre.
  const Eigen::Vector3d nearest = centre + axis * axis.dot(b.frame.centre - centre);
  EXPECT_LT((m.through - nearest).norm(), 1e-6);
}

TEST(LooseMotion, ASphereTurnsThreeWaysAboutItsCentre) {
  Block b{{Eigen::Vector3d(-4, 0, 1), 40}};
  const Eigen::Vector3d centre(3, 5, -2);
  addSphere(b, centre, 15);
  const LooseMotion m = loosestMotion(b.sum, b.frame);
  EXPECT_EQ(m.looseWays, 3);
  ASSERT_TRUE(m.turn);
  // Any axis through the centre will do: the one found passes through it.
  EXPECT_LT((centre - m.through).cross(m.axis).norm(), 1e-6);
}

TEST(LooseMotion, APlaneSlidesTwoWaysAndTurnsAboutItsNormal) {
  Block b{{Eigen::Vector3d::Zero(), 50}};
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) b.add(Eigen::Vector3d(i, j, 7), Eigen::Vector3d::UnitZ());
  EXPECT_EQ(loosestMotion(b.sum, b.frame).looseWays, 3);
}

TEST(LooseMotion, ASphereOffTheAxisHoldsEveryMotion) {
  Block b{{Eigen::Vector3d(8, 0, 16), 70}};
  addTorus(b, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 30, 12);
  addSphere(b, Eigen::Vector3d(50, 0, -4), 8);
  const LooseMotion m = loosestMotion(b.sum, b.frame);
  EXPECT_EQ(m.looseWays, 0);
  EXPECT_GT(m.hold, kLooseHold);
}

TEST(LooseMotion, NoOverlapHoldsNothing) {
  const LooseMotion m = loosestMotion(Matrix6d::Zero(), MotionFrame{});
  EXPECT_EQ(m.hold, 0);
  EXPECT_EQ(m.looseWays, 6);
}

TEST(LooseMotion, LooseScansAreTheJointFitsHeldBelowTheLimit) {
  std::vector<RegistrationStep> steps(3);
  for (size_t k = 0; k < 3; ++k) steps[k].scan = k, steps[k].loose.hold = 0.5;
  steps[1].loose.hold = 0.5 * kLooseHold;
  const std::vector<ScanStanding> loose = findLooseScans(lastStandings(steps));
  ASSERT_EQ(loose.size(), 1u);
  EXPECT_EQ(loose[0].scan, 1u);
}

}  // namespace
}  // namespace rangefuse
