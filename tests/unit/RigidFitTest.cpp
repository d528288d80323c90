#include <gtest/gtest.h>

#include <random>

#include "rangefuse/register/Registration.h"
#include "rangefuse/register/RigidFit.h"

using namespace rangefuse;

namespace {

Pose randomMotion(std::mt19937& rng, double maxDeg) {
  std::uniform_real_distribution<double> u(-1, 1);
  Pose p;
  const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  p.R = Eigen::AngleAxisd(maxDeg * M_PI / 180 * u(rng), axis).toRotationMatrix();
  p.t = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 5;
  return p;
}

}  // namespace

TEST(RigidFit, RecoversExactTransformsUpTo30Degrees) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10, 10), w(0.1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose truth = randomMotion(rng, 30);
    RigidSums sums;
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d p(u(rng), u(rng), u(rng));
      sums.add(p, truth.apply(p), w(rng));
    }
    const Pose fit = fitRigid(sums);
    EXPECT_LT((fit.R - truth.R).norm(), 1e-12);
    EXPECT_LT((fit.t - truth.t).norm(), 1e-11);
  }
}

TEST(RigidFit, NoisyCorrespondencesGiveTheTransformWithinNoise) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-10, 10);
  std::normal_distribution<double> noise(0, 0.05);
  const Pose truth = randomMotion(rng, 30);
  RigidSums sums;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    sums.add(p, truth.apply(p) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)), 1);
  }
  const Pose fit = fitRigid(sums);
  EXPECT_LT(rotationDegrees(fit.R * truth.R.transpose()), 0.01);
  EXPECT_LT((fit.t - truth.t).norm(), 0.01);
  EXPECT_NEAR(sums.rms(), 0, 10);  // defined before the fit: the raw offsets
}

TEST(RigidFit, SumsAddAcrossParts) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-10, 10);
  const Pose truth = randomMotion(rng, 10);
  RigidSums whole, a, b;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    whole.add(p, truth.apply(p), 1);
    (i % 2 ? a : b).add(p, truth.apply(p), 1);
  }
  a += b;
  EXPECT_LT((fitRigid(a).R - fitRigid(whole).R).norm(), 1e-12);
  EXPECT_EQ(fitRigid(RigidSums{}).R, Eigen::Matrix3d::Identity());  // too few points
}
