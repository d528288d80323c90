#include <gtest/gtest.h>

#include <random>

#include "rangefuse/core/Error.h"
#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/scan/Bvh.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;

namespace {

ScanSettings small(int views) {
  ScanSettings s;
  s.views = views;
  s.width = 40;
  s.height = 30;
  return s;
}

std::vector<Eigen::Vector3d> worldPoints(const SyntheticScan& s) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : s.grid.points) out.push_back(s.truth.apply(p));
  return out;
}

}  // namespace

TEST(Bvh, FirstHitMatchesBruteForceOnRandomRays) {
  const TriangleMesh mesh = makeComposite();
  const Bvh bvh(mesh);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  // 800 rays: the brute force costs a minute per 2000 under the sanitizers.
  for (int i = 0; i < 800; ++i) {
    Eigen::Vector3d o(80 * u(rng), 80 * u(rng), 80 * u(rng));
    Eigen::Vector3d target(40 * u(rng), 40 * u(rng), 30 * u(rng));
    Eigen::Vector3d d = (target - o).normalized();
    RayHit a, b;
    const bool fa = bvh.firstHit(o, d, 0, INFINITY, a),
               fb = bvh.firstHitBruteForce(o, d, 0, INFINITY, b);
    ASSERT_EQ(fa, fb);
    if (!fa) continue;
    ++hits;
    EXPECT_EQ(a.t, b.t);
  }
  EXPECT_GT(hits, 200);
}

TEST(SyntheticScanner, NoiselessPointsLieOnTheMesh) {
  const TriangleMesh mesh = makeShape("torus");
  const SyntheticSet set = scanMesh(mesh, small(6));
  const MeshDistance dist(mesh);
  size_t n = 0;
  for (const auto& s : set.scans)
    for (const auto& p : worldPoints(s)) {
      EXPECT_LT(dist.distance(p), 1e-5);  // voxel = 1
      ++n;
    }
  EXPECT_GT(n, 1000u);
}

TEST(SyntheticScanner, PinholeProjectionGivesBackThePixel) {
  const SyntheticSet set = scanMesh(makeShape("sphere"), small(2));
  const RangeGrid& g = set.scans[1].grid;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const int32_t i = g.at(r, c);
      if (i < 0) continue;
      const Eigen::Vector3d& p = g.points[i];
      EXPECT_NEAR(g.pinhole->cx + g.pinhole->fx * p.x() / -p.z(), c, 1e-9);
      EXPECT_NEAR(g.pinhole->cy + g.pinhole->fy * p.y() / -p.z(), r, 1e-9);
    }
}

TEST(SyntheticScanner, NoiseHasTheRequestedSigmaAlongTheRay) {
  const TriangleMesh mesh = makeShape("sphere");
  ScanSettings s = small(4);
  s.width = 120;
  s.height = 90;
  s.noise = 0.5;
  s.voxel = 0.8;
  const SyntheticSet set = scanMesh(mesh, s);
  const Bvh bvh(mesh);
  double sum = 0, sum2 = 0;
  size_t n = 0;
  for (const auto& sc : set.scans)
    for (const auto& p : sc.grid.points) {
      RayHit hit;
      const Eigen::Vector3d dir = sc.truth.R * p.normalized();
      ASSERT_TRUE(bvh.firstHit(sc.truth.t, dir, 0, INFINITY, hit));
      const double e = p.norm() - hit.t;
      sum += e, sum2 += e * e, ++n;
    }
  const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0, 0.02);
  EXPECT_NEAR(sigma, 0.4, 0.02);  // 0.5 voxel x 0.8
}

TEST(SyntheticScanner, OutlierFractionAsRequested) {
  const TriangleMesh mesh = makeShape("sphere");
  ScanSettings s = small(4);
  s.width = 120;
  s.height = 90;
  s.outliers = 0.1;
  const SyntheticSet set = scanMesh(mesh, s);
  const MeshDistance dist(mesh);
  size_t off = 0, n = 0;
  for (const auto& sc : set.scans)
    for (const auto& p : worldPoints(sc)) off += dist.distance(p) > 1e-3, ++n;
  EXPECT_NEAR(double(off) / n, 0.1, 0.015);  // a few outliers land on the surface by chance
}

TEST(SyntheticScanner, PerturbationStatisticsMatchWhatWasAsked) {
  ScanSettings s = small(300);
  s.width = s.height = 4;
  s.rotDeg = 5;
  s.transVox = 3;
  s.voxel = 2;
  const SyntheticSet set = scanMesh(makeShape("sphere"), s);
  EXPECT_TRUE(set.scans[0].perturbed.R.isApprox(set.scans[0].truth.R, 0));
  EXPECT_EQ(set.scans[0].perturbed.t, set.scans[0].truth.t);
  Eigen::Vector3d maxRot = Eigen::Vector3d::Zero(), meanRot = Eigen::Vector3d::Zero();
  Eigen::Vector3d maxT = Eigen::Vector3d::Zero();
  for (size_t i = 1; i < set.scans.size(); ++i) {
    maxRot = maxRot.cwiseMax(set.scans[i].rotationDeg.cwiseAbs());
    meanRot += set.scans[i].rotationDeg / (set.scans.size() - 1);
    maxT = maxT.cwiseMax(set.scans[i].translation.cwiseAbs());
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(maxRot[a], 5.0);
    EXPECT_GT(maxRot[a], 4.8);
    EXPECT_NEAR(meanRot[a], 0, 0.5);  // uniform: sd of the mean = 5/sqrt(3*299)
    EXPECT_LE(maxT[a], 6.0);
    EXPECT_GT(maxT[a], 5.7);
  }
  // The perturbation is a rotation about the object centre followed by the translation.
  const SyntheticScan& sc = set.scans[7];
  const Eigen::Vector3d p(1, 2, 3);
  const Eigen::Vector3d moved = sc.perturbed.apply(p) - sc.translation - set.centre;
  EXPECT_NEAR(moved.norm(), (sc.truth.apply(p) - set.centre).norm(), 1e-9);
}

TEST(SyntheticScanner, SameSeedSameScansOtherSeedOtherScans) {
  ScanSettings s = small(3);
  s.noise = 1;
  s.outliers = 0.05;
  s.patches = 1;
  s.rotDeg = 2;
  const SyntheticSet a = scanMesh(makeShape("torus"), s), b = scanMesh(makeShape("torus"), s);
  s.seed = 2;
  const SyntheticSet c = scanMesh(makeShape("torus"), s);
  for (size_t i = 0; i < a.scans.size(); ++i) {
    EXPECT_EQ(a.scans[i].grid.points, b.scans[i].grid.points);
    EXPECT_EQ(a.scans[i].grid.cell, b.scans[i].grid.cell);
    EXPECT_EQ(a.scans[i].perturbed.R, b.scans[i].perturbed.R);
  }
  EXPECT_NE(a.scans[1].grid.points, c.scans[1].grid.points);
}

TEST(SyntheticScanner, EachPatchIsSeenByItsScanOnly) {
  ScanSettings s = small(8);
  s.width = 80;
  s.height = 60;
  s.patches = 2;
  const SyntheticSet set = scanMesh(makeShape("composite"), s);
  ASSERT_EQ(set.patches.size(), 2u);
  const MeshDistance patch0(patchMesh({set.patches[0]})), patch1(patchMesh({set.patches[1]}));
  for (const auto& sc : set.scans) {
    size_t on0 = 0, on1 = 0;
    for (const auto& p : worldPoints(sc))
      on0 += patch0.distance(p) < 1e-6, on1 += patch1.distance(p) < 1e-6;
    const int scan = static_cast<int>(&sc - set.scans.data());
    EXPECT_EQ(on0 > 0, scan == set.patches[0].scan) << scan;
    EXPECT_EQ(on1 > 0, scan == set.patches[1].scan) << scan;
  }
}

TEST(SyntheticScanner, BadSettingsAreRefused) {
  const TriangleMesh mesh = makeShape("sphere");
  ScanSettings s = small(0);
  EXPECT_THROW(scanMesh(mesh, s), InputError);
  s = small(2);
  s.noise = -1;
  EXPECT_THROW(scanMesh(mesh, s), InputError);
  EXPECT_THROW(scanMesh(TriangleMesh{}, small(2)), InputError);
  EXPECT_THROW(makeShape("cube"), InputError);
}

TEST(SyntheticScanner, DisparityBaselineQuantisesDepthIntoEighthPixelSteps) {
  // Each depth is f b / (n / 8) for a whole n, and lies within the rounding of the surface's
  // disparity.
  const TriangleMesh mesh = makeShape("sphere");
  ScanSettings s = small(3);
  s.disparityBaseline = 0.5;
  const SyntheticSet set = scanMesh(mesh, s);
  const MeshDistance dist(mesh);
  size_t points = 0;
  for (const auto& sc : set.scans) {
    const double fb = sc.grid.pinhole->fx * s.disparityBaseline;
    for (const auto& p : sc.grid.points) {
      const double z = -p.z(), eighths = 8 * fb / z;
      EXPECT_NEAR(eighths, std::round(eighths), 1e-6 * eighths);
      // Rounding moved the disparity by 1/16 at most: the depth by no more than its far side's.
      const double d = fb / z, farthest = fb / (d - 1.0 / 16) - z;
      EXPECT_LE(dist.distance(sc.truth.apply(p)), farthest * p.norm() / z + 1e-9);
      ++points;
    }
  }
  EXPECT_GT(points, 1000u);
  s.disparityBaseline = -1;
  EXPECT_THROW(scanMesh(mesh, s), InputError);
}
