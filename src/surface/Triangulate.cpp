#include <algorithm>
#include <cmath>

#include "GridShape.h"
#include "GridSteps.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {
namespace {

/// Azimuth of a column about the station's z axis (circular mean of its points), or NaN when
/// the column holds no point off the axis.
double columnAzimuth(const RangeGrid& g, int c) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int r = 0; r < g.rows; ++r)
    if (const int32_t k = g.at(r, c); k >= 0) {
      const Eigen::Vector2d xy = g.points[k].head<2>();
      if (xy.norm() > 0) sum += xy.normalized();
    }
  return sum.norm() > 0 ? std::atan2(sum.y(), sum.x()) : NAN;
}

/// a - b wrapped into (-pi, pi].
double angleBetween(double a, double b) {
  return std::remainder(a - b, 2 * M_PI);
}

}  // namespace

namespace internal {

bool longerThan(const Eigen::Vector3d& d, double limit) {
  const double s = d.squaredNorm(), limit2 = limit * limit;
  // A square of normal size is rounded to a part in 10^16, and so is a root: outside a margin
  // of a part in 10^12 the squares give the root's answer. Subnormal or infinite squares (and
  // NaN) take the root.
  if (limit > 0 && std::isnormal(limit2)) {
    if (s < limit2 * (1 - 1e-12)) return false;
    if (s > limit2 * (1 + 1e-12)) return true;
  }
  return std::sqrt(s) > limit;
}

namespace {

/// Whether cos = (n . t) / (|n| |t|) >= minCos is settled by squares (no root, no division):
/// as for longerThan, outside a margin of a part in 10^9 the squares give the roots' answer,
/// and a cosine of either sign whose square is below minCos^2 fails. Unsettled (NaN or
/// zero lengths, subnormal or infinite squares, a bound near zero) returns -1.
int cosineAtLeast(const Eigen::Vector3d& n, const Eigen::Vector3d& t, double minCos) {
  const double q = n.dot(t), bound = minCos * minCos * n.squaredNorm() * t.squaredNorm();
  if (!(minCos > 1e-6) || !std::isnormal(bound) || !std::isfinite(q)) return -1;
  if (q < 0 || q * q < bound * (1 - 1e-9)) return 0;
  if (q * q > bound * (1 + 1e-9)) return 1;
  return -1;
}

}  // namespace

bool keepsTriangle(const RangeGrid& g, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c, double maxEdge, double minCos) {
  if (longerThan(a - b, maxEdge) || longerThan(b - c, maxEdge) || longerThan(c - a, maxEdge))
    return false;
  Eigen::Vector3d n = (b - a).cross(c - a);
  Eigen::Vector3d centre = (a + b + c) / 3.0;
  // Most triangles face the sensor well inside or well outside the limit: settled without the
  // two roots and four divisions of the cosine itself.
  const Sensor sensor = g.sensor();
  const int settled =
      cosineAtLeast(n, sensor.isPoint ? sensor.point - centre : sensor.direction, minCos);
  if (settled >= 0) return settled == 1;
  double len = n.norm();
  if (len == 0) return false;
  return n.dot(g.towardSensor(centre)) / len >= minCos;
}

bool wrapsAround(const RangeGrid& g, int turnColumns) {
  const int cols = turnColumns < 0 ? g.cols : turnColumns;
  if (!g.spherical || cols < 8) return false;
  std::vector<double> azimuth(g.cols), steps;
  for (int c = 0; c < g.cols; ++c) azimuth[c] = columnAzimuth(g, c);
  for (int c = 0; c + 1 < g.cols; ++c)
    if (!std::isnan(azimuth[c]) && !std::isnan(azimuth[c + 1]))
      steps.push_back(angleBetween(azimuth[c + 1], azimuth[c]));
  if (steps.empty() || std::isnan(azimuth.front()) || std::isnan(azimuth.back())) return false;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double step = steps[steps.size() / 2];
  if (!(std::abs(step) > 0)) return false;
  // A full turn: the columns' steps add up to 2 pi and the seam is about one step wide.
  const double seam = angleBetween(azimuth.front(), azimuth.back());
  return std::abs(cols * std::abs(step) - 2 * M_PI) <= 2 * std::abs(step) && seam * step > 0 &&
         std::abs(seam) <= 1.5 * std::abs(step);
}

bool facesSensor(const RangeGrid& g) {
  long toward = 0, away = 0;
  for (int r = 0; r + 1 < g.rows; ++r)
    for (int c = 0; c + 1 < g.cols; ++c) {
      const int32_t a = g.at(r, c), b = g.at(r, c + 1), d = g.at(r + 1, c);
      if (a < 0 || b < 0 || d < 0) continue;
      const Eigen::Vector3d& p = g.points[a];
      const double side = (g.points[b] - p).cross(g.points[d] - p).dot(g.towardSensor(p));
      toward += side > 0;
      away += side < 0;
    }
  return toward >= away;
}

}  // namespace internal

double gridSpacing(const RangeGrid& grid, int downEvery) {
  // Squares keep the order, so the median step is the root of the median square: one root.
  return std::sqrt(internal::medianNeighbourStep(grid, internal::squaredStep, downEvery));
}

GridTriangulation gridTriangulation(const RangeGrid& grid, const SurfaceOptions& options) {
  return gridTriangulation(grid, options, options.maxEdgeFactor * gridSpacing(grid));
}

GridTriangulation gridTriangulation(const RangeGrid& grid, const SurfaceOptions& options,
                                    double maxEdge) {
  // (r,c),(r,c+1),(r+1,c) has its normal toward +z, the sensor side (NOTES.md), in Stanford
  // and pinhole grids; a station's columns may turn either way, so the cells vote.
  return {maxEdge, options.minCosine, internal::facesSensor(grid), internal::wrapsAround(grid)};
}

TriangleMesh triangulateGrid(const RangeGrid& grid, const SurfaceOptions& options) {
  return triangulateGrid(grid, gridTriangulation(grid, options));
}

TriangleMesh triangulateGrid(const RangeGrid& grid, const GridTriangulation& rules,
                             std::vector<int>* cellColumns, std::vector<int32_t>* sources) {
  std::vector<int32_t> remap(grid.points.size(), -1);
  TriangleMesh mesh;
  auto use = [&](int32_t i) {
    if (remap[i] < 0) {
      remap[i] = static_cast<int32_t>(mesh.vertices.size());
      mesh.vertices.push_back(grid.points[i]);
      if (!grid.colours.empty()) mesh.colours.push_back(grid.colours[i]);
      if (sources) sources->push_back(i);
    }
    return remap[i];
  };
  int column = 0;
  auto emit = [&](int32_t a, int32_t b, int32_t c) {
    if (a < 0 || b < 0 || c < 0) return;
    if (!internal::keepsTriangle(grid, grid.points[a], grid.points[b], grid.points[c],
                                 rules.maxEdge, rules.minCosine))
      return;
    mesh.faces.push_back({use(a), use(b), use(c)});
    if (cellColumns) cellColumns->push_back(column);
  };
  auto cell = [&](int32_t a, int32_t b, int32_t c) {
    rules.forward ? emit(a, b, c) : emit(a, c, b);
  };
  // A full turn closes: the last column's neighbour is the first.
  const int columns = rules.wraps ? grid.cols : grid.cols - 1;
  for (int r = 0; r + 1 < grid.rows; ++r)
    for (column = 0; column < columns; ++column) {
      const int c = column, next = c + 1 < grid.cols ? c + 1 : 0;
      cell(grid.at(r, c), grid.at(r, next), grid.at(r + 1, c));
      cell(grid.at(r, next), grid.at(r + 1, next), grid.at(r + 1, c));
    }
  return mesh;
}

}  // namespace rangefuse
