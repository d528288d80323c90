// Scans read from a Leica PTX file fuse to the same mesh as the same grids read from
// range-grid PLY files and a .conf: the file format changes nothing downstream (to the last
// bit when the poses are the same to the last bit).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "SharedTemp.h"
#include "rangefuse/eval/Comparison.h"
#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/run/FuseJob.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"
#include "rangefuse/surface/ScanSurface.h"
#include "surface/GridShape.h"

using namespace rangefuse;

namespace {

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

FuseOptions fuseOptions(const std::string& scans, const std::string& out) {
  FuseOptions o;
  o.scans = scans;
  o.field.voxel = 2;
  o.outputs.out = out;
  return o;
}

/// Three stations of (480 x 200) * density^2 points in the synthetic room, noise 0.3 voxel.
SyntheticSet roomStations(double voxel, int density = 1) {
  ScanSettings s;
  s.views = 3, s.width = 480 * density, s.height = 200 * density, s.voxel = voxel, s.noise = 0.3;
  s.path = ViewPath::Stations;
  return scanMesh(makeRoom(), s);
}

/// Rank 0 writes the stations as one PTX file, dir/name (the folder made); every rank waits.
void writeStations(const SyntheticSet& set, const std::string& dir, const std::string& name) {
  if (mpi::rank() == 0) {
    std::filesystem::create_directories(dir);
    std::vector<RangeGrid> grids;
    std::vector<Pose> poses;
    for (const SyntheticScan& sc : set.scans) grids.push_back(sc.grid), poses.push_back(sc.truth);
    io::writePtx(dir + "/" + name, grids, poses);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace

TEST(PtxFuse, AStationFileFusesToTheSameMeshAsThePlyFilesOfItsScans) {
  const std::string dir = test::sharedTempPath("ptx-fuse");
  ScanSettings s;
  s.views = 5, s.width = 120, s.height = 90, s.voxel = 2, s.noise = 0.3;
  const SyntheticSet set = scanMesh(makeShape("sphere"), s);
  std::vector<io::ConfScan> conf;
  std::vector<RangeGrid> grids;
  std::vector<Pose> poses;
  for (const SyntheticScan& sc : set.scans) {
    conf.push_back({sc.name, dir + "/" + sc.name, sc.truth});
    // What the PLY files hold: float coordinates; and an intensity, which PTX always has.
    RangeGrid g = sc.grid;
    for (Eigen::Vector3d& p : g.points) p = p.cast<float>().cast<double>();
    g.colourKind = ColourKind::intensity;
    for (size_t k = 0; k < g.points.size(); ++k)
      g.colours.push_back(Colour::Constant(static_cast<float>(k % 97) / 96));
    grids.push_back(g);
    poses.push_back(sc.truth);
  }
  if (mpi::rank() == 0) {
    std::filesystem::create_directories(dir);
    for (size_t i = 0; i < grids.size(); ++i)
      io::writeRangeGridPly(dir + "/" + set.scans[i].name, grids[i],
                            io::PlyEncoding::BinaryLittleEndian);
    io::writeConf(dir + "/scans.conf", conf);
    io::writePtx(dir + "/stations.ptx", grids, poses);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  ASSERT_EQ(runFuse(fuseOptions(dir + "/scans.conf", dir + "/ply.ply"), MPI_COMM_WORLD), 0);
  ASSERT_EQ(runFuse(fuseOptions(dir + "/stations.ptx", dir + "/ptx.ply"), MPI_COMM_WORLD), 0);
  // A .conf may name the scans of a PTX file too.
  if (mpi::rank() == 0) {
    std::vector<io::ConfScan> named = conf;
    for (size_t i = 0; i < named.size(); ++i) {
      named[i].name = "stations.ptx#" + std::to_string(i + 1);
      named[i].path = dir + "/stations.ptx";
    }
    io::writeConf(dir + "/named.conf", named);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  ASSERT_EQ(runFuse(fuseOptions(dir + "/named.conf", dir + "/named.ply"), MPI_COMM_WORLD), 0);
  if (mpi::rank() == 0) {
    const std::string ply = bytes(dir + "/ply.ply");
    EXPECT_GT(ply.size(), 10000u);
    EXPECT_EQ(ply, bytes(dir + "/named.ply"));
    // The PTX header gives each pose as a matrix, the .conf as a quaternion: the same pose to
    // the last bit or two, so a placed point may round to the neighbouring point of its scan's
    // lattice (decision 45). The same surface to a thousandth of a voxel, not the same bytes.
    const TriangleMesh fromPly = io::readMeshPly(dir + "/ply.ply");
    const TriangleMesh fromPtx = io::readMeshPly(dir + "/ptx.ply");
    EXPECT_LE(summarize(sampledDistances(fromPtx, fromPly, 20000, 3)).max, 2e-3);  // voxel 2
    const io::ConfFile list = io::readScanList(dir + "/stations.ptx");
    ASSERT_EQ(list.scans.size(), 5u);
    EXPECT_EQ(list.scans[4].name, "stations.ptx#5");
    EXPECT_THROW(io::readScanList(dir + "/bad.conf"), std::exception);
    io::writeConf(dir + "/bad.conf", {{"stations.ptx#6", "", Pose{}}});
    try {
      io::readScanList(dir + "/bad.conf");
      ADD_FAILURE() << "a sixth scan of a five-scan file was accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find("holds only 5 scans"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
  }
}

TEST(PtxFuse, ThreeStationsInARoomFuseCloseToTheRoom) {
  const std::string dir = test::sharedTempPath("ptx-room");
  const double voxel = 0.05;
  const SyntheticSet set = roomStations(voxel);
  EXPECT_TRUE(internal::wrapsAround(set.scans[0].grid));  // a full turn: the seam closes
  writeStations(set, dir, "room.ptx");
  FuseOptions o = fuseOptions(dir + "/room.ptx", dir + "/room.ply");
  o.field.voxel = voxel;
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  if (mpi::rank() == 0) {
    const MeshComparison c = compareMeshes(io::readMeshPly(o.outputs.out), makeRoom(),
                                           CompareSettings{voxel, 3 * voxel, 50000, 1});
    std::printf("room from 3 stations: accuracy mean %.3f voxel, precision %.4f, recall %.4f\n",
                c.accuracy.mean / voxel, c.precision, c.recall);
    EXPECT_LT(c.accuracy.mean, 0.15 * voxel);
    EXPECT_GT(c.precision, 0.99);
    EXPECT_GT(c.recall, 0.8);  // what the stations cannot see: under the desk, behind the cabinet
    std::filesystem::remove_all(dir);
  }
}

TEST(PtxFuse, StationsReadInBandsFuseTheSameOnAnyRankCountAndAsCloseToTheRoom) {
  // Each station of 96 000 cells becomes three bands of 160 columns, read by either rank.
  const std::string dir = test::sharedTempPath("ptx-bands");
  const double voxel = 0.05;
  writeStations(roomStations(voxel), dir, "room.ptx");
  FuseOptions whole = fuseOptions(dir + "/room.ptx", dir + "/whole.ply");
  whole.field.voxel = voxel;
  whole.bandCells = 0;
  ASSERT_EQ(runFuse(whole, MPI_COMM_WORLD), 0);
  FuseOptions banded = whole;
  banded.bandCells = 40000;
  banded.outputs.out = dir + "/two.ply";
  ASSERT_EQ(runFuse(banded, MPI_COMM_WORLD), 0);
  if (mpi::rank() != 0) return;
  EXPECT_EQ(io::splitIntoBands(io::readScanList(banded.scans), 40000).scans.size(), 9u);
  banded.outputs.out = dir + "/one.ply";
  ASSERT_EQ(runFuse(banded, MPI_COMM_SELF), 0);
  EXPECT_EQ(bytes(dir + "/one.ply"), bytes(dir + "/two.ply"));
  const CompareSettings compare{voxel, 3 * voxel, 50000, 1};
  const MeshComparison a = compareMeshes(io::readMeshPly(whole.outputs.out), makeRoom(), compare);
  const MeshComparison b = compareMeshes(io::readMeshPly(banded.outputs.out), makeRoom(), compare);
  std::printf("room whole / in bands: accuracy mean %.4f / %.4f voxel, recall %.4f / %.4f\n",
              a.accuracy.mean / voxel, b.accuracy.mean / voxel, a.recall, b.recall);
  EXPECT_NEAR(b.accuracy.mean, a.accuracy.mean, 0.01 * voxel);
  EXPECT_NEAR(b.recall, a.recall, 0.005);
  EXPECT_GT(b.precision, 0.99);
  std::filesystem::remove_all(dir);
}

TEST(PtxFuse, DenseStationsMergedToTheVoxelKeepTheirAccuracy) {
  // Twice the angular resolution: cells about 2 cm apart on the walls against 5 cm voxels, so
  // --merge-cells 1 merges the spherical grids in blocks of 2 x 2 (their azimuths and
  // elevations stay a station's: the seam still closes).
  const std::string dir = test::sharedTempPath("ptx-dense");
  const double voxel = 0.05;
  writeStations(roomStations(voxel, 2), dir, "room.ptx");
  const CompareSettings compare{voxel, 3 * voxel, 50000, 1};
  MeshComparison c[2];
  uint64_t triangles[2];
  for (int merge = 0; merge < 2; ++merge) {
    FuseOptions o = fuseOptions(dir + "/room.ptx", dir + "/m" + std::to_string(merge) + ".ply");
    o.field.voxel = voxel;
    o.mergeCells = merge;
    o.outputs.report = dir + "/m" + std::to_string(merge) + ".json";
    ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
    if (mpi::rank() != 0) continue;
    c[merge] = compareMeshes(io::readMeshPly(o.outputs.out), makeRoom(), compare);
    triangles[merge] = io::readJson(o.outputs.report)["inputs"]["scan_triangles"].get<uint64_t>();
  }
  if (mpi::rank() != 0) return;
  std::printf(
      "dense stations: %llu triangles, chamfer %.4f voxel, recall %.4f; merged %llu, "
      "%.4f, %.4f\n",
      static_cast<unsigned long long>(triangles[0]), c[0].chamfer / voxel, c[0].recall,
      static_cast<unsigned long long>(triangles[1]), c[1].chamfer / voxel, c[1].recall);
  EXPECT_LT(triangles[1] * 3, triangles[0]);
  EXPECT_LE(c[1].chamfer, std::max(1.1 * c[0].chamfer, c[0].chamfer + 0.01 * voxel));
  EXPECT_GT(c[1].precision, 0.99);
  EXPECT_NEAR(c[1].recall, c[0].recall, 0.01);
  std::filesystem::remove_all(dir);
}

TEST(PtxFuse, AGhostOneStationSawIsRemovedByWhatTheOthersSawThrough) {
  // Station 0 sees a block of its cells at 60 % of their range: a surface floating in the room
  // (someone walking past), which the other stations look through. Prism fusion keeps it;
  // robust fusion's free-space evidence, from the stations' sight maps, removes it.
  const std::string dir = test::sharedTempPath("ptx-ghost");
  const double voxel = 0.05;
  SyntheticSet set = roomStations(voxel);
  RangeGrid& ghosted = set.scans[0].grid;
  for (int r = 90; r < 130; ++r)
    for (int c = 200; c < 250; ++c)
      if (const int32_t i = ghosted.at(r, c); i >= 0) ghosted.points[i] *= 0.6;
  writeStations(set, dir, "ghost.ptx");
  // Prism, robust, and robust with each station read in three bands (a sight map each).
  const FieldMethod methods[3] = {FieldMethod::Prism, FieldMethod::Robust, FieldMethod::Robust};
  double spurious[3] = {0, 0, 0};
  for (int run = 0; run < 3; ++run) {
    FuseOptions o = fuseOptions(dir + "/ghost.ptx", dir + "/ghost.ply");
    o.field.voxel = voxel;
    o.field.method = methods[run];
    o.bandCells = run == 2 ? 40000 : 0;
    ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
    if (mpi::rank() != 0) continue;
    const MeshComparison c = compareMeshes(io::readMeshPly(o.outputs.out), makeRoom(),
                                           CompareSettings{voxel, 3 * voxel, 50000, 1});
    spurious[run] = c.spuriousAreaFraction;
    std::printf("ghost, %s: spurious area %.4f%%, accuracy mean %.3f voxel, recall %.4f\n",
                run == 0   ? "prism"
                : run == 1 ? "robust"
                           : "robust in bands",
                100 * c.spuriousAreaFraction, c.accuracy.mean / voxel, c.recall);
    EXPECT_GT(c.recall, 0.8);  // the room stays
  }
  if (mpi::rank() == 0) {
    EXPECT_GT(spurious[0], 0.005);  // the ghost is there with prism fusion
    EXPECT_LT(spurious[1], 0.1 * spurious[0]);
    EXPECT_LT(spurious[2], 0.1 * spurious[0]);
    std::filesystem::remove_all(dir);
  }
}
