#include <gtest/gtest.h>

#include <random>

#include "rangefuse/eval/Comparison.h"
#include "rangefuse/eval/SeenSurface.h"

using namespace rangefuse;

namespace {

/// The square [x0, x0 + 1] x [0, 1] at z = 0 as two triangles.
TriangleMesh square(double x0) {
  TriangleMesh m;
  m.vertices = {{x0, 0, 0}, {x0 + 1, 0, 0}, {x0 + 1, 1, 0}, {x0, 1, 0}};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

TriangleMesh join(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const int base = static_cast<int>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (Triangle t : b.faces) m.faces.push_back({t[0] + base, t[1] + base, t[2] + base});
  return m;
}

}  // namespace

TEST(SeenCells, KeepsTheStatedDistanceBoundsAroundASparseSurface) {
  const double cell = 0.05;  // the square's two triangles are 20 cells across
  SeenCells seen(cell);
  seen.addSurface(square(0), Pose{});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1), off(-cell, cell);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d onOrNear(u(rng), u(rng), off(rng));
    EXPECT_TRUE(seen.near(onOrNear)) << onOrNear.transpose();
    const Eigen::Vector3d above(u(rng), u(rng), 2 * std::sqrt(3.0) * cell + 1e-3);
    EXPECT_FALSE(seen.near(above)) << above.transpose();
    const Eigen::Vector3d beside(1 + 2 * std::sqrt(3.0) * cell + u(rng), u(rng), 0);
    EXPECT_FALSE(seen.near(beside)) << beside.transpose();
  }
}

TEST(SeenCells, PlacesTheSurfaceByItsPose) {
  SeenCells seen(0.05);
  Pose pose;
  pose.R = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  pose.t = {0, 0, 5};
  seen.addSurface(square(0), pose);  // now the plane y = 0, z in [5, 6]
  EXPECT_TRUE(seen.near({0.5, 0, 5.5}));
  EXPECT_FALSE(seen.near({0.5, 0.5, 0}));
  EXPECT_GT(seen.cells(), 300u);  // 20 x 20 cells, at least
}

TEST(CompareMeshes, SeenSurfaceLeavesWhatNoScanSawOutOfCompleteness) {
  const TriangleMesh reference = join(square(0), square(3));  // the second square: unseen
  const TriangleMesh mesh = square(0);
  SeenCells seen(0.01);
  seen.addSurface(square(0), Pose{});
  const CompareSettings settings{0.02, 0.06, 20000, 1};
  const MeshComparison all = compareMeshes(mesh, reference, settings);
  const MeshComparison onSeen = compareMeshes(mesh, reference, settings, &seen);
  EXPECT_NEAR(all.recall, 0.5, 0.02);
  EXPECT_DOUBLE_EQ(all.seenFraction, 1.0);
  EXPECT_NEAR(onSeen.seenFraction, 0.5, 0.02);
  EXPECT_DOUBLE_EQ(onSeen.recall, 1.0);
  EXPECT_DOUBLE_EQ(onSeen.precision, all.precision);
  EXPECT_LT(onSeen.completeness.max, 1e-12);
}
