// The pose graph and the key-frame fit of loop closure (src/track) against known answers and
// brute force.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "track/KeyFrameFit.h"
#include "track/PoseGraph.h"

namespace rangefuse::internal {
namespace {

Pose turnAbout(const Eigen::Vector3d& axis, double angle, const Eigen::Vector3d& t) {
  return Pose{Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(), t};
}

/// n cameras on a circle of radius 2 looking at its centre.
std::vector<Pose> ring(size_t n) {
  std::vector<Pose> poses;
  for (size_t k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    poses.push_back(
        turnAbout(Eigen::Vector3d::UnitZ(), a, 2 * Eigen::Vector3d(std::cos(a), std::sin(a), 0)));
  }
  return poses;
}

double worstOffset(const std::vector<Pose>& a, const std::vector<Pose>& b) {
  double worst = 0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, (a[k].t - b[k].t).norm());
  return worst;
}

TEST(PoseGraph, ConsistentRingReturnsToTheTruthFromDriftedPoses) {
  const std::vector<Pose> truth = ring(12);
  std::vector<PoseEdge> edges;
  for (size_t k = 0; k < truth.size(); ++k) {
    PoseEdge e;
    e.from = k, e.to = (k + 1) % truth.size();
    e.measured = relative(truth[e.from], truth[e.to]);
    edges.push_back(e);
  }
  // Each pose after the first drifted by a turn and a shift growing along the ring.
  std::vector<Pose> poses = truth;
  for (size_t k = 1; k < poses.size(); ++k)
    poses[k] =
        turnAbout(Eigen::Vector3d(1, 2, 3), 0.01 * k, Eigen::Vector3d(0.02 * k, 0, -0.01 * k)) *
        poses[k];
  ASSERT_GT(worstOffset(poses, truth), 0.2);
  const double cost = optimisePoseGraph(poses, edges);
  EXPECT_LT(cost, 1e-16);
  EXPECT_LT(worstOffset(poses, truth), 1e-9);
  EXPECT_EQ(poses[0].t, truth[0].t);  // the first holds the world frame
}

TEST(PoseGraph, LoopEdgeSpreadsBiasedOdometryAroundTheLoop) {
  // Odometry that overestimates every step's turn by 0.5 degrees drifts; a loop edge from the
  // last pose back to the first takes most of that drift out.
  const std::vector<Pose> truth = ring(24);
  std::vector<PoseEdge> edges;
  std::vector<Pose> poses = {truth[0]};
  const Pose bias = turnAbout(Eigen::Vector3d::UnitZ(), 0.5 * M_PI / 180, Eigen::Vector3d::Zero());
  for (size_t k = 0; k + 1 < truth.size(); ++k) {
    PoseEdge e;
    e.from = k, e.to = k + 1;
    e.measured = relative(truth[k], truth[k + 1]) * bias;
    poses.push_back(poses.back() * e.measured);
    edges.push_back(e);
  }
  PoseEdge loop;
  loop.from = 0, loop.to = truth.size() - 1;
  loop.measured = relative(truth[0], truth.back());
  loop.information *= 100;
  edges.push_back(loop);
  const double before = worstOffset(poses, truth);
  const double cost = graphCost(poses, edges);
  optimisePoseGraph(poses, edges);
  EXPECT_LT(graphCost(poses, edges), 0.1 * cost);
  EXPECT_LT(worstOffset(poses, truth), 0.25 * before) << "before " << before;
}

/// Points on three faces of a box corner and a bump: a shape that pins every motion.
KeyFramePoints corner(double spacing) {
  std::vector<Eigen::Vector3d> points, normals;
  for (double u = 0; u < 1; u += spacing)
    for (double v = 0; v < 1; v += spacing) {
      points.emplace_back(u, v, 0), normals.emplace_back(0, 0, 1);
      points.emplace_back(u, 0, v), normals.emplace_back(0, 1, 0);
      points.emplace_back(0, u, v), normals.emplace_back(1, 0, 0);
    }
  for (double a = 0; a < M_PI / 2; a += spacing)
    for (double b = 0; b < 2 * M_PI; b += spacing) {
      const Eigen::Vector3d n(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a));
      points.push_back(Eigen::Vector3d(0.5, 0.5, 0) + 0.2 * n), normals.push_back(n);
    }
  return KeyFramePoints(std::move(points), std::move(normals));
}

TEST(KeyFrameFit, NearestMatchesBruteForce) {
  const KeyFramePoints target = corner(0.05);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  for (int q = 0; q < 200; ++q) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    double best = INFINITY;
    for (const Eigen::Vector3d& t : target.points()) best = std::min(best, (t - p).norm());
    const long j = target.nearest(p, 0.1);
    if (best > 0.1) {
      EXPECT_EQ(j, -1);
    } else {
      ASSERT_GE(j, 0);
      EXPECT_NEAR((target.points()[static_cast<size_t>(j)] - p).norm(), best, 1e-12);
    }
  }
}

TEST(KeyFrameFit, RecoversAKnownMotion) {
  const KeyFramePoints target = corner(0.02);
  const Pose motion =
      turnAbout(Eigen::Vector3d(1, -1, 2), 3 * M_PI / 180, Eigen::Vector3d(0.03, -0.02, 0.04));
  // The source sees the same surface from where `motion` puts it: source = motion^-1 target.
  std::vector<Eigen::Vector3d> points, normals;
  for (size_t i = 0; i < target.points().size(); ++i) {
    points.push_back(motion.inverse().apply(target.points()[i]));
    normals.push_back(motion.R.transpose() * target.normals()[i]);
  }
  const KeyFramePoints source(std::move(points), std::move(normals));
  EXPECT_LT(overlapShare(target, source, Pose{}, 0.01), 0.5);
  PairFitSettings s;
  s.startRadius = 0.1, s.endRadius = 0.02, s.huber = 0.01;
  const PairFit fit = fitPair(target, source, Pose{}, s);
  EXPECT_LT((fit.motion.t - motion.t).norm(), 1e-6);
  EXPECT_LT((fit.motion.R - motion.R).norm(), 1e-6);
  EXPECT_GT(fit.inliers, 0.99);
  EXPECT_LT(fit.rms, 1e-6);
  EXPECT_NEAR(overlapShare(target, source, fit.motion, 1e-3), 1.0, 1e-12);
  // Every direction pinned: the information is positive definite.
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(fit.information).eigenvalues()(0), 0);
}

}  // namespace
}  // namespace rangefuse::internal
