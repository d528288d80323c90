// Which scans loadScan smooths, and whose normals it filters apart: a depth camera's frames,
// never a scanner's grid.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <set>

#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/HeldScans.h"
#include "rangefuse/route/ScanLoader.h"

namespace rangefuse {
namespace {

/// RMS distance of points from their least-squares plane.
double planeRms(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - mean) * (p - mean).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(scatter, Eigen::ComputeFullU);
  const Eigen::Vector3d normal = svd.matrixU().col(2);
  double sum = 0;
  for (const Eigen::Vector3d& p : points) sum += std::pow(normal.dot(p - mean), 2);
  return std::sqrt(sum / static_cast<double>(points.size()));
}

/// A 160 x 120 depth camera of focal length `f` pixels.
io::DepthCamera wallCamera(double f) {
  io::DepthCamera camera;
  camera.fx = camera.fy = f, camera.cx = 79.5, camera.cy = 59.5;
  return camera;
}

/// Its image (millimetre counts) of a wall 3 m away, tilted along the rows, with depth noise of
/// `noiseMm`.
io::DepthImage wallImage(double noiseMm) {
  io::DepthImage image;
  image.width = 160, image.height = 120;
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0, noiseMm);
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u)
      image.counts.push_back(static_cast<uint16_t>(std::lround(3000 + 4 * u + noise(random))));
  return image;
}

io::ConfScan depthScan(const io::DepthImage& image, const io::DepthCamera& camera) {
  io::ConfScan scan;
  scan.name = scan.path = "depth";
  scan.memory = std::make_shared<io::MemoryScan>(io::MemoryScan{{}, image, {}});
  scan.depth = camera;
  return scan;
}

/// The same samples as a scanner's range grid.
io::ConfScan gridScan(const io::DepthImage& image, const io::DepthCamera& camera) {
  io::ConfScan scan;
  scan.name = scan.path = "grid";
  scan.memory = std::make_shared<io::MemoryScan>(
      io::MemoryScan{io::depthGrid(image, camera, "wall"), {}, {}});
  return scan;
}

TEST(ScanLoader, OnlyADepthCameraFrameIsSmoothed) {
  // 30 mm of depth noise, 3 voxels of 1 cm: the same samples as a depth image and as a grid.
  const io::DepthCamera camera = wallCamera(200);
  const io::DepthImage image = wallImage(30);
  const RangeGrid grid = io::depthGrid(image, camera, "wall");

  SurfaceOptions options;
  options.smoothTarget = 0.01;
  const io::ConfScan asGrid = gridScan(image, camera);
  const io::ConfScan asDepth = depthScan(image, camera);

  // The surface keeps the points its triangles use, each exactly as the grid has it.
  std::set<std::array<double, 3>> read;
  for (const Eigen::Vector3d& p : grid.points) read.insert({p.x(), p.y(), p.z()});
  const PrismScan fromGrid = loadScan(asGrid, options, InputLimits{}, 0.04);
  ASSERT_GT(fromGrid.surface.points.size(), grid.points.size() / 2);
  for (const Eigen::Vector3d& p : fromGrid.surface.points)
    ASSERT_TRUE(read.count({p.x(), p.y(), p.z()})) << "a grid point moved to " << p.transpose();

  const PrismScan fromDepth = loadScan(asDepth, options, InputLimits{}, 0.04);
  const double rough = planeRms(fromGrid.surface.points),
               smooth = planeRms(fromDepth.surface.points);
  EXPECT_GT(rough, 0.025);
  EXPECT_LT(smooth, 0.5 * rough) << "the depth frame was not smoothed";
}

TEST(ScanLoader, ADepthCameraFrameTakesItsOwnNormalPasses) {
  const io::DepthCamera camera = wallCamera(200);
  const io::DepthImage image = wallImage(10);
  const io::ConfScan asGrid = gridScan(image, camera);
  const io::ConfScan asDepth = depthScan(image, camera);
  const auto normals = [](const io::ConfScan& scan, int passes, int depthPasses) {
    SurfaceOptions options;
    options.normalPasses = passes, options.depthNormalPasses = depthPasses;
    return loadScan(scan, options, InputLimits{}, 0.04).surface.normals;
  };
  // A depth frame: depth passes when given, else the scans' passes.
  EXPECT_EQ(normals(asDepth, 2, 4), normals(asDepth, 4, -1));
  EXPECT_EQ(normals(asDepth, 2, -1), normals(asDepth, 2, 2));
  EXPECT_NE(normals(asDepth, 2, 4), normals(asDepth, 2, -1));
  // A scanner's grid: the scans' passes alone.
  EXPECT_EQ(normals(asGrid, 2, 4), normals(asGrid, 2, -1));
  EXPECT_NE(normals(asGrid, 2, 4), normals(asGrid, 4, -1));
  // Frames held for registration or tracking keep the scans' passes.
  ReadSettings read;
  read.surface.normalPasses = 2, read.surface.depthNormalPasses = 4, read.eps = 0.04;
  const auto held = heldScans({asDepth}, {0}, 0, read);
  EXPECT_EQ(held->read({0}, 1).at(0).surface.normals, normals(asDepth, 2, -1));
}

TEST(ScanLoader, NoiseIsMeasuredWhereSomethingReadsIt) {
  // A field's scanner grids skip the measurement; registration's scans, depth images and sight
  // maps measure it.
  const io::DepthCamera camera = wallCamera(200);
  const io::DepthImage image = wallImage(30);
  const io::ConfScan asGrid = gridScan(image, camera);
  SurfaceOptions options;
  options.measureNoise = false;
  EXPECT_TRUE(loadScan(asGrid, options, InputLimits{}, 0.04).noise.empty());
  const RangeNoise measured =
      loadScan(depthScan(image, camera), options, InputLimits{}, 0.04).noise;
  ASSERT_FALSE(measured.empty());
  EXPECT_NEAR(measured.at(3.3), 0.030, 0.006);
  options.sightMap = true;
  EXPECT_FALSE(loadScan(asGrid, options, InputLimits{}, 0.04).noise.empty());
  options.sightMap = false, options.measureNoise = true;
  EXPECT_FALSE(loadScan(asGrid, options, InputLimits{}, 0.04).noise.empty());
}

}  // namespace
}  // namespace rangefuse
