// Joining flat blocks of grid cells: known answers on a plane, chords measured by brute force on
// a sphere, and no crack or turned triangle where joined blocks meet fine cells.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "rangefuse/surface/FlatBlocks.h"

namespace rangefuse {
namespace {

constexpr double kFocal = 200;

/// A pinhole image, `cols` x `rows`, of the surface met at distance depth(ray) along each
/// pixel's ray (NaN: no return).
RangeGrid imageOf(int cols, int rows, const std::function<double(const Eigen::Vector3d&)>& depth) {
  RangeGrid g;
  g.cols = cols, g.rows = rows;
  g.pinhole = Pinhole{kFocal, kFocal, 0.5 * (cols - 1), 0.5 * (rows - 1)};
  g.cell.assign(size_t(cols) * rows, -1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector3d ray((c - g.pinhole->cx) / kFocal, (r - g.pinhole->cy) / kFocal, -1);
      const double t = depth(ray);
      if (std::isnan(t)) continue;
      g.cell[size_t(r) * cols + c] = int32_t(g.points.size());
      g.points.push_back(t * ray);
    }
  return g;
}

/// The tilted plane z = -2 + 0.1 x + 0.05 y.
double plane(const Eigen::Vector3d& ray) {
  return -2 / Eigen::Vector3d(-0.1, -0.05, 1).dot(ray);
}

/// The near side of a sphere of radius `radius` about (0, 0, -depth).
std::function<double(const Eigen::Vector3d&)> sphere(double radius, double depth) {
  return [radius, depth](const Eigen::Vector3d& ray) {
    const Eigen::Vector3d u = ray.normalized(), centre(0, 0, -depth);
    const double b = u.dot(centre), disc = b * b - centre.squaredNorm() + radius * radius;
    return disc < 0 ? NAN : (b - std::sqrt(disc)) / ray.norm();
  };
}

GridSurface fineSurface(const RangeGrid& g, const GridTriangulation& rules) {
  GridSurface s;
  s.mesh = triangulateGrid(g, rules, nullptr, &s.sources);
  s.normals = filteredVertexNormals(s.mesh, 2);
  return s;
}

GridTriangulation rulesOf(const RangeGrid& g) {
  return gridTriangulation(g, SurfaceOptions{});
}

double area(const TriangleMesh& m) {
  double sum = 0;
  for (const Triangle& t : m.faces)
    sum += 0.5 *
           (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  return sum;
}

/// How many triangles use each undirected edge.
std::map<std::pair<int32_t, int32_t>, int> edgeUses(const TriangleMesh& m) {
  std::map<std::pair<int32_t, int32_t>, int> uses;
  for (const Triangle& t : m.faces)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  return uses;
}

/// Each surface vertex is its grid point, with the normal the fine surface gave that point.
void expectVerticesOfTheGrid(const RangeGrid& g, const GridSurface& fine, const GridSurface& s) {
  ASSERT_EQ(s.mesh.vertices.size(), s.normals.size());
  ASSERT_EQ(s.mesh.vertices.size(), s.sources.size());
  std::map<int32_t, Eigen::Vector3d> fineNormal;
  for (size_t v = 0; v < fine.sources.size(); ++v) fineNormal[fine.sources[v]] = fine.normals[v];
  for (size_t v = 0; v < s.sources.size(); ++v) {
    EXPECT_EQ(s.mesh.vertices[v], g.points[s.sources[v]]);
    EXPECT_EQ(s.normals[v], fineNormal.at(s.sources[v]));
  }
}

TEST(FlatBlocks, JoinsEveryBlockOfAPlaneIntoTwoTriangles) {
  const RangeGrid g = imageOf(41, 31, plane);  // 20 x 15 blocks of 2 x 2 cells
  const GridTriangulation rules = rulesOf(g);
  const GridSurface fine = fineSurface(g, rules);
  GridSurface s = fine;
  joinFlatBlocks(g, rules, 1e-6, s);
  EXPECT_EQ(s.mesh.faces.size(), 2u * 20 * 15);
  EXPECT_EQ(s.mesh.vertices, fine.mesh.vertices);  // control points of registration
  EXPECT_NEAR(area(s.mesh), area(fine.mesh), 1e-12 * area(fine.mesh));
  expectVerticesOfTheGrid(g, fine, s);
  // Tolerance 0 joins nothing: the triangles are the grid's, in its order.
  GridSurface kept = fine;
  joinFlatBlocks(g, rules, 0, kept);
  EXPECT_EQ(kept.mesh.faces, fine.mesh.faces);
}

TEST(FlatBlocks, JoinedChordsStayWithinTheToleranceOfASphere) {
  const double radius = 0.5;
  const RangeGrid g = imageOf(61, 61, sphere(radius, 3));
  const GridTriangulation rules = rulesOf(g);
  const GridSurface fine = fineSurface(g, rules);
  // Where the sphere faces the camera a block's diagonal spans about 2 sqrt(2) pixels at 2.5 m:
  // its chord's sagitta is L² / 8R. Toward the rim the blocks grow and turn more.
  const double diagonal = 2 * std::sqrt(2.0) * 2.5 / kFocal;
  const double sagitta = diagonal * diagonal / (8 * radius);
  std::set<std::array<int32_t, 3>> fineTriangles;
  for (const Triangle& t : fine.mesh.faces)
    fineTriangles.insert({fine.sources[t[0]], fine.sources[t[1]], fine.sources[t[2]]});
  size_t previous = fine.mesh.faces.size() + 1;
  for (double times : {0.25, 0.8, 1.5, 3.0}) {
    GridSurface s = fine;
    joinFlatBlocks(g, rules, times * sagitta, s);
    // Brute force: the farthest of many points on each joined triangle from the sphere.
    double farthest = 0;
    for (const Triangle& t : s.mesh.faces) {
      if (fineTriangles.count({s.sources[t[0]], s.sources[t[1]], s.sources[t[2]]})) continue;
      for (int i = 0; i <= 8; ++i)
        for (int j = 0; i + j <= 8; ++j) {
          const Eigen::Vector3d p = s.mesh.vertices[t[0]] +
                                    i / 8.0 * (s.mesh.vertices[t[1]] - s.mesh.vertices[t[0]]) +
                                    j / 8.0 * (s.mesh.vertices[t[2]] - s.mesh.vertices[t[0]]);
          farthest = std::max(farthest, std::abs((p - Eigen::Vector3d(0, 0, -3)).norm() - radius));
        }
    }
    // Within the tolerance, give or take the filtered normals' estimate of the turn (a fifth
    // low where the sphere turns away from the camera).
    EXPECT_LE(farthest, 1.3 * times * sagitta) << times;
    EXPECT_LE(s.mesh.faces.size(), previous) << times;  // a looser tolerance joins no fewer
    previous = s.mesh.faces.size();
    expectVerticesOfTheGrid(g, fine, s);
  }
  EXPECT_LT(previous, fine.mesh.faces.size() / 2);
  GridSurface tight = fine;
  joinFlatBlocks(g, rules, 0.25 * sagitta, tight);
  EXPECT_EQ(tight.mesh.faces, fine.mesh.faces);  // no block is that flat
}

TEST(FlatBlocks, AreJoinedInScanSurfacesWithColourToo) {
  RangeGrid g = imageOf(41, 31, plane);
  SurfaceOptions options;
  options.flatTolerance = 1e-6;
  const ScanSurface plain = buildScanSurface(g, Pose{}, options);
  EXPECT_EQ(plain.triangles.size(), 2u * 20 * 15);
  EXPECT_TRUE(plain.texels.empty());
  // A coloured grid joins the same blocks and keeps its cells' colours as texels
  // (SurfaceColour tests what its triangles show).
  g.colours.assign(g.points.size(), Colour(0.5f, 0.25f, 1.0f));
  g.colourKind = ColourKind::rgb;
  const ScanSurface coloured = buildScanSurface(g, Pose{}, options);
  EXPECT_EQ(coloured.triangles, plain.triangles);
  EXPECT_EQ(coloured.points, plain.points);
  EXPECT_EQ(coloured.texels.cells.size(), 41u * 31);
  EXPECT_EQ(coloured.blocks.size(), coloured.points.size());
}

/// A plane with a hemispherical bump in its middle and a hole: joined and fine cells meet.
RangeGrid bumpAndHole() {
  return imageOf(60, 45, [](const Eigen::Vector3d& ray) {
    const double t = plane(ray), bump = sphere(0.12, 2.05)(ray);
    const Eigen::Vector3d p = t * ray;
    if (p.x() > 0.15 && p.x() < 0.2 && p.y() > 0.1 && p.y() < 0.15) return double(NAN);
    return std::isnan(bump) ? t : std::min(t, bump);
  });
}

TEST(FlatBlocks, LeavesNoCrackWhereJoinedBlocksMeetFineCells) {
  for (bool mirrored : {false, true}) {
    RangeGrid g = bumpAndHole();
    if (mirrored)  // columns running the other way: triangles wound the other way round
      for (int r = 0; r < g.rows; ++r)
        std::reverse(g.cell.begin() + size_t(r) * g.cols, g.cell.begin() + size_t(r + 1) * g.cols);
    const GridTriangulation rules = rulesOf(g);
    ASSERT_EQ(rules.forward, !mirrored);
    const GridSurface fine = fineSurface(g, rules);
    GridSurface s = fine;
    joinFlatBlocks(g, rules, 1e-4, s);
    ASSERT_LT(s.mesh.faces.size(), fine.mesh.faces.size() * 0.6);  // the plane is joined
    ASSERT_GT(s.mesh.faces.size(), fine.mesh.faces.size() / 4);    // the bump is not
    EXPECT_NEAR(area(s.mesh), area(fine.mesh), 1e-3 * area(fine.mesh));
    // An edge of one triangle lies where the fine surface has its own border: on the grid's
    // border, or around the hole and the bump's rim, where the fine surface's borders are.
    std::map<std::pair<int32_t, int32_t>, int> fineEdges;
    for (const auto& [edge, uses] : edgeUses(fine.mesh))
      fineEdges[std::minmax(fine.sources[edge.first], fine.sources[edge.second])] = uses;
    std::map<int32_t, int> fineBorderPoints;
    for (const auto& [edge, uses] : fineEdges)
      if (uses == 1) ++fineBorderPoints[edge.first], ++fineBorderPoints[edge.second];
    for (const auto& [edge, uses] : edgeUses(s.mesh)) {
      EXPECT_LE(uses, 2);
      if (uses == 1) {
        EXPECT_TRUE(fineBorderPoints.count(s.sources[edge.first]) &&
                    fineBorderPoints.count(s.sources[edge.second]))
            << "an edge inside the surface has one triangle: a crack";
      }
    }
    for (const Triangle& t : s.mesh.faces) {
      const Eigen::Vector3d &a = s.mesh.vertices[t[0]], &b = s.mesh.vertices[t[1]],
                            &c = s.mesh.vertices[t[2]];
      EXPECT_GT((b - a).cross(c - a).dot(g.towardSensor((a + b + c) / 3)), 0);
    }
    expectVerticesOfTheGrid(g, fine, s);
  }
}

}  // namespace
}  // namespace rangefuse
