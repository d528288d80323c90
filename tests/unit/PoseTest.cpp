// Pose composition, inverse and relative motion against applying transforms point by point;
// the one rotation check against rotations, rounded rotations, scalings and reflections.
#include <gtest/gtest.h>

#include <random>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/Pose.h"

using namespace rangefuse;

namespace {

Pose randomPose(std::mt19937& rng) {
  std::normal_distribution<double> n;
  const Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return Pose{q.normalized().toRotationMatrix(), Eigen::Vector3d(n(rng), n(rng), n(rng))};
}

/// R rounded to `digits` decimals, as a text file prints it.
Eigen::Matrix3d rounded(const Eigen::Matrix3d& R, int digits) {
  const double scale = std::pow(10.0, digits);
  return R.unaryExpr([&](double v) { return std::round(v * scale) / scale; });
}

TEST(Pose, ComposeInverseAndRelativeMatchApplyingThePosesInTurn) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose a = randomPose(rng), b = randomPose(rng);
    const Eigen::Vector3d p(rng() % 100 / 10.0, -2.5, 0.125);
    EXPECT_LT(((a * b).apply(p) - a.apply(b.apply(p))).norm(), 1e-12);
    EXPECT_LT((a.inverse().apply(a.apply(p)) - p).norm(), 1e-12);
    EXPECT_LT(((a * relative(a, b)).apply(p) - b.apply(p)).norm(), 1e-12);
    EXPECT_LT((relative(a, b).apply(p) - a.inverse().apply(b.apply(p))).norm(), 1e-12);
  }
}

TEST(Pose, RotationsAndRotationsPrintedTo8DigitsPassTheCheck) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d R = randomPose(rng).R;
    EXPECT_EQ(rotationProblem(R), "");
    const Eigen::Matrix3d printed = rounded(R, 8);
    EXPECT_EQ(rotationProblem(printed), "");
    // Read as the nearest rotation: exact to rounding, within the printing of the file.
    const Pose read = rigidPose(Pose{printed, Eigen::Vector3d::Zero()}, "f");
    EXPECT_TRUE((read.R.transpose() * read.R).isIdentity(1e-12));
    EXPECT_GT(read.R.determinant(), 0);
    EXPECT_LT((read.R - R).norm(), 1e-7);
  }
  // 7-Scenes prints its poses so that R^T R is off by up to 3.8e-4: still a rotation.
  Eigen::Matrix3d sevenScenes = Eigen::Matrix3d::Identity();
  sevenScenes(0, 0) = 1 + 1.9e-4;
  EXPECT_EQ(rotationProblem(sevenScenes), "");
}

TEST(Pose, AnExactRotationIsKeptBitForBit) {
  std::mt19937 rng(3);
  const Pose p = randomPose(rng);
  const Pose kept = rigidPose(p, "f");
  EXPECT_EQ(kept.R, p.R);
  EXPECT_EQ(kept.t, p.t);
}

TEST(Pose, ScalingsReflectionsAndNonFiniteMatricesAreNamed) {
  Eigen::Matrix3d z2 = Eigen::Matrix3d::Identity();
  z2(2, 2) = 2;
  EXPECT_NE(rotationProblem(z2).find("not rigid"), std::string::npos);
  EXPECT_NE(rotationProblem(z2).find("scales lengths by 1 to 2"), std::string::npos);
  Eigen::Matrix3d onePercent = Eigen::Matrix3d::Identity() * 1.01;
  EXPECT_NE(rotationProblem(onePercent), "");
  Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
  mirror(0, 0) = -1;
  EXPECT_NE(rotationProblem(mirror).find("a reflection"), std::string::npos);
  Eigen::Matrix3d bad = Eigen::Matrix3d::Identity();
  bad(1, 1) = NAN;
  EXPECT_EQ(rotationProblem(bad), "not finite");
  try {
    rigidPose(Pose{z2, Eigen::Vector3d::Zero()}, "station 3");
    ADD_FAILURE() << "a scaling was read as a pose";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("station 3: the pose's rotation is not rigid"),
              std::string::npos);
  }
  EXPECT_THROW(rigidPose(Pose{Eigen::Matrix3d::Identity(), Eigen::Vector3d(INFINITY, 0, 0)}, "f"),
               InputError);
}

}  // namespace
