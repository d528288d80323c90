#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "rangefuse/eval/PoseConsistency.h"

using namespace rangefuse;

namespace {

/// A square grid of points in the plane z = 0, 0.1 apart, normals +z, moved by `pose`.
ScanSurface plane(int n, const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity()) {
  ScanSurface s;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      s.points.push_back(pose * Eigen::Vector3d(0.1 * i, 0.1 * j, 0));
      s.normals.push_back(pose.linear() * Eigen::Vector3d::UnitZ());
      s.confidence.push_back(1);
    }
  return s;
}

ConsistencySettings settings() {
  ConsistencySettings s;
  s.maxDistance = 1;
  s.maxTangential = 0.1;
  s.stride = 1;
  return s;
}

}  // namespace

TEST(PoseConsistency, ParallelPlanesGiveTheirSeparation) {
  Eigen::Isometry3d up = Eigen::Isometry3d::Identity();
  up.translation() = Eigen::Vector3d(0.03, 0.02, 0.25);  // across the plane: no effect
  const auto c = poseConsistency({plane(20), plane(20, up)}, settings());
  ASSERT_EQ(c.size(), 2u);
  for (const auto& s : c) {
    EXPECT_NEAR(s.rms, 0.25, 1e-12);
    EXPECT_GE(s.pairs, 19u * 19u);
  }
}

TEST(PoseConsistency, TurningWithinThePlaneCostsNothing) {
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto c = poseConsistency({plane(20), plane(20, turn)}, settings());
  EXPECT_GT(c[0].pairs, 100u);
  EXPECT_NEAR(c[0].rms, 0, 1e-12);
}

TEST(PoseConsistency, SlidingAlongThePlaneKeepsTheRmsButLosesPartners) {
  // Point-to-plane RMS cannot see a scan slide along a flat surface; the partners each pair
  // keeps can: sliding by half the patch halves them.
  Eigen::Isometry3d slide = Eigen::Isometry3d::Identity();
  slide.translation() = Eigen::Vector3d(0.95, 0.0, 0.0);  // 19 spacings of 0.1: half of 1.9
  const auto still = poseConsistency({plane(20), plane(20)}, settings());
  const auto slid = poseConsistency({plane(20), plane(20, slide)}, settings());
  ASSERT_EQ(still[0].pairsWith.size(), 2u);
  EXPECT_EQ(still[0].pairsWith[1], 400u);
  EXPECT_EQ(still[0].sampled, 400u);
  EXPECT_NEAR(slid[0].rmsWith[1], 0, 1e-12);
  EXPECT_NEAR(slid[1].rmsWith[0], 0, 1e-12);
  for (int k : {0, 1}) {
    const size_t kept = slid[k].pairsWith[1 - k];
    EXPECT_GE(kept, 180u) << k;
    EXPECT_LE(kept, 220u) << k;  // about half of 400
    EXPECT_EQ(slid[k].pairs, kept);
  }
}

TEST(PoseConsistency, OppositeFacesAndFarScansAreNotOverlap) {
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  flip.translation() = Eigen::Vector3d(0, 1.9, 0.01);  // the back of a thin sheet
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() = Eigen::Vector3d(0, 0, 5);
  const auto c = poseConsistency({plane(20), plane(20, flip), plane(20, far)}, settings());
  for (const auto& s : c) EXPECT_EQ(s.pairs, 0u);
}

TEST(PoseConsistency, MatchesBruteForceOnANoisyPatch) {
  // A bumpy patch against a noisy, slightly moved copy: the k-d tree result must equal the
  // residuals found by trying every vertex.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.01);
  ScanSurface a = plane(15), b = plane(15);
  for (auto& p : a.points) p.z() = 0.05 * std::sin(3 * p.x()) + noise(rng);
  for (auto& p : b.points)
    p = Eigen::Vector3d(p.x() + 0.04, p.y() - 0.03, 0.05 * std::sin(3 * p.x()) + 0.02 + noise(rng));
  const ConsistencySettings s = settings();
  double sum = 0;
  size_t pairs = 0;
  for (size_t v = 0; v < a.points.size(); ++v) {
    size_t best = 0;
    for (size_t w = 1; w < b.points.size(); ++w)
      if ((b.points[w] - a.points[v]).squaredNorm() < (b.points[best] - a.points[v]).squaredNorm())
        best = w;
    const Eigen::Vector3d d = a.points[v] - b.points[best];
    const double along = b.normals[best].dot(d);
    if (std::abs(along) > s.maxDistance || (d - along * b.normals[best]).norm() > s.maxTangential)
      continue;
    sum += along * along;
    ++pairs;
  }
  const auto c = poseConsistency({a, b}, s);
  ASSERT_GT(pairs, 100u);
  EXPECT_EQ(c[0].pairs, pairs);
  EXPECT_NEAR(c[0].rms, std::sqrt(sum / static_cast<double>(pairs)), 1e-12);
}
