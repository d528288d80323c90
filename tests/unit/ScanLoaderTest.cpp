// Which scans loadScan smooths: a depth camera's frames, never a scanner's grid.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <set>

#include "rangefuse/io/DepthCamera.h"
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

TEST(ScanLoader, OnlyADepthCameraFrameIsSmoothed) {
  // A tilted wall 3 m away with 30 mm of depth noise, 3 voxels of 1 cm: the same samples as
  // a depth image and as a range grid.
  io::DepthCamera camera;
  camera.fx = camera.fy = 200, camera.cx = 79.5, camera.cy = 59.5;
  io::DepthImage image;
  image.width = 160, image.height = 120;
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0, 30);
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u)
      image.counts.push_back(static_cast<uint16_t>(std::lround(3000 + 4 * u + noise(random))));
  const RangeGrid grid = io::depthGrid(image, camera, "wall");

  SurfaceOptions options;
  options.smoothTarget = 0.01;
  io::ConfScan asGrid, asDepth;
  asGrid.name = asGrid.path = "grid", asDepth.name = asDepth.path = "depth";
  asGrid.memory = std::make_shared<io::MemoryScan>(io::MemoryScan{grid, {}, {}});
  asDepth.memory = std::make_shared<io::MemoryScan>(io::MemoryScan{{}, image, {}});
  asDepth.depth = camera;

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

}  // namespace
}  // namespace rangefuse
