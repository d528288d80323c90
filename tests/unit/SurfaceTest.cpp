#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "rangefuse/surface/ScanSurface.h"
#include "surface/GridShape.h"

using namespace rangefuse;

namespace {

/// A cols x rows grid on the plane z = slope * x, 0.5 apart, with the sensor on +z.
RangeGrid planeGrid(int cols, int rows, double slope) {
  RangeGrid g;
  g.cols = cols;
  g.rows = rows;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      g.points.emplace_back(0.5 * c, 0.5 * r, slope * 0.5 * c);
    }
  return g;
}

/// A station inside a cylinder of radius 5: columns step `turn` / cols in azimuth (a full turn
/// when |turn| = 2 pi; negative: clockwise), rows 0.2 apart in height.
RangeGrid stationGrid(int cols, int rows, double turn) {
  RangeGrid g;
  g.cols = cols, g.rows = rows, g.spherical = true;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double a = turn * c / cols;
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      g.points.emplace_back(5 * std::cos(a), 5 * std::sin(a), 0.2 * (r - rows / 2));
    }
  return g;
}

/// Edges used by one triangle only.
size_t boundaryEdges(const std::vector<Triangle>& triangles) {
  std::map<std::pair<int32_t, int32_t>, int> uses;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  size_t n = 0;
  for (const auto& [edge, count] : uses) n += count == 1;
  return n;
}

}  // namespace

TEST(Surface, AStationsFullTurnClosesAcrossTheSeamFacingTheStation) {
  for (double turn : {2 * M_PI, -2 * M_PI}) {
    const RangeGrid g = stationGrid(120, 10, turn);
    EXPECT_TRUE(internal::wrapsAround(g));
    const ScanSurface s = buildScanSurface(g, Pose{}, SurfaceOptions{});
    EXPECT_EQ(s.triangles.size(), 2u * 9 * 120) << turn;
    EXPECT_EQ(boundaryEdges(s.triangles), 2u * 120) << turn;  // the top and bottom rows only
    for (size_t i = 0; i < s.points.size(); ++i) {
      const Eigen::Vector3d inward(-s.points[i].x(), -s.points[i].y(), 0);
      EXPECT_GT(s.normals[i].dot(inward.normalized()), 0.999) << turn;
    }
  }
}

TEST(Surface, APartialTurnStaysOpen) {
  const RangeGrid g = stationGrid(120, 10, 0.9 * 2 * M_PI);
  EXPECT_FALSE(internal::wrapsAround(g));
  EXPECT_EQ(buildScanSurface(g, Pose{}, SurfaceOptions{}).triangles.size(), 2u * 9 * 119);
  RangeGrid pinhole = stationGrid(120, 10, 2 * M_PI);
  pinhole.spherical = false;
  pinhole.pinhole = Pinhole{100, 100, 60, 5};
  EXPECT_FALSE(internal::wrapsAround(pinhole));
}

TEST(Surface, TwoTrianglesPerFullCellFacingTheSensor) {
  RangeGrid g = planeGrid(10, 8, 0);
  g.cell[3 * 10 + 4] = -1;  // a missing sample removes the 6 triangles around it
  ScanSurface s = buildScanSurface(g, Pose{}, SurfaceOptions{});
  EXPECT_EQ(s.triangles.size(), 2u * 9 * 7 - 6);
  for (size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_NEAR(s.normals[i].z(), 1.0, 1e-12);
    EXPECT_NEAR(s.confidence[i], 1.0, 1e-12);
  }
}

TEST(Surface, DropsLongEdgesAndGrazingTriangles) {
  RangeGrid g = planeGrid(6, 6, 0);
  g.points[2 * 6 + 2].z() = 10;  // a spike: its triangles have long edges
  EXPECT_EQ(buildScanSurface(g, Pose{}, SurfaceOptions{}).triangles.size(), 2u * 25 - 6);
  RangeGrid steep = planeGrid(6, 6, 12);  // cos = 1/sqrt(145) < 0.15
  EXPECT_TRUE(buildScanSurface(steep, Pose{}, SurfaceOptions{}).triangles.empty());
}

TEST(Surface, ConfidenceIsCosineToViewAndPoseMovesPoints) {
  RangeGrid g = planeGrid(5, 5, 1);  // 45 degrees to the +z view
  Pose pose;
  pose.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.t = Eigen::Vector3d(1, 2, 3);
  ScanSurface s = buildScanSurface(g, pose, SurfaceOptions{});
  const Eigen::Vector3d expected = pose.R * Eigen::Vector3d(-1, 0, 1).normalized();
  for (size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_NEAR(s.confidence[i], std::sqrt(0.5), 1e-12);
    EXPECT_LT((s.normals[i] - expected).norm(), 1e-12);
  }
  EXPECT_LT((s.points[0] - pose.apply(g.points[0])).norm(), 1e-12);
}

TEST(Surface, FilteringSmoothsANoisyNormal) {
  RangeGrid g = planeGrid(7, 7, 0);
  g.points[3 * 7 + 3].z() = 0.3;
  const TriangleMesh m = triangulateGrid(g, SurfaceOptions{});
  auto raw = filteredVertexNormals(m, 0), smooth = filteredVertexNormals(m, 3);
  // The bump's neighbours tilt; filtering brings them back toward the plane normal.
  size_t nb = 0;
  for (size_t i = 0; i < m.vertices.size(); ++i)
    if ((m.vertices[i] - Eigen::Vector3d(2, 1.5, 0)).norm() < 1e-9) nb = i;
  EXPECT_GT(smooth[nb].z(), raw[nb].z());
}

// The adjacency is built in place from triangle corners; here every vertex's neighbours are
// found by a scan of all triangles, and the passes are summed in the same (ascending) order.
/// filteredVertexNormals the slow way: each vertex's neighbours found anew by scanning every
/// triangle, kept in a set (ascending, each once).
std::vector<Eigen::Vector3d> bruteForceNormals(const TriangleMesh& m, int passes) {
  std::vector<Eigen::Vector3d> n(m.vertices.size(), Eigen::Vector3d::Zero());
  for (const Triangle& t : m.faces) {
    const auto &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    for (int32_t v : t) n[v] += (b - a).cross(c - a).normalized();
  }
  for (auto& v : n) v.normalize();
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<Eigen::Vector3d> next = n;
    for (size_t v = 0; v < n.size(); ++v) {
      std::set<int32_t> around;
      for (const Triangle& t : m.faces)
        if (std::count(t.begin(), t.end(), static_cast<int32_t>(v)))
          for (int32_t u : t)
            if (u != static_cast<int32_t>(v)) around.insert(u);
      for (int32_t u : around) next[v] += n[u];
      next[v].normalize();
    }
    n = next;
  }
  return n;
}

TEST(Surface, FilteredNormalsMatchABruteForceNeighbourAverage) {
  RangeGrid g = planeGrid(9, 8, 0.2);
  std::srand(7);
  for (auto& p : g.points) p.z() += 0.05 * (std::rand() % 7);
  g.cell[2 * 9 + 4] = g.cell[5 * 9 + 1] = -1;  // holes: vertices of differing degree
  TriangleMesh m = triangulateGrid(g, SurfaceOptions{});
  // As triangulated (vertices numbered as first used), then numbered in a shuffled order, so
  // that a vertex's neighbours come in no order the triangles suggest.
  for (int numbering = 0; numbering < 2; ++numbering) {
    const std::vector<Eigen::Vector3d> n = bruteForceNormals(m, 2);
    const std::vector<Eigen::Vector3d> fast = filteredVertexNormals(m, 2);
    ASSERT_EQ(fast.size(), n.size());
    for (size_t v = 0; v < n.size(); ++v)
      EXPECT_EQ(fast[v], n[v]) << "numbering " << numbering << ", vertex " << v;
    std::vector<int32_t> to(m.vertices.size());
    std::iota(to.begin(), to.end(), 0);
    std::shuffle(to.begin(), to.end(), std::mt19937(11));
    TriangleMesh shuffled = m;
    for (size_t v = 0; v < to.size(); ++v) shuffled.vertices[to[v]] = m.vertices[v];
    for (Triangle& t : shuffled.faces)
      for (int32_t& v : t) v = to[v];
    m = shuffled;
  }
}

TEST(Surface, EdgeLengthsAreTestedAsTheirRootsWould) {
  // longerThan, the squares' fast path, against d.norm() > limit: lengths a few rounding steps
  // to a part in 10^9 either side of limits from tiny to huge, and the limits a square cannot
  // hold (subnormal, infinite), zero, negative and NaN.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  const double limits[] = {1e-160,
                           1e-150,
                           3e-7,
                           0.0125,
                           1,
                           4.5,
                           1e150,
                           1e200,
                           0,
                           -1,
                           std::numeric_limits<double>::infinity(),
                           NAN};
  const double offsets[] = {0,     1e-17,  -1e-17, 1e-16,  -1e-16, 3e-16, -3e-16, 1e-13, -1e-13,
                            1e-12, -1e-12, 2e-12,  -2e-12, 1e-9,   -1e-9, 0.5,    -0.5};
  int checked = 0;
  for (const double limit : limits)
    for (const double offset : offsets)
      for (int k = 0; k < 200; ++k) {
        Eigen::Vector3d d(unit(random), unit(random), unit(random));
        const double length = std::isfinite(limit) && limit > 0 ? limit : 1;
        d *= length * (1 + offset) / d.norm();
        EXPECT_EQ(internal::longerThan(d, limit), d.norm() > limit)
            << "limit " << limit << ", length " << d.norm();
        ++checked;
      }
  EXPECT_EQ(internal::longerThan(Eigen::Vector3d(NAN, 0, 0), 1), false);
  EXPECT_GT(checked, 40000);
}

TEST(Surface, ObliquenessIsTestedAsTheCosineWould) {
  // keepsTriangle settles most triangles by squares; it must keep exactly the triangles whose
  // cosine to the line of sight, computed with its roots and divisions, reaches the limit.
  // Triangles tilted to a few rounding steps, to a part in 10^9 and far either side of each
  // limit, on pinhole (point) and orthographic (direction) grids, facing toward and away.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  const double limits[] = {0.15, 0.5, 0.999, 1e-7, 0, -0.3};
  const double offsets[] = {0, 1e-16, -1e-16, 4e-16, -4e-16, 1e-12, -1e-12, 1e-9, -1e-9, 0.1, -0.1};
  int checked = 0, kept = 0;
  for (const bool pinhole : {true, false}) {
    RangeGrid g;
    if (pinhole) g.pinhole = Pinhole{};
    for (const double limit : limits)
      for (const double offset : offsets)
        for (int k = 0; k < 100; ++k) {
          // A triangle about a centre, its normal at the angle whose cosine is the limit
          // (moved by the offset) from the line of sight there.
          const Eigen::Vector3d centre(unit(random), unit(random), -2 - unit(random));
          const Eigen::Vector3d sight =
              pinhole ? Eigen::Vector3d(-centre.normalized()) : Eigen::Vector3d::UnitZ();
          const Eigen::Vector3d side =
              sight.cross(Eigen::Vector3d(unit(random), unit(random), unit(random))).normalized();
          const double cosine = std::clamp(limit * (1 + offset), -1.0, 1.0);
          const Eigen::Vector3d normal =
              cosine * sight + std::sqrt(1 - cosine * cosine) * sight.cross(side);
          const Eigen::Vector3d u = side, v = normal.cross(side);
          const double r = 0.01 * (1 + unit(random));
          const Eigen::Vector3d a = centre + r * u, b = centre + r * v, c = centre - r * (u + v);
          const Eigen::Vector3d n = (b - a).cross(c - a);
          const bool expected =
              n.norm() > 0 && n.dot(g.towardSensor((a + b + c) / 3.0)) / n.norm() >= limit;
          EXPECT_EQ(internal::keepsTriangle(g, a, b, c, 1, limit), expected)
              << (pinhole ? "pinhole" : "orthographic") << " limit " << limit << " offset "
              << offset;
          ++checked;
          kept += expected;
        }
  }
  RangeGrid g;
  const Eigen::Vector3d o = Eigen::Vector3d::Zero(), x = Eigen::Vector3d::UnitX();
  EXPECT_FALSE(internal::keepsTriangle(g, o, x, 2 * x, 1, 0.15));  // no area
  EXPECT_FALSE(internal::keepsTriangle(g, o, x, Eigen::Vector3d(NAN, 0, 0), 1, 0.15));
  EXPECT_GT(checked, 13000);
  EXPECT_GT(kept, 3000);
  EXPECT_LT(kept, checked - 3000);
}

TEST(Surface, PinholeViewRayRunsToTheOrigin) {
  RangeGrid g = planeGrid(4, 4, 0);
  for (auto& p : g.points) p.z() = -5;
  g.pinhole = Pinhole{100, 100, 2, 2};
  const Eigen::Vector3d p(3, 4, -5);
  EXPECT_LT((g.towardSensor(p) - Eigen::Vector3d(-3, -4, 5).normalized()).norm(), 1e-15);
}
