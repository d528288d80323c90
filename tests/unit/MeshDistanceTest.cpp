#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#include "rangefuse/eval/MeshDistance.h"

using namespace rangefuse;

namespace {

/// Dense barycentric sampling: an upper bound on the true distance, close to it.
double sampledTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  double best = INFINITY;
  const int n = 300;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      Eigen::Vector3d q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
      best = std::min(best, (p - q).norm());
    }
  return best;
}

TriangleMesh randomMesh(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1, 1);
  TriangleMesh m;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d c(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k)
      m.vertices.push_back(c + 0.2 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    m.faces.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return m;
}

}  // namespace

TEST(ClosestPoint, MatchesBruteForceInEveryRegion) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0.3, 0.8, 0.1);
  for (int i = 0; i < 300; ++i) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    double exact = (p - closestPointOnTriangle(p, a, b, c)).norm();
    double sampled = sampledTriangleDistance(p, a, b, c);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_NEAR(exact, sampled, 4e-3);
  }
  EXPECT_EQ(closestPointOnTriangle({-1, -1, 0}, a, b, c), a);  // vertex region
  EXPECT_LT((closestPointOnTriangle({0.5, -1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0, 0)).norm(),
            1e-15);
}

TEST(ClosestPoint, DegenerateTrianglesGiveTheirSegmentsClosestPoint) {
  // Marching cubes makes triangles with two corners at one point where the surface passes
  // through a lattice vertex; they were answered with NaN.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  const Eigen::Vector3d a(0, 0, 0), b(1, 0.5, 0.25);
  auto onSegment = [&](const Eigen::Vector3d& p) {
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return a + t * (b - a);
  };
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    for (const auto& [x, y, z] : {std::array{a, a, b}, std::array{a, b, a}, std::array{b, a, a},
                                  std::array{a, b, b}, std::array{b, a, b}, std::array{b, b, a}}) {
      const Eigen::Vector3d q = closestPointOnTriangle(p, x, y, z);
      ASSERT_TRUE(q.allFinite()) << p.transpose();
      EXPECT_NEAR((p - q).norm(), (p - onSegment(p)).norm(), 1e-12);
    }
    EXPECT_EQ(closestPointOnTriangle(p, a, a, a), a);
  }
}

TEST(MeshDistance, MatchesBruteForceOverAllTriangles) {
  std::mt19937 rng(9);
  TriangleMesh m = randomMesh(rng, 400);
  MeshDistance dist(m);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 500; ++i) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    double brute = INFINITY;
    for (const auto& t : m.faces)
      brute = std::min(brute, (p - closestPointOnTriangle(p, m.vertices[t[0]], m.vertices[t[1]],
                                                          m.vertices[t[2]]))
                                  .norm());
    EXPECT_EQ(dist.distance(p), brute);
  }
}

TEST(MeshDistance, ClosestFaceAndWeightsMatchBruteForce) {
  std::mt19937 rng(13);
  TriangleMesh m = randomMesh(rng, 300);
  MeshDistance dist(m);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    size_t face = 0;
    double brute = INFINITY;
    for (size_t f = 0; f < m.faces.size(); ++f) {
      const auto& t = m.faces[f];
      const double d =
          (p - closestPointOnTriangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]))
              .norm();
      if (d < brute) brute = d, face = f;
    }
    const ClosestPoint c = dist.closest(p);
    ASSERT_EQ(c.face, face);
    EXPECT_EQ(c.distance, brute);
    const auto& t = m.faces[face];
    const Eigen::Vector3d q = c.weights[0] * m.vertices[t[0]] + c.weights[1] * m.vertices[t[1]] +
                              c.weights[2] * m.vertices[t[2]];
    EXPECT_NEAR((p - q).norm(), brute, 1e-12);
    EXPECT_NEAR(c.weights.sum(), 1, 1e-12);
  }
  EXPECT_EQ(MeshDistance(TriangleMesh{}).closest(Eigen::Vector3d::Zero()).distance, INFINITY);
}

TEST(MeshDistance, MeshAgainstItselfIsZeroAndShiftedPlaneIsShift) {
  TriangleMesh plane;
  plane.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  plane.faces = {{0, 1, 2}, {0, 2, 3}};
  DistanceStats self = summarize(sampledDistances(plane, plane, 2000, 1));
  EXPECT_LT(self.max, 1e-15);
  TriangleMesh big;
  big.vertices = {{-5, -5, 0.25}, {5, -5, 0.25}, {5, 5, 0.25}, {-5, 5, 0.25}};
  big.faces = plane.faces;
  DistanceStats shifted = summarize(sampledDistances(plane, big, 2000, 1));
  EXPECT_NEAR(shifted.mean, 0.25, 1e-12);
  EXPECT_NEAR(shifted.max, 0.25, 1e-12);
}
