// A depth camera's sequence (16-bit PNG frames along one orbit, noise growing with the square of
// the range) fuses from its TUM, Redwood and 7-Scenes folders and a .conf naming its images:
// close to the truth, and to the same mesh whichever list names the same images and poses;
// joining its flat blocks of cells changes the mesh by no more than their tolerance.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "SharedTemp.h"
#include "rangefuse/eval/Comparison.h"
#include "rangefuse/io/DepthSequence.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/run/FuseJob.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;

namespace {

constexpr double kVoxel = 0.01;  // 1 cm, the scene 1.2 m across

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TriangleMesh scene() {
  TriangleMesh m = makeComposite();
  for (Eigen::Vector3d& v : m.vertices) v *= 0.01;
  return m;
}

/// Writes the sequence as TUM (0.2 mm counts), Redwood and 7-Scenes (1 mm counts) folders on
/// rank 0.
void writeSequences(const std::string& dir) {
  if (mpi::rank() != 0) return;
  ScanSettings s;
  s.views = 16, s.width = 160, s.height = 120, s.voxel = kVoxel, s.noise = 0.5;
  s.depthNoise = true, s.path = ViewPath::Orbit;
  const SyntheticSet set = scanMesh(scene(), s);
  for (const auto& [name, unit] : {std::pair{"tum", 1.0 / 5000}, std::pair{"redwood", 1e-3}}) {
    std::vector<io::DepthFrame> frames;
    for (const SyntheticScan& sc : set.scans)
      frames.push_back({io::depthImage(sc.grid, unit), io::cameraPose(sc.truth)});
    const io::DepthCamera camera = io::depthCamera(set.scans[0].grid, unit);
    if (std::string(name) == "tum") {
      io::writeTumSequence(dir + "/tum", frames, camera);
    } else {
      io::writeRedwoodSequence(dir + "/redwood", frames, camera);
      io::writeSevenScenesSequence(dir + "/7scenes", frames, camera);
    }
  }
}

FuseOptions fuseOptions(const std::string& scans, const std::string& out) {
  FuseOptions o;
  o.scans = scans;
  o.field.voxel = kVoxel;
  o.outputs.out = out;
  return o;
}

}  // namespace

TEST(DepthSequenceFuse, TumRedwoodSevenScenesAndNamedImagesFuseCloseToTheTruth) {
  const std::string dir = test::sharedTempPath("depth-seq");
  writeSequences(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  ASSERT_EQ(runFuse(fuseOptions(dir + "/tum", dir + "/tum.ply"), MPI_COMM_WORLD), 0);
  ASSERT_EQ(runFuse(fuseOptions(dir + "/redwood", dir + "/redwood.ply"), MPI_COMM_WORLD), 0);
  ASSERT_EQ(runFuse(fuseOptions(dir + "/7scenes", dir + "/7scenes.ply"), MPI_COMM_WORLD), 0);
  if (mpi::rank() == 0)
    io::writeConf(dir + "/tum/named.conf", io::readScanList(dir + "/tum").scans);
  MPI_Barrier(MPI_COMM_WORLD);
  ASSERT_EQ(runFuse(fuseOptions(dir + "/tum/named.conf", dir + "/named.ply"), MPI_COMM_WORLD), 0);
  if (mpi::rank() == 0) {
    EXPECT_EQ(bytes(dir + "/tum.ply"), bytes(dir + "/named.ply"));
    for (const char* name : {"tum", "redwood", "7scenes"}) {
      const TriangleMesh mesh = io::readMeshPly(dir + "/" + name + ".ply");
      const MeshComparison c =
          compareMeshes(mesh, scene(), CompareSettings{kVoxel, 3 * kVoxel, 50000, 1});
      std::printf("%s sequence: accuracy mean %.3f voxel, precision %.4f, recall %.4f\n", name,
                  c.accuracy.mean / kVoxel, c.precision, c.recall);
      // The orbit never sees the undersides: accuracy and precision are the measures here.
      EXPECT_LT(c.accuracy.mean, 0.15 * kVoxel) << name;
      EXPECT_GT(c.precision, 0.99) << name;
      EXPECT_GT(c.recall, 0.7) << name;
    }
    std::filesystem::remove_all(dir);
  }
}

TEST(DepthSequenceFuse, JoinedFlatBlocksMoveTheMeshByLessThanTheirTolerance) {
  const std::string dir = test::sharedTempPath("depth-join");
  writeSequences(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  FuseOptions joined = fuseOptions(dir + "/tum", dir + "/joined.ply");
  FuseOptions fine = fuseOptions(dir + "/tum", dir + "/fine.ply");
  ASSERT_GT(joined.joinFlat, 0);  // the default joins
  fine.joinFlat = 0;
  ASSERT_EQ(runFuse(joined, MPI_COMM_WORLD), 0);
  ASSERT_EQ(runFuse(fine, MPI_COMM_WORLD), 0);
  if (mpi::rank() == 0) {
    const TriangleMesh a = io::readMeshPly(dir + "/joined.ply");
    const TriangleMesh b = io::readMeshPly(dir + "/fine.ply");
    EXPECT_NE(a.vertices, b.vertices);  // the scene's flat faces were joined
    const CompareSettings settings{kVoxel, 3 * kVoxel, 50000, 1};
    const MeshComparison apart = compareMeshes(a, b, settings);
    const MeshComparison toTruth = compareMeshes(a, scene(), settings);
    const MeshComparison fineToTruth = compareMeshes(b, scene(), settings);
    std::printf("joined to fine: mean %.4f voxel; to the truth %.4f against %.4f voxel\n",
                apart.accuracy.mean / kVoxel, toTruth.accuracy.mean / kVoxel,
                fineToTruth.accuracy.mean / kVoxel);
    // The chords stand at most the tolerance off the fine triangles, and the field averages
    // them with the frames that kept the block fine.
    EXPECT_LT(apart.accuracy.mean, joined.joinFlat * kVoxel);
    EXPECT_LT(toTruth.accuracy.mean, fineToTruth.accuracy.mean + 0.01 * kVoxel);
    std::filesystem::remove_all(dir);
  }
}
