#include <gtest/gtest.h>

#include <random>

#include "rangefuse/consensus/Consensus.h"
#include "rangefuse/consensus/ConsensusSampler.h"
#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;

namespace {

/// A square grid surface of side `size` centred at `centre`, facing `normal`.
ScanSurface square(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double size, int n,
                   double confidence) {
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  ScanSurface s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      s.points.push_back(centre + size * ((double(i) / n - 0.5) * u + (double(j) / n - 0.5) * v));
      s.normals.push_back(normal);
      s.confidence.push_back(confidence);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      s.triangles.push_back({a, b, d});
      s.triangles.push_back({a, d, c});
    }
  return s;
}

void appendSurface(ScanSurface& a, const ScanSurface& b) {
  const int32_t base = static_cast<int32_t>(a.points.size());
  a.points.insert(a.points.end(), b.points.begin(), b.points.end());
  a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
  a.confidence.insert(a.confidence.end(), b.confidence.begin(), b.confidence.end());
  for (const auto& t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

ConsensusParams params(double quorum) {
  ConsensusParams p;
  p.quorum = quorum;
  p.sameDistance = 2;
  p.sameCosine = std::cos(M_PI / 4);
  return p;
}

/// Three views of the plane z = 0; the third also sees a floating patch at z = 5.
std::vector<ScanSurface> planeWithPatch() {
  std::vector<ScanSurface> views;
  for (int k = 0; k < 3; ++k) views.push_back(square({0, 0, 0.01 * k}, {0, 0, 1}, 40, 40, 0.9));
  appendSurface(views[2], square({0, 0, 5}, {0, 0, 1}, 6, 6, 0.9));
  return views;
}

std::vector<ViewIndex> indexAll(const std::vector<ScanSurface>& surfaces) {
  std::vector<ViewIndex> v;
  for (const auto& s : surfaces) v.emplace_back(s);
  return v;
}

}  // namespace

TEST(SameSurface, Bounds) {
  const ConsensusParams p = params(1);
  const Eigen::Vector3d n(0, 0, 1);
  EXPECT_TRUE(sameSurface({0, 0, 0}, n, {2, 0, 0}, n, p));        // exactly delta_d
  EXPECT_FALSE(sameSurface({0, 0, 0}, n, {2.0001, 0, 0}, n, p));  // just beyond
  const Eigen::Vector3d at45(std::sin(M_PI / 4 - 1e-9), 0, std::cos(M_PI / 4 - 1e-9));
  const Eigen::Vector3d past45(std::sin(M_PI / 4 + 1e-6), 0, std::cos(M_PI / 4 + 1e-6));
  EXPECT_TRUE(sameSurface({0, 0, 0}, n, {0, 0, 0}, at45, p));
  EXPECT_FALSE(sameSurface({0, 0, 0}, n, {0, 0, 0}, past45, p));
}

TEST(ViewIndex, ClosestMatchesBruteForce) {
  const TriangleMesh torus = makeTorus(Eigen::Vector3d::Zero(), 10, 3, 60, 24);
  ScanSurface s;
  s.points = torus.vertices;
  s.triangles = torus.faces;
  for (const auto& p : s.points) s.normals.push_back(p.normalized()), s.confidence.push_back(1);
  const ViewIndex index(s);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-16, 16);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d x(u(rng), u(rng), u(rng) * 0.5);
    double brute = INFINITY;
    for (const auto& t : s.triangles)
      brute = std::min(
          brute,
          (x - closestPointOnTriangle(x, s.points[t[0]], s.points[t[1]], s.points[t[2]])).norm());
    SurfaceObservation o;
    ASSERT_TRUE(index.closest(x, INFINITY, o));
    EXPECT_EQ(o.distance, brute);
    EXPECT_NEAR((x - o.point).norm(), brute, 1e-12);
    EXPECT_EQ(index.closest(x, 0.99 * brute, o), false);  // the cap is honoured
  }
}

TEST(Consensus, FloatingPatchIgnoredByConsensusKeptByNaive) {
  const auto surfaces = planeWithPatch();
  const auto views = indexAll(surfaces);
  const RegionViews all(views);
  SignedDistance c, n;
  const Eigen::Vector3d abovePatch(0.5, 0.3, 5.4);
  ASSERT_TRUE(consensusSignedDistance(abovePatch, all, params(1.5), c));
  ASSERT_TRUE(naiveSignedDistance(abovePatch, all, params(1.5), n));
  EXPECT_NEAR(c.d, 5.4 - 0.01, 0.011);  // the plane: consensus of three views
  EXPECT_NEAR(n.d, 0.4, 1e-12);         // the patch
  const Eigen::Vector3d belowPatch(0.5, 0.3, 4.6);
  ASSERT_TRUE(naiveSignedDistance(belowPatch, all, params(1.5), n));
  EXPECT_LT(n.d, 0);  // naive: a zero crossing at the patch
  ASSERT_TRUE(consensusSignedDistance(belowPatch, all, params(1.5), c));
  EXPECT_GT(c.d, 4);  // consensus: none
}

TEST(Consensus, WithFewViewsOneViewPassesTheQuorumButNotTwoViews) {
  // Few views give a small quorum (2.25 x 3 / 48 = 0.14): one view's confidence (0.9) passes it
  // and the floating patch stays. Asking for two views removes the patch and keeps the plane.
  const auto surfaces = planeWithPatch();
  const auto views = indexAll(surfaces);
  const RegionViews all(views);
  ConsensusParams one = params(2.25 * 3 / 48), two = one;
  two.minViews = 2;
  const Eigen::Vector3d belowPatch(0.5, 0.3, 4.6);
  SignedDistance c;
  ASSERT_TRUE(consensusSignedDistance(belowPatch, all, one, c));
  EXPECT_NEAR(c.d, -0.4, 1e-12);  // the patch, one view
  ASSERT_TRUE(consensusSignedDistance(belowPatch, all, two, c));
  EXPECT_GT(c.d, 4);  // the plane, three views
  const Eigen::Vector3d nearPlane(0.5, 0.3, 0.6);
  ASSERT_TRUE(consensusSignedDistance(nearPlane, all, two, c));
  EXPECT_NEAR(c.d, 0.6 - 0.01, 0.011);
}

TEST(Consensus, VoxelMidwayInAThinWall) {
  // A wall 2 thick: its top faces +z at z = 1, its bottom faces -z at z = -1, each side seen
  // by two views. Normals disagree, so the two sides never average into one surface.
  std::vector<ScanSurface> surfaces;
  for (int k = 0; k < 2; ++k) surfaces.push_back(square({0, 0, 1}, {0, 0, 1}, 30, 30, 1));
  for (int k = 0; k < 2; ++k) surfaces.push_back(square({0, 0, -1}, {0, 0, -1}, 30, 30, 1));
  const auto views = indexAll(surfaces);
  const RegionViews all(views);
  SignedDistance sd;
  ASSERT_TRUE(consensusSignedDistance({0.2, 0.1, 0}, all, params(1.5), sd));
  EXPECT_NEAR(sd.d, -1, 1e-12);
  ASSERT_TRUE(consensusSignedDistance({0.2, 0.1, 0.4}, all, params(1.5), sd));
  EXPECT_NEAR(sd.d, -0.6, 1e-12);
  ASSERT_TRUE(consensusSignedDistance({0.2, 0.1, -1.3}, all, params(1.5), sd));
  EXPECT_NEAR(sd.d, 0.3, 1e-12);
  EXPECT_LT((sd.gradient - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
}

/// An ideal orthographic view of a sphere from direction `axis`: a grid of exact surface
/// points out to 75 degrees from the axis, exact normals, confidence = cosine to the axis.
ScanSurface sphereCap(double r, const Eigen::Vector3d& axis, double step) {
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  const int n = static_cast<int>(2 * r / step);
  const double rim = r * std::sin(75 * M_PI / 180);
  ScanSurface s;
  std::vector<int32_t> id((n + 1) * (n + 1), -1);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double a = -r + i * step, b = -r + j * step;
      if (a * a + b * b > rim * rim) continue;
      const Eigen::Vector3d p = a * u + b * v + std::sqrt(r * r - a * a - b * b) * axis;
      id[j * (n + 1) + i] = static_cast<int32_t>(s.points.size());
      s.points.push_back(p);
      s.normals.push_back(p / r);
      s.confidence.push_back(p.dot(axis) / r);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = id[j * (n + 1) + i], b = id[j * (n + 1) + i + 1];
      const int32_t c = id[(j + 1) * (n + 1) + i], d = id[(j + 1) * (n + 1) + i + 1];
      if (a >= 0 && b >= 0 && d >= 0) s.triangles.push_back({a, b, d});
      if (a >= 0 && d >= 0 && c >= 0) s.triangles.push_back({a, d, c});
    }
  return s;
}

TEST(Consensus, IdealSphereFromSixViewsIsTheAnalyticDistance) {
  const double r = 30;
  std::vector<ScanSurface> surfaces;
  for (int a = 0; a < 3; ++a)
    for (double sign : {1.0, -1.0})
      surfaces.push_back(sphereCap(r, sign * Eigen::Vector3d::Unit(a), 0.25));
  const auto views = indexAll(surfaces);
  const RegionViews all(views);
  ConsensusParams p = params(0.5);
  p.edgeCosine = std::cos(78 * M_PI / 180);
  p.edgeSlack = 0.5;
  p.memberSlack = 0.05;
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> h(-2, 2);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const double offset = h(rng);
    SignedDistance sd;
    ASSERT_TRUE(consensusSignedDistance((r + offset) * dir, all, p, sd));
    EXPECT_NEAR(sd.d, offset, 0.01) << "at " << dir.transpose();  // 1% of a unit voxel
  }
}

TEST(Consensus, RegionCullingGivesExactlyTheFullAnswers) {
  const auto surfaces = planeWithPatch();
  const auto views = indexAll(surfaces);
  const RegionViews all(views);
  RegionViews focused(views);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 4);
  for (int b = 0; b < 20; ++b) {
    const Eigen::Vector3d lo(u(rng) * 4 - 8, u(rng) * 4 - 8, u(rng) * 2 - 2);
    const Eigen::AlignedBox3d box(lo, lo + Eigen::Vector3d::Constant(3));
    focused.focus(box, 3.0);  // a small margin forces the fallback paths too
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d x = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.75;
      SignedDistance a, c;
      const bool fa = consensusSignedDistance(x, all, params(1.5), a);
      ASSERT_EQ(fa, consensusSignedDistance(x, focused, params(1.5), c));
      if (fa) {
        EXPECT_EQ(a.d, c.d);
      }
      ASSERT_TRUE(naiveSignedDistance(x, all, params(1.5), a));
      ASSERT_TRUE(naiveSignedDistance(x, focused, params(1.5), c));
      EXPECT_EQ(a.d, c.d);
    }
  }
}

/// The triangles of `s` that some point of lies within `r` of `centre`, in order (what a
/// rank receives for a brick whose focus ball is (centre, r)), plus every `extra`-th other
/// triangle (what it receives for its other bricks).
static ScanSurface routedPart(const ScanSurface& s, const Eigen::Vector3d& centre, double r,
                              int extra) {
  ScanSurface part = s;
  part.triangles.clear();
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& f = s.triangles[t];
    const Eigen::Vector3d q =
        closestPointOnTriangle(centre, s.points[f[0]], s.points[f[1]], s.points[f[2]]);
    if ((q - centre).norm() <= r || t % extra == 0) part.triangles.push_back(f);
  }
  return part;
}

TEST(Consensus, RoutedTrianglesGiveTheFullAnswerOrNone) {
  const auto surfaces = planeWithPatch();
  const auto views = indexAll(surfaces);
  const RegionViews all(views);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 4);
  const ConsensusParams p = params(1.5);
  int settled = 0;
  for (int b = 0; b < 20; ++b) {
    const Eigen::Vector3d lo(u(rng) * 4 - 8, u(rng) * 4 - 8, u(rng) * 2 - 2);
    const Eigen::AlignedBox3d box(lo, lo + Eigen::Vector3d::Constant(3));
    const double margin = 8.0, reach = 0.5 * box.diagonal().norm() + margin;
    for (const int extra : {1000000, 7}) {
      std::vector<ScanSurface> parts;
      for (const auto& s : surfaces) parts.push_back(routedPart(s, box.center(), reach, extra));
      const auto partViews = indexAll(parts);
      RegionViews local(partViews, false);
      local.focus(box, margin);
      for (int i = 0; i < 20; ++i) {
        const Eigen::Vector3d x = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.75;
        SignedDistance a, c;
        const bool fa = consensusSignedDistance(x, all, p, a);
        const bool fc = consensusSignedDistance(x, local, p, c);
        if (fc) {
          ASSERT_TRUE(fa);
          EXPECT_EQ(a.d, c.d);
          EXPECT_EQ(a.weight, c.weight);
        }
        // A quorum surface closer than margin - 2 delta_d is always found.
        if (fa && a.weight >= p.quorum && std::abs(a.d) < margin - 2 * p.sameDistance) {
          EXPECT_TRUE(fc) << "at " << x.transpose();
          ++settled;
        }
        ASSERT_TRUE(naiveSignedDistance(x, all, p, a));
        if (naiveSignedDistance(x, local, p, c)) {
          EXPECT_EQ(a.d, c.d);
        } else {
          EXPECT_GE(std::abs(a.d), margin);
        }
      }
    }
  }
  EXPECT_GT(settled, 100);
}
