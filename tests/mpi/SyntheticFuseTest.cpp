#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "rangefuse/eval/Comparison.h"
#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"

using namespace rangefuse;

namespace {

/// Scans the composite shape into a fresh folder on rank 0; returns the folder.
std::string scanComposite(double noise) {
  std::string dir =
      (std::filesystem::temp_directory_path() / ("rangefuse-synth-" + std::to_string(getpid())))
          .string();
  dir = mpi::broadcastString(dir, 0, MPI_COMM_WORLD);
  if (mpi::rank() == 0) {
    std::filesystem::create_directories(dir);
    ScanSettings s;
    s.views = 12;
    s.width = 160;
    s.height = 120;
    s.noise = noise;
    const SyntheticSet set = scanMesh(makeComposite(), s);
    std::vector<io::ConfScan> conf;
    for (const auto& sc : set.scans) {
      io::writeRangeGridPly(dir + "/" + sc.name, sc.grid, io::PlyEncoding::BinaryLittleEndian);
      conf.push_back({sc.name, dir + "/" + sc.name, sc.truth});
    }
    io::writeConf(dir + "/truth.conf", conf);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir;
}

}  // namespace

TEST(SyntheticFuse, CompositeWithNoiseIsAccurateAndReported) {
  const std::string dir = scanComposite(0.5);
  FuseOptions o;
  o.scans = dir + "/truth.conf";
  o.voxel = 1;
  o.out = dir + "/mesh.ply";
  o.report = dir + "/report.json";
  o.preview = dir + "/preview.png";
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  if (mpi::rank() == 0) {
    const TriangleMesh mesh = io::readMeshPly(o.out);
    const MeshComparison c = compareMeshes(mesh, makeComposite(), CompareSettings{1, 3, 50000, 1});
    std::printf("composite, noise 0.5 voxel: chamfer %.3f voxel, F-score %.4f\n", c.chamfer,
                c.fscore);
    EXPECT_LT(c.chamfer, 0.15);
    EXPECT_GT(c.fscore, 0.99);
    EXPECT_EQ(c.spuriousAreaFraction, 0.0);
    const nlohmann::json r = io::readJson(o.report);
    ASSERT_EQ(r["per_rank"].size(), size_t(mpi::size()));
    uint64_t bricks = 0;
    for (const auto& rank : r["per_rank"]) {
      bricks += rank["bricks"].get<uint64_t>();
      EXPECT_TRUE(rank["stage_seconds"].contains("field"));
      EXPECT_GT(rank["peak_memory_mib"].get<uint64_t>(), 0u);
    }
    EXPECT_EQ(bricks, r["total_bricks"].get<uint64_t>());
    EXPECT_EQ(r["mesh"]["triangles"].get<size_t>(), mesh.faces.size());
    const Image img = io::readPng(o.preview);
    EXPECT_EQ(img.width, 512);
    EXPECT_EQ(img.height, 512);
    std::filesystem::remove_all(dir);
  }
}
