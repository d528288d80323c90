// The synthetic depth camera's faults against known answers: depths on the disparity steps a
// 7.5 cm baseline and 1/8 pixel give, the blank band, holes and mixed returns at a depth edge,
// a fixed share of dark surface, the projector's shadow beside an object in front of a wall
// against rays cast by brute force, and the working range.
#include <gtest/gtest.h>

#include <cmath>

#include "rangefuse/core/Error.h"
#include "rangefuse/scan/Bvh.h"
#include "rangefuse/scan/DepthSensorModel.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;

namespace {

constexpr double kFx = 585;

/// A depth image of two planes: 1 m on the left half, 2 m on the right.
std::vector<double> stepImage(int cols, int rows) {
  std::vector<double> d(static_cast<size_t>(cols) * rows);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) d[static_cast<size_t>(r) * cols + c] = c < cols / 2 ? 1.0 : 2.0;
  return d;
}

/// True when z is fb / (n / 8) for a whole n.
bool onDisparityStep(double z, double fb) {
  const double eighths = 8 * fb / z;
  return std::abs(eighths - std::round(eighths)) < 1e-6;
}

}  // namespace

TEST(DepthSensorModel, DepthsFallOnEighthPixelDisparitySteps) {
  DepthSensorModel m = DepthSensorModel::preset("kinect");
  m.edgeHoles = m.flying = 0, m.blankColumns = 0;
  std::mt19937_64 rng(3);
  std::vector<double> d(400);
  for (size_t k = 0; k < d.size(); ++k) d[k] = 0.8 + 2.7 * k / d.size();
  applyImageFaults(d, 400, 1, kFx, m, rng);
  const double fb = kFx * 0.075;
  for (double z : d) ASSERT_TRUE(onDisparityStep(z, fb)) << z;
  // The step at 1.88 m: z^2 / (f b) / 8, the 10 mm measured on 7-Scenes (docs/sensor.md).
  EXPECT_NEAR(1.88 * 1.88 / fb / 8, 0.010, 0.0005);
  // Without noise each depth goes to its nearest step, within half a step.
  m.disparityNoise = 0;
  std::vector<double> exact = {1.0, 1.88, 3.0};
  applyImageFaults(exact, 3, 1, kFx, m, rng);
  for (double z0 : {1.0, 1.88, 3.0}) {
    const double z = exact[z0 == 1.0 ? 0 : z0 == 1.88 ? 1 : 2];
    EXPECT_LE(std::abs(z - z0), 0.5 * z0 * z0 / fb / 8 * 1.01) << z0;
  }
}

TEST(DepthSensorModel, EdgesGetHolesOrMixedReturnsAndTheBandIsBlank) {
  DepthSensorModel m = DepthSensorModel::preset("kinect");
  m.disparityNoise = 0, m.quantum = 0;
  std::mt19937_64 rng(4);
  const int cols = 64, rows = 8;
  m.edgeHoles = 1, m.flying = 0, m.blankColumns = 80;  // 8 of 64 columns at this width
  std::vector<double> holes = stepImage(cols, rows);
  applyImageFaults(holes, cols, rows, kFx, m, rng);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double z = holes[static_cast<size_t>(r) * cols + c];
      const bool edge = c == cols / 2 - 1 || c == cols / 2, blank = c >= cols - 8;
      EXPECT_EQ(z == 0, edge || blank) << r << ", " << c;
    }
  m.edgeHoles = 0, m.flying = 1, m.blankColumns = 0;
  std::vector<double> mixed = stepImage(cols, rows);
  applyImageFaults(mixed, cols, rows, kFx, m, rng);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double z = mixed[static_cast<size_t>(r) * cols + c];
      if (c == cols / 2 - 1 || c == cols / 2) {
        EXPECT_GE(z, 1.0);
        EXPECT_LE(z, 2.0);
      } else {
        EXPECT_EQ(z, c < cols / 2 ? 1.0 : 2.0);
      }
    }
}

TEST(DepthSensorModel, DarkSurfaceIsAFixedShareOfCells) {
  DepthSensorModel m = DepthSensorModel::preset("kinect");
  size_t dark = 0, n = 0;
  for (int x = 0; x < 100; ++x)
    for (int y = 0; y < 100; ++y, ++n) {
      const double px = (x + 0.5) * m.darkCell, py = (y + 0.5) * m.darkCell;
      dark += onDarkSurface(px, py, 0.3, m);
      // Every point of a cell answers alike: the pattern is on the surface, not the view.
      EXPECT_EQ(onDarkSurface(px, py, 0.3, m), onDarkSurface(px + 0.4 * m.darkCell, py, 0.3, m));
    }
  EXPECT_NEAR(static_cast<double>(dark) / n, m.darkShare, 0.01);
  EXPECT_THROW(DepthSensorModel::preset("lidar"), InputError);
  const DepthSensorModel still = m.without("shutter,offset,steps");
  EXPECT_EQ(still.rollingShutter, 0);
  EXPECT_EQ(still.timeOffset, 0);
  EXPECT_EQ(still.quantum, 0);
  EXPECT_EQ(still.disparityNoise, m.disparityNoise);
  EXPECT_THROW(m.without("shutter,blur"), InputError);
  EXPECT_FALSE(DepthSensorModel::preset("none").active());
}

TEST(DepthSensorModel, ShadowsAreWhereTheProjectorCannotSee) {
  // A box on a floor, seen from 3.4 m through a narrow lens with the projector 7.5 cm to the
  // camera's right: floor just beside the box is seen by the camera but not lit by the projector.
  TriangleMesh scene = makeBox({-0.8, -0.8, -0.1}, {0.8, 0.8, 0}, true, 0.5);
  appendMesh(scene, makeBox({-0.15, -0.15, 0}, {0.15, 0.15, 0.6}, false, 0.5));
  ScanSettings s;
  s.views = 1, s.width = 160, s.height = 120, s.path = ViewPath::Orbit, s.fovDeg = 12;
  s.sensor = DepthSensorModel::preset("kinect");
  DepthSensorModel& m = s.sensor;
  m.disparityNoise = 0, m.quantum = 0, m.grazingCos = 0, m.darkShare = 0;
  m.edgeHoles = 0, m.flying = 0, m.blankColumns = 0, m.rollingShutter = 0, m.timeOffset = 0;
  m.nearest = 0, m.farthest = 0;
  const SyntheticSet set = scanMesh(scene, s);
  const SyntheticScan& view = set.scans[0];
  const RangeGrid& g = view.grid;
  const Bvh bvh(scene);
  const Eigen::Vector3d projector = view.truth.apply(Eigen::Vector3d(0.075, 0, 0));
  int shadowed = 0;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector3d ray = Eigen::Vector3d((c - g.pinhole->cx) / g.pinhole->fx,
                                                  (r - g.pinhole->cy) / g.pinhole->fy, -1)
                                      .normalized();
      RayHit hit;
      if (!bvh.firstHitBruteForce(view.truth.t, view.truth.R * ray, 0, INFINITY, hit)) continue;
      const Eigen::Vector3d p = view.truth.t + hit.t * (view.truth.R * ray);
      const Eigen::Vector3d toward = projector - p;
      RayHit block;
      const bool dark = bvh.firstHitBruteForce(p + 1e-6 * toward, toward.normalized(), 0,
                                               toward.norm() * (1 - 2e-6), block);
      shadowed += dark;
      EXPECT_EQ(g.at(r, c) < 0, dark) << r << ", " << c;
      if (!dark && g.at(r, c) >= 0) {
        EXPECT_NEAR(g.points[g.at(r, c)].norm(), hit.t, 1e-9);
      }
    }
  EXPECT_GT(shadowed, 20);
}

TEST(DepthSensorModel, TheWorkingRangeAndAScannerThatRefusesOtherNoise) {
  ScanSettings s;
  s.views = 4, s.width = 64, s.height = 48, s.path = ViewPath::Walk;
  s.sensor = DepthSensorModel::preset("kinect");
  const SyntheticSet set = scanMesh(makeRoom(), s);
  size_t points = 0;
  for (const SyntheticScan& v : set.scans)
    for (const Eigen::Vector3d& p : v.grid.points) {
      ++points;
      // Depth noise and the steps move a depth by a few per cent at most.
      EXPECT_GT(-p.z(), 0.8 * 0.97);
      EXPECT_LT(-p.z(), 3.5 * 1.03);
    }
  EXPECT_GT(points, 1000u);
  s.noise = 0.5;
  EXPECT_THROW(scanMesh(makeRoom(), s), InputError);
}
