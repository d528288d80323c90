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
