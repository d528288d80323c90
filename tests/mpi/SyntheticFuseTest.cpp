#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include "ScanSetFiles.h"
#include "SharedTemp.h"
#include "rangefuse/eval/Comparison.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/run/FuseJob.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;
using test::sharedTempPath;

namespace {

/// Scans the composite shape into a fresh folder on rank 0; returns the folder and, through
/// `patches`, the extraneous patches.
std::string scanComposite(double noise, double outliers = 0, int patchCount = 0,
                          std::vector<SyntheticPatch>* patches = nullptr, int views = 12,
                          int width = 160, int height = 120) {
  const std::string dir = sharedTempPath("synth");
  if (mpi::rank() == 0) {
    std::filesystem::create_directories(dir);
    ScanSettings s;
    s.views = views;
    s.width = width;
    s.height = height;
    s.noise = noise;
    s.outliers = outliers;
    s.patches = patchCount;
    const SyntheticSet set = scanMesh(makeComposite(), s);
    if (patches) *patches = set.patches;
    test::writeScanSet(dir, set);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir;
}

}  // namespace

TEST(SyntheticFuse, CompositeWithNoiseIsAccurateAndReported) {
  const std::string dir = scanComposite(0.5);
  FuseOptions o;
  o.scans = dir + "/truth.conf";
  o.field.voxel = 1;
  o.outputs.out = dir + "/mesh.ply";
  o.outputs.report = dir + "/report.json";
  o.outputs.preview = dir + "/preview.png";
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  if (mpi::rank() == 0) {
    const TriangleMesh mesh = io::readMeshPly(o.outputs.out);
    const MeshComparison c = compareMeshes(mesh, makeComposite(), CompareSettings{1, 3, 50000, 1});
    std::printf("composite, noise 0.5 voxel: chamfer %.3f voxel, F-score %.4f\n", c.chamfer,
                c.fscore);
    EXPECT_LT(c.chamfer, 0.15);
    EXPECT_GT(c.fscore, 0.99);
    EXPECT_EQ(c.spuriousAreaFraction, 0.0);
    const nlohmann::json r = io::readJson(o.outputs.report);
    ASSERT_EQ(r["per_rank"].size(), size_t(mpi::size()));
    uint64_t bricks = 0;
    for (const auto& rank : r["per_rank"]) {
      bricks += rank["bricks"].get<uint64_t>();
      EXPECT_TRUE(rank["stage_seconds"].contains("field"));
      EXPECT_GT(rank["peak_memory_mib"].get<uint64_t>(), 0u);
    }
    EXPECT_EQ(bricks, r["total_bricks"].get<uint64_t>());
    EXPECT_EQ(r["mesh"]["triangles"].get<size_t>(), mesh.faces.size());
    const Image img = io::readPng(o.outputs.preview);
    EXPECT_EQ(img.width, 512);
    EXPECT_EQ(img.height, 512);
    std::filesystem::remove_all(dir);
  }
}

TEST(SyntheticFuse, DenseScansMergedToTheVoxelKeepTheirAccuracy) {
  // Pixels about a third of a voxel: --merge-cells 1 merges 3 x 3 blocks.
  const std::string dir = scanComposite(0.5, 0, 0, nullptr, 6, 480, 360);
  FuseOptions o;
  o.scans = dir + "/truth.conf";
  o.field.voxel = 1;
  double chamfer[2];
  uint64_t triangles[2];
  for (int m = 0; m < 2; ++m) {
    o.mergeCells = m;
    o.outputs.out = dir + "/mesh" + std::to_string(m) + ".ply";
    o.outputs.report = dir + "/report" + std::to_string(m) + ".json";
    ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
    if (mpi::rank() != 0) continue;
    const TriangleMesh mesh = io::readMeshPly(o.outputs.out);
    chamfer[m] = compareMeshes(mesh, makeComposite(), CompareSettings{1, 3, 50000, 1}).chamfer;
    triangles[m] = io::readJson(o.outputs.report)["inputs"]["scan_triangles"].get<uint64_t>();
  }
  if (mpi::rank() == 0) {
    std::printf("dense composite: %llu triangles, chamfer %.3f voxel; merged %llu, %.3f\n",
                static_cast<unsigned long long>(triangles[0]), chamfer[0],
                static_cast<unsigned long long>(triangles[1]), chamfer[1]);
    EXPECT_LT(triangles[1] * 6, triangles[0]);
    EXPECT_LE(chamfer[1], std::max(1.1 * chamfer[0], chamfer[0] + 0.01));
    std::filesystem::remove_all(dir);
  }
}

namespace {

/// Share of a patch's area within one unit of the mesh.
double patchKept(const SyntheticPatch& patch, const TriangleMesh& mesh) {
  const std::vector<double> d = sampledDistances(patchMesh({patch}), mesh, 4000, 7);
  return double(std::count_if(d.begin(), d.end(), [](double x) { return x <= 1.0; })) / d.size();
}

}  // namespace

TEST(SyntheticFuse, ConsensusDropsExtraneousPatchesNaiveKeepsThem) {
  std::vector<SyntheticPatch> patches;
  const std::string dir = scanComposite(0.5, 0.01, 2, &patches);
  FuseOptions o;
  o.scans = dir + "/truth.conf";
  o.field.voxel = 1;
  o.field.quorum = 1.2;  // 12 views: above one view's confidence, so one view alone is no quorum
  double kept[2][2];
  for (int m = 0; m < 2; ++m) {
    o.field.method = m == 0 ? FieldMethod::Consensus : FieldMethod::Naive;
    o.outputs.out = dir + "/" + toString(o.field.method) + ".ply";
    ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
    if (mpi::rank() != 0) continue;
    const TriangleMesh mesh = io::readMeshPly(o.outputs.out);
    for (int k = 0; k < 2; ++k) kept[m][k] = patchKept(patches[k], mesh);
    if (m == 0) {
      const MeshComparison c =
          compareMeshes(mesh, makeComposite(), CompareSettings{1, 3, 50000, 1});
      std::printf(
          "consensus: chamfer %.3f voxel, F %.4f, spurious %.4f%%, patches kept %.3f %.3f\n",
          c.chamfer, c.fscore, 100 * c.spuriousAreaFraction, kept[0][0], kept[0][1]);
      EXPECT_LT(c.spuriousAreaFraction, 0.001);
      EXPECT_GT(c.fscore, 0.98);
    }
  }
  if (mpi::rank() == 0) {
    std::printf("naive: patches kept %.3f %.3f\n", kept[1][0], kept[1][1]);
    for (int k = 0; k < 2; ++k) {
      EXPECT_LE(kept[0][k], 0.05);
      EXPECT_GE(kept[1][k], 0.5);
    }
    std::filesystem::remove_all(dir);
  }
}

// Robust fusion removes a patch one scan saw (other scans looked through it) with few or many
// views, where the prism field keeps it; and loses no accuracy doing so.
TEST(SyntheticFuse, RobustRemovesOneScanPatchesThePrismFieldKeeps) {
  for (int views : {6, 12, 18, 24}) {
    std::vector<SyntheticPatch> patches;
    const std::string dir = scanComposite(0.5, 0.01, 2, &patches, views);
    FuseOptions o;
    o.scans = dir + "/truth.conf";
    o.field.voxel = 1;
    double kept[2][2], chamfer[2];
    for (int m = 0; m < 2; ++m) {
      o.field.method = m == 0 ? FieldMethod::Robust : FieldMethod::Prism;
      o.outputs.out = dir + "/" + toString(o.field.method) + ".ply";
      ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
      if (mpi::rank() != 0) continue;
      const TriangleMesh mesh = io::readMeshPly(o.outputs.out);
      for (int k = 0; k < 2; ++k) kept[m][k] = patchKept(patches[k], mesh);
      chamfer[m] = compareMeshes(mesh, makeComposite(), CompareSettings{1, 3, 50000, 1}).chamfer;
    }
    if (mpi::rank() != 0) continue;
    std::printf("%d views: robust chamfer %.3f, patches kept %.3f %.3f; prism %.3f, %.3f %.3f\n",
                views, chamfer[0], kept[0][0], kept[0][1], chamfer[1], kept[1][0], kept[1][1]);
    for (int k = 0; k < 2; ++k) {
      EXPECT_LE(kept[0][k], 0.05);
      EXPECT_GE(kept[1][k], 0.5);
    }
    EXPECT_LT(chamfer[0], 0.25);
    std::filesystem::remove_all(dir);
  }
}
