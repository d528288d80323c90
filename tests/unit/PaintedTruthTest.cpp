// The painted truth keeps the surface where it was and resolves check edges to `finest`.
#include <gtest/gtest.h>

#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/scan/PaintedTruth.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;

namespace {

double area(const TriangleMesh& m) {
  double a = 0;
  for (const Triangle& t : m.faces)
    a += 0.5 *
         (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  return a;
}

}  // namespace

TEST(PaintedTruth, SplitsOnlyAcrossCheckEdgesAndKeepsTheSurface) {
  const TriangleMesh sphere = makeShape("sphere");
  const double size = 20, finest = 0.25;
  const TriangleMesh m = paintedTruth(sphere, size, finest);
  ASSERT_EQ(m.colours.size(), m.vertices.size());
  for (size_t i = 0; i < m.vertices.size(); ++i)
    ASSERT_EQ(m.colours[i], checkColour(m.vertices[i], size)) << i;
  size_t fine = 0;
  for (const Triangle& t : m.faces) {
    if (m.colours[t[0]] == m.colours[t[1]] && m.colours[t[1]] == m.colours[t[2]]) continue;
    ++fine;
    for (int k = 0; k < 3; ++k)
      ASSERT_LE((m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm(), finest);
  }
  EXPECT_GT(fine, 0u);
  EXPECT_NEAR(area(m), area(sphere), 1e-9 * area(sphere));
  // Every new vertex lies on the original surface.
  const MeshDistance original(sphere);
  for (size_t i = sphere.vertices.size(); i < m.vertices.size(); i += 97)
    ASSERT_LT(original.distance(m.vertices[i]), 1e-9);
  // Far fewer triangles than splitting everything to that size would make.
  EXPECT_LT(m.faces.size(), 30 * sphere.faces.size());
}

TEST(PaintedTruth, AWallOfTwoTrianglesShowsTheChecksInside) {
  // An 8 x 8 square whose four corners fall in checks of one colour (checks of 2, their edges
  // 0.382 of a side off round coordinates): without splitting its
  // two triangles would show that colour everywhere. The truth's colour at points inside
  // must be the checks' own, except within `finest` of a check edge.
  TriangleMesh wall;
  wall.vertices = {{0.5, 0.5, 0.5}, {8.5, 0.5, 0.5}, {8.5, 8.5, 0.5}, {0.5, 8.5, 0.5}};
  wall.faces = {{0, 1, 2}, {0, 2, 3}};
  const double size = 2, finest = 0.1;
  const TriangleMesh m = paintedTruth(wall, size, finest);
  const MeshDistance truth(m);
  int wrong = 0, tested = 0;
  for (double y = 1.03; y < 8.4; y += 0.37)
    for (double x = 0.97; x < 8.4; x += 0.41) {
      const Eigen::Vector3d p(x, y, 0.5);
      bool nearEdge = false;  // within `finest` of a check edge
      for (int axis = 0; axis < 2; ++axis) {
        const Eigen::Vector3d step = finest * Eigen::Vector3d::Unit(axis);
        nearEdge |= checkColour(p + step, size) != checkColour(p, size) ||
                    checkColour(p - step, size) != checkColour(p, size);
      }
      if (nearEdge) continue;
      const ClosestPoint c = truth.closest(p);
      const Triangle& t = m.faces[c.face];
      Eigen::Vector3f colour = Eigen::Vector3f::Zero();
      for (int k = 0; k < 3; ++k) colour += float(c.weights[k]) * m.colours[t[k]];
      ++tested;
      if ((colour - checkColour(p, size)).norm() > 1e-4) ++wrong;
    }
  EXPECT_GT(tested, 250);
  EXPECT_EQ(wrong, 0);
  EXPECT_NEAR(area(m), 64, 1e-9);
}
