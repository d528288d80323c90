#include <gtest/gtest.h>

#include "rangefuse/eval/Comparison.h"
#include "rangefuse/scan/Shapes.h"

using namespace rangefuse;

TEST(CompareMeshes, MeshAgainstItselfIsPerfect) {
  const TriangleMesh m = makeShape("torus");
  const MeshComparison c = compareMeshes(m, m, CompareSettings{1, 3, 20000, 1});
  EXPECT_LT(c.accuracy.max, 1e-12);
  EXPECT_LT(c.completeness.max, 1e-12);
  EXPECT_EQ(c.fscore, 1.0);
  EXPECT_EQ(c.spuriousAreaFraction, 0.0);
}

TEST(CompareMeshes, ConcentricSpheresDifferByTheirRadii) {
  const double r = 50, delta = 0.8;
  const TriangleMesh a = makeSphere(Eigen::Vector3d::Zero(), r, 200, 400);
  const TriangleMesh b = makeSphere(Eigen::Vector3d::Zero(), r + delta, 200, 400);
  const MeshComparison c = compareMeshes(a, b, CompareSettings{0.5, 3, 20000, 1});
  // Chords of a fine tessellation lie at most r (1 - cos(pi/400)) = 0.0015 inside.
  EXPECT_NEAR(c.accuracy.mean, delta, 0.003);
  EXPECT_NEAR(c.completeness.mean, delta, 0.003);
  EXPECT_NEAR(c.chamfer, delta, 0.003);
  EXPECT_EQ(c.precision, 0.0);  // every sample is 0.8 away, beyond tau = 0.5
  const MeshComparison loose = compareMeshes(a, b, CompareSettings{1.0, 3, 20000, 1});
  EXPECT_EQ(loose.fscore, 1.0);
}

TEST(CompareMeshes, SpuriousAreaIsTheFarPart) {
  TriangleMesh ref, mesh;
  ref.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  ref.faces = {{0, 1, 2}, {0, 2, 3}};
  mesh = ref;
  // A second square of the same area floating 10 units above: half the area is spurious.
  for (int k = 0; k < 4; ++k) mesh.vertices.push_back(ref.vertices[k] + Eigen::Vector3d(0, 0, 10));
  mesh.faces.push_back({4, 5, 6});
  mesh.faces.push_back({4, 6, 7});
  const MeshComparison c = compareMeshes(mesh, ref, CompareSettings{0.1, 3, 40000, 1});
  EXPECT_NEAR(c.spuriousAreaFraction, 0.5, 0.01);
  EXPECT_NEAR(c.precision, 0.5, 0.01);
  EXPECT_EQ(c.recall, 1.0);
}

TEST(ComparePose, KnownRotationAndTranslation) {
  Pose ref, est;
  ref.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  ref.t = Eigen::Vector3d(1, 2, 3);
  est.R = Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() * ref.R;
  est.t = ref.t + Eigen::Vector3d(0.3, 0, -0.4);
  const PoseError e = comparePose(est, ref, {Eigen::Vector3d::Zero()});
  EXPECT_NEAR(e.rotationDeg, 3.0, 1e-9);
  EXPECT_NEAR(e.translation, 0.5, 1e-12);
  EXPECT_NEAR(e.displacementMean, 0.5, 1e-12);  // the scan origin moves with t only
  const PoseError same = comparePose(ref, ref, {Eigen::Vector3d(5, 5, 5)});
  EXPECT_NEAR(same.rotationDeg, 0, 1e-6);
  EXPECT_EQ(same.displacementMax, 0);
}

TEST(CommonMotion, AGroupMovedTogetherShowsTheMotionAndNoRelativeError) {
  // Three scans whose estimates are their references moved by one rigid motion G, one of
  // them also off by 0.01 on its own: the common motion is G (to the small scan's share) and,
  // removed, leaves only that scan's error.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.02, Eigen::Vector3d(1, -2, 3).normalized()).toRotationMatrix();
  const Pose g{R, Eigen::Vector3d(0.3, -0.1, 0.2)};
  std::vector<std::vector<Eigen::Vector3d>> points(3);
  std::vector<Pose> refs(3), est(3);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 400; ++k)
      points[i].push_back(Eigen::Vector3d(k % 20, k / 20, i + 0.1 * (k % 7)) * 0.1);
    refs[i].t = Eigen::Vector3d(i, 0, 1);
    const Pose inverse = g.inverse();
    est[i] = Pose{inverse.R * refs[i].R, inverse.R * refs[i].t + inverse.t};
  }
  Pose found = commonMotion(est, refs, points, 1);
  EXPECT_LT((found.R - g.R).norm(), 1e-12);
  EXPECT_LT((found.t - g.t).norm(), 1e-12);
  est[2].t += Eigen::Vector3d(0.01, 0, 0);
  found = commonMotion(est, refs, points, 1);
  EXPECT_LT((found.t - g.t).norm(), 0.01);
  EXPECT_GT((found.t - g.t).norm(), 0.001);
}
