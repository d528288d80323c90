// Numerical edge cases end to end on every rank: degenerate and collinear grid rows, a scan
// with one valid cell, coincident scans, a voxel larger than the object.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "SharedTemp.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/run/FuseJob.h"

using namespace rangefuse;
using test::sharedTempPath;

namespace {

/// A flat n x n grid at z = 1 with 1 cm spacing, facing the sensor (+z).
RangeGrid planeGrid(int n) {
  RangeGrid g;
  g.cols = g.rows = n;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      g.points.emplace_back(0.01 * c, 0.01 * r, 1.0);
    }
  return g;
}

/// Writes the grids (rank 0) and a .conf listing `order` of them at identity poses.
std::string writeScans(const std::string& name, const std::vector<RangeGrid>& grids,
                       const std::vector<int>& order) {
  const std::string dir = sharedTempPath(name);
  if (mpi::rank() == 0) {
    std::filesystem::create_directories(dir);
    std::ofstream conf(dir + "/scans.conf");
    for (size_t i = 0; i < grids.size(); ++i)
      io::writeRangeGridPly(dir + "/s" + std::to_string(i) + ".ply", grids[i],
                            io::PlyEncoding::BinaryLittleEndian);
    for (int i : order) conf << "bmesh s" << i << ".ply 0 0 0 0 0 0 1\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir;
}

/// Fuses dir/scans.conf; the mesh on every rank (empty if the job failed).
TriangleMesh fuse(const std::string& dir, double voxel, int* code = nullptr) {
  FuseOptions o;
  o.scans = dir + "/scans.conf";
  o.field.voxel = voxel;
  o.outputs.out = dir + "/mesh.ply";
  const int rc = runFuse(o, MPI_COMM_WORLD);
  if (code) *code = rc;
  return rc == 0 ? io::readMeshPly(o.outputs.out) : TriangleMesh{};
}

void cleanUp(const std::string& dir) {
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove_all(dir);
}

void expectOnThePlane(const TriangleMesh& m, double tolerance) {
  ASSERT_FALSE(m.faces.empty());
  for (const auto& v : m.vertices) {
    ASSERT_TRUE(v.allFinite());
    EXPECT_NEAR(v.z(), 1.0, tolerance);
  }
}

}  // namespace

TEST(EdgeCases, DegenerateAndCollinearRowsAreHarmless) {
  RangeGrid g = planeGrid(24);
  for (int c = 0; c < g.cols; ++c) {
    g.points[g.at(5, c)] = Eigen::Vector3d(0.05, 0.05, 1.0);      // a row of one repeated point
    g.points[g.at(6, c)] = Eigen::Vector3d(0.01 * c, 0.06, 1.0);  // collinear with its row
    g.points[g.at(7, c)] = Eigen::Vector3d(0.01 * c, 0.06, 1.0);  // the same again: zero area
  }
  const std::string dir = writeScans("degenerate", {g}, {0});
  expectOnThePlane(fuse(dir, 0.004), 1e-4);
  cleanUp(dir);
}

TEST(EdgeCases, SingleValidCellScanIsSkippedAndChangesNothing) {
  RangeGrid single = planeGrid(3);
  for (int i = 0; i < 9; ++i) single.cell[i] = i == 4 ? 4 : -1;
  const std::string dir = writeScans("single", {planeGrid(24), single}, {0, 1});
  const TriangleMesh both = fuse(dir, 0.004);
  std::filesystem::path alone = dir + "/alone.conf";
  if (mpi::rank() == 0) std::ofstream(alone) << "bmesh s0.ply 0 0 0 0 0 0 1\n";
  MPI_Barrier(MPI_COMM_WORLD);
  FuseOptions o;
  o.scans = alone.string();
  o.field.voxel = 0.004;
  o.outputs.out = dir + "/alone.ply";
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  const TriangleMesh reference = io::readMeshPly(o.outputs.out);
  EXPECT_EQ(both.vertices, reference.vertices);
  cleanUp(dir);
}

TEST(EdgeCases, CoincidentScansGiveTheSingleScanSurface) {
  const std::string dir = writeScans("coincident", {planeGrid(24)}, {0});
  const TriangleMesh once = fuse(dir, 0.004);
  const std::string twiceDir = writeScans("coincident2", {planeGrid(24)}, {0, 0, 0});
  const TriangleMesh thrice = fuse(twiceDir, 0.004);
  EXPECT_EQ(thrice.faces, once.faces);
  ASSERT_EQ(thrice.vertices.size(), once.vertices.size());
  for (size_t i = 0; i < once.vertices.size(); ++i)
    EXPECT_LT((thrice.vertices[i] - once.vertices[i]).norm(), 1e-9);
  cleanUp(dir);
  cleanUp(twiceDir);
}

TEST(EdgeCases, VoxelLargerThanTheObjectStillGivesAFiniteResult) {
  const std::string dir = writeScans("bigvoxel", {planeGrid(24)}, {0});
  int code = -1;
  const TriangleMesh m = fuse(dir, 1.0, &code);  // the plane is 0.23 wide
  EXPECT_EQ(code, 0);
  for (const auto& v : m.vertices) EXPECT_TRUE(v.allFinite());
  cleanUp(dir);
}
